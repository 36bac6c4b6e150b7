// `bssrdf-workbench render` (render_command.h): the SceneStage pipeline run to completion headless.
#include "cli/render_command.h"
#include "cli/args.h"
#include "cli/command.h"
#include "cli/output.h"

#include "cli/capture_commands.h"
#include "cli/options.h"
#include "core/core.h"
#include "gl/gl.h"
#include "pathtrace/image_io.h"
#include "pipeline/image_display.h"
#include "pipeline/texspace_images.h"
#include "pipeline/workbench.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

namespace app {
namespace fs = std::filesystem;

namespace {

// "dir:x,y,z" or "ibl:FILE.exr" → the light settings.
void parseLight(const std::string& text, SceneSettings& s) {
    if (text.rfind("dir:", 0) == 0) {
        const glm::dvec3 d = parseRgb(text.substr(4), "--light");
        if (!(glm::dot(d, d) > 0) || !std::isfinite(glm::dot(d, d)))
            throw core::Error("--light", 0, "the direction must be finite and non-zero");
        s.light.mode = irradiance::LightMode::Directional;
        s.light.direction = glm::vec3(d);
        return;
    }
    if (text.rfind("ibl:", 0) == 0 && text.size() > 4) {
        s.light.mode = irradiance::LightMode::Ibl;
        s.environmentFile = text.substr(4);
        return;
    }
    throw core::Error("--light", 0, "expected dir:x,y,z or ibl:FILE.exr, got '" + text + "'");
}

// --renderer texture-space: the texture-space stage on the scene's mesh, light and view, run to
// its target; the EXR holds L_o and its variance of the mean over the sets.
template <class Progress>
int writeTextureSpace(Workbench& wb, const RenderArgs& a, core::Stopwatch& clock,
                      const Progress& progress) {
    progress("texture space", -1);
    wb.textureSpaceSettings() = a.textureSpace;
    wb.textureSpaceSettings().sampling.hybrid = a.renderer == "hybrid";
    wb.finishTextureSpace();
    core::progressEnd();
    const TextureSpaceStage& ts = wb.textureSpace();
    const texspace::Pipeline& p = *ts.pipeline();
    const litsphere::Image img = ts.radiance();
    pathtrace::writeExr(a.out, img);
    if (!a.png.empty()) {
        const render::Settings& r = wb.scene().settings().render;
        std::vector<uint8_t> rgba = tonemap(img, r.exposure, r.gamma);
        paintMisses(rgba, wb.scene().readback().hdr, r.background); // as the frame's PNG has them
        gl::writePng(a.png, img.width, img.height, rgba);
    }
    if (!a.stageImages.empty()) {
        const fs::path dir = a.stageImages;
        std::error_code ec;
        fs::create_directories(dir, ec);
        if (ec) throw core::Error(dir.string(), 0, "--stage-images: " + ec.message());
        auto png = [&](const std::string& name, const Rgba8Image& im) {
            gl::writePng(dir / name, im.width, im.height, im.rgba);
        };
        png("eprime.png", eprimeImage(p));
        png("atlas.png", atlasImage(p));
        png("samples.png", samplesImage(p, p.lastSet()));
        for (size_t l = 0; l < p.cdf().levels.size(); ++l)
            png("cdf_level" + std::to_string(l) + ".png", cdfLevelImage(p.cdf(), int(l)));
    }
    double var = 0, sum2 = 0;
    for (size_t i = 0; i < img.mean.size(); ++i) {
        var += img.variance[i];
        sum2 += double(img.mean[i]) * img.mean[i];
    }
    std::printf("%s with %s: %s, %s, K = %d (%zu covered texels standing for %.4g of "
                "%.4g mesh units²), N = %d, %d sets, %dx%d\n",
                a.mesh.c_str(), wb.sceneModelInput().entry->displayPath.c_str(),
                a.renderer == "hybrid" ? "hybrid" : "texture space",
                p.parameterization().fromMesh ? "the mesh's UVs" : "atlas", p.texels().size,
                p.texels().covered, p.representedArea(), pointcloud::meshArea(wb.scene().mesh()),
                a.textureSpace.sampling.samples, p.setsDone(), img.width, img.height);
    if (!ts.note().empty()) std::printf("note: %s\n", ts.note().c_str());
    if (a.renderer == "hybrid")
        std::printf("hybrid: R_p %.4g, %.4g, %.4g mm, %zu taps, local term %.1f ms\n",
                    double(p.hybridRp().x), double(p.hybridRp().y), double(p.hybridRp().z),
                    p.hybridTaps().size(), p.localMs());
    std::printf("relative standard error %.3g; last set drawn in %.1f ms, rendered in %.1f ms; "
                "total %.1f s\n",
                sum2 > 0 ? std::sqrt(var / sum2) : 0.0, p.lastSampleMs(), p.lastRenderMs(),
                clock.ms() / 1000.0);
    std::printf("wrote %s\n", a.out.c_str());
    return 0;
}

} // namespace

void addRenderOptions(CLI::App* cmd, RenderArgs& a) {
    cmd->add_option("--mesh", a.mesh, "triangle mesh (OBJ)")->required();
    cmd->add_option("--model", a.model, ".bssrdf file")->required();
    cmd->add_option("--preset", a.preset,
                    "material preset (sigma_s', sigma_a); a material is required: "
                    "--preset, or both --sigma-a and --sigma-s");
    cmd->add_option("--sigma-a", a.sigmaA, "absorption R,G,B in 1/mm");
    cmd->add_option("--sigma-s", a.sigmaS, "scattering R,G,B in 1/mm");
    cmd->add_option("--g", a.g, "mean cosine (default 0)");
    cmd->add_option("--eta", a.eta, "relative index of refraction (default 1.3)");
    cmd->add_option("--scale", a.scale, "mm per mesh unit (longest axis = 1 unit; default 50)");
    addSettingOptions(cmd, a.scene,
                      {{"points.count", "--points"},
                       {"points.method", "--method"},
                       {"points.seed", "--seed"},
                       {"light.occluded_samples", "--env-samples"},
                       {"render.eps", "--eps"},
                       {"render.second_order", "--second-order,!--first-order"},
                       {"render.bbox_criterion", "--bbox-criterion"},
                       {"render.brute_force", "--bruteforce,!--no-bruteforce"},
                       {"render.width", "--width"},
                       {"render.height", "--height"},
                       {"render.camera.yaw", "--yaw"},
                       {"render.camera.pitch", "--pitch"},
                       {"render.exposure", "--exposure"}});
    const glm::vec3 d = a.scene.light.direction;
    cmd->add_option("--light", a.light,
                    "dir:x,y,z (towards the light) or ibl:FILE.exr (default dir:" + defaultText(d) +
                        ")");
    cmd->add_flag("--occluded", a.occluded, "with ibl: occluded IBL (shadow-mapped samples)");
    cmd->add_option("--irradiance", a.irradiance,
                    "directional E0 (default " + defaultText(a.scene.light.irradiance.x) +
                        "), or the environment intensity (default " +
                        defaultText(a.scene.light.envIntensity) + ")");
    cmd->add_option("--renderer", a.renderer,
                    "hierarchical | bruteforce (the point cloud, thesis 3.3) | texture-space "
                    "(Chang 2007: N texels by the irradiance-weighted mip CDF, averaged over sets; "
                    "the EXR gains varR, varG, varB) | hybrid (texture space for the global part "
                    "of R_d, a light-view ring filter for the local part; directional light, "
                    "radial models) (default hierarchical)")
        ->check(CLI::IsMember({"hierarchical", "bruteforce", "texture-space", "hybrid"}));
    addSettingOptions(cmd, a.textureSpace.sampling,
                      {{"texture_size", "--texture-size"},
                       {"samples", "--samples"},
                       {"sample_sets", "--sets"},
                       {"seed", "--draw-seed"},
                       {"local.rings", "--rings"},
                       {"local.per_ring", "--per-ring"},
                       {"local.k", "--hybrid-k"},
                       {"local.lower_bound", "--rp-bound"}});
    cmd->add_option("--stage-images", a.stageImages,
                    "texture-space: write the stage images (E', CDF levels, samples, atlas) as "
                    "PNG into this folder");
    cmd->add_option("--png", a.png, "also write the tone-mapped image as PNG");
    cmd->add_flag("--no-cache{false}", a.useCache, "neither read nor write the point-cloud cache");
    cmd->add_option("--out", a.out, "EXR file: R, G, B radiance")->required();
    // An option of one renderer (or light) given with another is refused, not ignored.
    refuseIgnoredOptions(
        cmd, {{{"--texture-size", "--samples", "--sets", "--draw-seed", "--stage-images"},
               [&a] { return a.renderer != "texture-space" && a.renderer != "hybrid"; },
               "only with --renderer texture-space or hybrid"},
              {{"--rings", "--per-ring", "--hybrid-k", "--rp-bound"},
               [&a] { return a.renderer != "hybrid"; },
               "only with --renderer hybrid"},
              {{"--env-samples"},
               [&a] { return !a.occluded; },
               "only with --occluded (--light ibl:FILE.exr)"}});
}

int runRenderCli(const fs::path& root, const RenderArgs& a) {
    if (a.out.empty()) throw core::Error("--out", 0, "give the EXR file to write");
    checkOutput(a.out, "--out", ".exr");
    checkOutput(a.png, "--png", ".png");
    if (a.mesh.empty()) throw core::Error("--mesh", 0, "give the OBJ file to render");
    const render::Settings& r = a.scene.render;
    if (r.width < 1 || r.width > 8192 || r.height < 1 || r.height > 8192)
        throw core::Error("--width", 0, "width and height must lie in [1, 8192]");
    if (!(r.eps >= 0) || !std::isfinite(r.eps))
        throw core::Error("--eps", 0, "must be a finite number >= 0");
    const int occludedSamples = a.scene.light.occludedTotalSamples;
    if (occludedSamples < 1 || occludedSamples > (1 << 20))
        throw core::Error("--env-samples", 0, "must lie in [1, 1048576]");
    const bool textureSpace = a.renderer == "texture-space" || a.renderer == "hybrid";
    if (textureSpace) {
        texspace::Settings ts = a.textureSpace.sampling;
        ts.hybrid = a.renderer == "hybrid";
        try {
            texspace::validateSettings(ts);
        } catch (const core::Error& e) {
            const std::string m = e.what();
            throw core::Error(m.find("texture_size") != std::string::npos  ? "--texture-size"
                              : m.find("samples") != std::string::npos     ? "--samples"
                              : m.find("sample_sets") != std::string::npos ? "--sets"
                              : m.find("taps") != std::string::npos        ? "--rings"
                              : m.find("per_ring") != std::string::npos    ? "--per-ring"
                              : m.find("rings") != std::string::npos       ? "--rings"
                              : m.find("lower_bound") != std::string::npos ? "--rp-bound"
                                                                           : "--hybrid-k",
                              0, m);
        }
    }
    if (!std::ifstream(a.mesh)) throw core::Error(a.mesh, 0, "--mesh: cannot open the file");
    const fs::path model = resolveModel(root, a.model);
    // The scene as the arguments give it, checked before the GL context, the model and the
    // point cloud: a refused combination is an error at once, not after seconds of work.
    SceneSettings scene = a.scene;
    scene.enabled = true;
    scene.useCache = a.useCache;
    scene.meshFile = fs::absolute(a.mesh).string();
    if (a.renderer == "bruteforce") scene.render.bruteForce = true;
    pointcloud::checkOptions(scene.points);
    if (!a.light.empty()) parseLight(a.light, scene);
    if (a.occluded) {
        if (scene.light.mode != irradiance::LightMode::Ibl)
            throw core::Error("--occluded", 0, "needs --light ibl:FILE.exr");
        scene.light.mode = irradiance::LightMode::OccludedIbl;
    }
    if (a.renderer == "hybrid" && scene.light.mode != irradiance::LightMode::Directional)
        throw core::Error("--light", 0,
                          "--renderer hybrid: its local term needs the directional light "
                          "(--light dir:x,y,z; the light-view map), not image-based lighting");
    if (a.irradiance) {
        if (scene.light.mode == irradiance::LightMode::Directional)
            scene.light.irradiance = glm::vec3(*a.irradiance);
        else
            scene.light.envIntensity = *a.irradiance;
    }
    if (!scene.environmentFile.empty() && scene.light.mode != irradiance::LightMode::Directional) {
        scene.environmentFile = fs::absolute(scene.environmentFile).string();
        if (!std::ifstream(scene.environmentFile))
            throw core::Error(scene.environmentFile, 0, "--light ibl: cannot open the file");
    }
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, {model});
    auto& e = wb.library().entries().at(0);
    if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    wb.shared() = settingsFromArgs(wb, a.preset, a.sigmaA, a.sigmaS, a.g, a.eta);
    if (a.scale) {
        wb.shared().params.scale = *a.scale;
        material::validate(wb.shared().params, "--scale");
    }
    SceneSettings& s = wb.scene().settings();
    s = scene;
    core::Stopwatch clock;
    // A progress line on stderr: each step as it starts, the point cloud's fraction while it
    // is generated, with the time so far.
    auto progress = [&clock](const char* step, double fraction) {
        if (fraction >= 0)
            core::progress("render: %s %5.1f%%  %.1f s", step, 100.0 * fraction,
                           clock.ms() / 1000.0);
        else
            core::progress("render: %s ...  %.1f s", step, clock.ms() / 1000.0);
    };
    wb.update();
    wb.finishScene(progress);
    // Everything the pipeline refused is an error here (the GUI would keep the last good).
    for (const auto& p : wb.scene().problems())
        throw core::Error(p);
    auto& v = wb.view(e.displayPath);
    if (!v.effective) throw core::Error(e.displayPath, 0, v.materialProblem);
    if (!wb.scene().hasFrame()) throw core::Error("render", 0, "nothing was rendered");
    // The camera is fitted to the mesh on load; apply the requested orbit and render again.
    s.render.camera.yaw = r.camera.yaw;
    s.render.camera.pitch = r.camera.pitch;
    wb.finishScene(progress);
    if (textureSpace) return writeTextureSpace(wb, a, clock, progress);
    core::progressEnd();
    const render::Readback rb = wb.scene().readback();
    const pathtrace::Image img = hdrImage(rb);
    const size_t pixels = size_t(rb.width) * size_t(rb.height);
    uint64_t steps = 0, flagged = 0, hits = 0, maxSteps = 0;
    for (size_t p = 0; p < pixels; ++p) {
        if (rb.position[p].w > 0.5f) {
            ++hits;
            steps += rb.stats[p].x;
            maxSteps = std::max<uint64_t>(maxSteps, rb.stats[p].x);
            flagged += rb.stats[p].z != 0;
        }
    }
    pathtrace::writeExr(a.out, img);
    if (!a.png.empty()) gl::writePng(a.png, rb.width, rb.height, rb.ldr);
    const render::Frame& f = wb.scene().frame();
    const auto* t = wb.scene().tree();
    std::printf("%s with %s: %zu points (%s), octree %zu nodes depth %d, %dx%d, eps %g%s%s\n",
                a.mesh.c_str(), e.displayPath.c_str(), wb.scene().cloud().points.size(),
                pointcloud::methodName(s.points.method), t->stats.nodes, t->stats.maxDepth,
                rb.width, rb.height, double(r.eps),
                r.boundingBoxCriterion ? " (bounding-box criterion)" : "",
                r.bruteForce ? " BRUTE FORCE" : "");
    std::printf("traversal %.1f ms%s (G-buffer %.1f ms, profile %.1f ms); mean steps/pixel %.1f, "
                "max %llu; flagged pixels %llu; total %.1f s\n",
                f.traverseMs,
                f.bands > 1 ? (" in " + std::to_string(f.bands) + " bands of rows").c_str() : "",
                f.gbufferMs, f.profileMs, hits ? double(steps) / double(hits) : 0.0,
                (unsigned long long)maxSteps, (unsigned long long)flagged, clock.ms() / 1000.0);
    std::printf("wrote %s\n", a.out.c_str());
    return 0;
}

Command renderCommand() {
    return {"render", "mesh rendered by the hierarchical point-cloud method (thesis 3.3) as EXR",
            false, [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<RenderArgs>();
                addRenderOptions(&cmd, *a);
                return [a](CommandContext& ctx) { return runRenderCli(ctx.root(), *a); };
            }};
}

} // namespace app
