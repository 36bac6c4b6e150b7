// The Render panel's texture-space renderer (texspace_stage.h).
#include "pipeline/texspace_stage.h"

#include "core/fields.h"
#include "gl/gl.h"
#include "pipeline/param_json.h"

#include <algorithm>

namespace app {

namespace fs = std::filesystem;

bool TextureSpaceStage::update(const TextureSpaceInputs& in) {
    const TextureSpaceSettings& s = in.settings;
    if (!s.enabled || !in.scene) return false;
    SceneStage& scene = *in.scene;
    const bssrdf::ModelEntry* e = in.model.entry;
    if (!e || !e->usable() || !scene.hasMesh()) return false;
    core::Stopwatch clock;
    try {
        texspace::validateSettings(s.sampling);
        if (!m_pipe) m_pipe = std::make_unique<texspace::Pipeline>(m_root);
        clearProblem("settings");
    } catch (const std::exception& err) {
        setProblem("settings", err.what());
        return false;
    }
    texspace::Pipeline& p = *m_pipe;
    bool changed = false;

    // Stage 0: parameterisation and texels.
    const std::string meshKey = scene.meshHash() + "/" + std::to_string(s.sampling.textureSize);
    if (meshKey != m_meshKey) {
        m_meshKey = meshKey;
        m_lightKey.clear();
        try {
            p.setMesh(scene.mesh(), s.sampling.textureSize);
            m_note = p.parameterization().note;
            clearProblem("mesh");
        } catch (const std::exception& err) {
            setProblem("mesh", err.what()); // not retried until the mesh or K change
        }
    }
    if (!p.hasMesh()) return false;

    // Stage 1: the scene's light with the rendered model's η.
    irradiance::Settings light = scene.settings().light;
    light.ior = in.model.builtins.ior;
    const bool ibl = light.mode == irradiance::LightMode::Ibl ||
                     light.mode == irradiance::LightMode::OccludedIbl;
    const std::string& envFile = scene.settings().environmentFile;
    if (ibl && envFile != m_envTried) {
        m_envTried = envFile;
        try {
            const fs::path f =
                fs::path(envFile).is_absolute() ? fs::path(envFile) : m_root / envFile;
            p.irradianceStage().loadEnvironment(f);
            ++m_envLoads;
            clearProblem("environment");
        } catch (const std::exception& err) {
            setProblem("environment", err.what());
        }
    }
    const std::string& texFile = scene.settings().projectedTextureFile;
    if (light.mode == irradiance::LightMode::Filtered && texFile != m_texTried) {
        m_texTried = texFile;
        try {
            if (texFile.empty())
                p.irradianceStage().useCheckerTexture();
            else
                p.irradianceStage().loadProjectedTexture(
                    fs::path(texFile).is_absolute() ? fs::path(texFile) : m_root / texFile);
            ++m_texLoads;
            clearProblem("projected texture");
        } catch (const std::exception& err) {
            setProblem("projected texture", err.what());
        }
    }
    const std::string lightKey =
        m_meshKey + core::keyOf(light, ibl ? m_envLoads : 0,
                                light.mode == irradiance::LightMode::Filtered ? m_texLoads : 0);
    if (lightKey != m_lightKey) {
        m_lightKey = lightKey;
        m_runKey.clear();
        m_lightRunning = false;
        try {
            if (ibl && !p.irradianceStage().hasEnvironment())
                throw core::Error(envFile, 0, "no environment map loaded");
            gl::ScopedStageTimer t("texture space: irradiance");
            p.setGivenIrradiance(m_givenEt);
            p.beginLight(light);
            m_lightRunning = true;
            clearProblem("irradiance");
        } catch (const std::exception& err) {
            setProblem("irradiance", err.what());
        }
    }
    if (m_lightRunning) {
        try {
            do {
                gl::ScopedStageTimer t("texture space: irradiance");
                if (p.advanceLight()) m_lightRunning = false;
            } while (m_lightRunning && in.budgetMs < 0);
        } catch (const std::exception& err) {
            m_lightRunning = false;
            setProblem("irradiance", err.what());
        }
        changed = true;
    }
    if (!p.lightReady()) return changed;

    // Stage 3's model and material. A changed model waits while the check's server generates
    // the code of its traversal program, which this stage's renderer dispatches (as the scene's
    // does: SceneStage::updateRender); the last image stays, and the run pauses.
    const std::string modelKey = core::keyOf(e->displayPath, e->modelGeneration);
    if (modelKey != m_modelKey && in.model.codePending && in.budgetMs >= 0) return changed;
    if (modelKey != m_modelKey) {
        m_modelKey = modelKey;
        m_runKey.clear();
        try {
            p.setModel(*e->model);
            clearProblem("model");
        } catch (const std::exception& err) {
            setProblem("model", err.what());
        }
    }
    render::Settings view = scene.settings().render;
    // Interactive: a set's brute-force sum over its N texels per pixel in short dispatches, as
    // the scene's frames are, so a frame waits for one of them, not for the whole sum (N = 1024
    // held each frame 0.67 s on llvmpipe at 480x270); the result does not depend on it.
    if (in.budgetMs >= 0) view.iterationsPerDispatch = SceneStage::kInteractiveIterations;
    texspace::Settings run = s.sampling;
    const int sets = run.sampleSets;
    run.sampleSets = 0; // a target the accumulation runs to, not an input
    const std::string runKey = m_lightKey + m_modelKey + core::keyOf(view, run) +
                               toJson(e->values).dump() + in.model.materialKey +
                               std::to_string(e->generation) + "/" + std::to_string(m_givenVersion);
    if (runKey != m_runKey) {
        m_runKey = runKey;
        m_runOk = false;
        try {
            p.setMaterial(e->values, in.model.builtins);
            p.renderer().setGivenGbuffer(m_givenGbuffer);
            p.setGivenLocalRadiance(m_givenLocalL);
            run.sampleSets = sets;
            p.begin(run, view);
            m_runOk = true;
            m_seconds = 0;
            clearProblem("render");
        } catch (const std::exception& err) {
            setProblem("render", err.what());
        }
        changed = true;
    } else if (m_runOk) {
        p.setSampleSets(sets); // only the target changed: carry on (or stop) from here
    }
    if (m_runOk && !p.done()) {
        try {
            p.advance(in.budgetMs < 0 ? 1e30 : std::max(1.0, in.budgetMs - clock.ms()));
            changed = true;
            m_seconds += clock.ms() / 1000.0;
        } catch (const std::exception& err) {
            m_runOk = false;
            setProblem("render", err.what());
        }
    }
    return changed;
}

void TextureSpaceStage::finish(TextureSpaceInputs in) {
    in.budgetMs = -1;
    in.settings.enabled = true;
    update(in);
    const std::vector<std::string> p = problems();
    if (!p.empty()) throw core::Error("texture space", 0, p.front());
    if (!m_pipe || !m_pipe->done())
        throw core::Error("texture space", 0,
                          "nothing rendered (needs a usable model and the scene's mesh)");
}

litsphere::Image TextureSpaceStage::radiance() const {
    return m_pipe ? m_pipe->radiance() : litsphere::Image{};
}

bool TextureSpaceStage::reloadShaders(const std::vector<fs::path>& changed) {
    if (!m_pipe) return false;
    const shader::Reloaded r = m_pipe->reloadShaders(changed);
    if (!r.problem.empty())
        setProblem("shaders", r.problem);
    else
        clearProblem("shaders");
    if (r.rebuilt > 0) {
        m_lightKey.clear();
        m_runKey.clear();
    }
    return r.rebuilt > 0;
}

shader::Records TextureSpaceStage::shaderRecords() const {
    shader::Records out;
    if (m_pipe)
        for (const auto& [name, r] : m_pipe->shaderRecords())
            out["texture space:" + name] = r;
    return out;
}

void TextureSpaceStage::setProblem(const std::string& stage, const std::string& text) {
    m_problems[stage] = text;
}
void TextureSpaceStage::clearProblem(const std::string& stage) {
    m_problems.erase(stage);
}
std::vector<std::string> TextureSpaceStage::problems() const {
    std::vector<std::string> out;
    for (const auto& [stage, text] : m_problems)
        out.push_back(stage + ": " + text);
    return out;
}

StageStatus TextureSpaceStage::status() const {
    StageStatus st;
    st.problems = problems();
    if (m_pipe) {
        st.running = m_lightRunning || (m_runOk && !m_pipe->done());
        st.progress = m_lightRunning
                          ? m_pipe->lightProgress()
                          : double(m_pipe->setsDone()) / double(std::max(1, m_pipe->setsTarget()));
        st.stats.emplace_back("sets", std::to_string(m_pipe->setsDone()));
    }
    return st;
}

void TextureSpaceStage::setGivenGbuffer(std::optional<render::Gbuffer> g) {
    m_givenGbuffer = std::move(g);
    ++m_givenVersion; // the accumulation starts again at the next update or finish
}

void TextureSpaceStage::setGivenLocalRadiance(std::optional<std::vector<glm::vec3>> l) {
    m_givenLocalL = std::move(l);
    ++m_givenVersion;
}

void TextureSpaceStage::setGivenIrradiance(std::optional<std::vector<glm::vec3>> et) {
    m_givenEt = std::move(et);
    m_lightKey.clear();
}

namespace {

// E′ = E_t · A_S/A_T: the irradiance's float32 roundings and one more product.
constexpr double kEprimeRel = 2e-5, kEprimeAbs = 1e-7;
constexpr const char* kIrradianceInput = "texture_space.irradiance";

// The E_t per texel the draws read, recorded as the replay's input (K × K, row 0 = texel row 0).
CaptureEntry irradianceInput(const texspace::Pipeline& p) {
    CaptureEntry e = captureEntry(CaptureEntry::Kind::ExrInput, kIrradianceInput);
    const std::vector<glm::vec3>& et = p.drawnIrradiance();
    e.image.width = e.image.height = p.texels().size;
    e.image.samples = 1;
    for (const glm::vec3& x : et)
        e.image.mean.insert(e.image.mean.end(), {x.x, x.y, x.z});
    e.image.variance.assign(e.image.mean.size(), 0.0f);
    e.note = "E_t per texel as the CDF, the draws and the render read it (0 off the chart), given "
             "to them again on replay; compared through texture_space.eprime*";
    return e;
}

// The recorded image of `stage` as RGB per pixel (row-major), where the capture has it; one of
// another size than width × height is an error naming both (`what` it holds, and `expected`: the
// setting that sets the size, with its value).
std::optional<std::vector<glm::vec3>> recordedRgb(const CaptureEntries& out, const char* stage,
                                                  const char* what, int width, int height,
                                                  const std::string& expected) {
    if (!out.recordedImage) return std::nullopt;
    const std::optional<pathtrace::Image> img = out.recordedImage(stage);
    if (!img) return std::nullopt;
    if (img->width != width || img->height != height)
        throw core::Error(std::string(stage) + ": the recorded " + what + " is " +
                          std::to_string(img->width) + "x" + std::to_string(img->height) + ", " +
                          expected);
    std::vector<glm::vec3> rgb(size_t(width) * size_t(height));
    for (size_t p = 0; p < rgb.size(); ++p)
        rgb[p] = glm::vec3(img->mean[3 * p], img->mean[3 * p + 1], img->mean[3 * p + 2]);
    return rgb;
}

// The hybrid's local term: a sum of up to 1025 taps, each a profile-table value (the table itself
// 1e-5 apart between drivers, render/profile_table.h) times Ft and W_l in float32 (GLSL exp:
// (3 + 2|x|) ulp), n·2^-24 ≈ 6e-5 for the longest sums: 1e-4 relative plus 1e-6 of the largest.
constexpr double kLocalRel = 1e-4, kLocalFloor = 1e-6;
constexpr const char* kLocalInput = "texture_space.local_radiance";

// The local L_o per pixel the render added, recorded as the replay's input (the view's size).
CaptureEntry localInput(const texspace::Pipeline& p) {
    CaptureEntry e = captureEntry(CaptureEntry::Kind::ExrInput, kLocalInput);
    e.image = p.localRadiance();
    e.image.samples = 1;
    e.note = "the hybrid's local L_o per pixel (the light-view ring filter) as the render adds "
             "it, given to it again on replay; compared through texture_space.local";
    return e;
}

// This run's own local L_o at every 4th surface pixel, with (on replay) the allowance of
// another driver's light-view map and tap places (Pipeline::localSpread, made here).
CaptureEntry localEntry(texspace::Pipeline& p, bool forReplay) {
    CaptureEntry e = captureEntry(CaptureEntry::Kind::Csv, "texture_space.local", "pixel");
    e.table.columns = {"pixel", "R", "G", "B"};
    const std::vector<glm::vec4>& own = p.ownLocalRadiance();
    std::vector<size_t> shown;
    float largest = 0;
    for (size_t px = 0, k = 0; px < own.size(); ++px) {
        if (own[px].w == 0.0f) continue;
        largest = std::max({largest, own[px].x, own[px].y, own[px].z});
        if (k++ % 4 == 0) shown.push_back(px);
    }
    for (size_t px : shown)
        e.table.rows.push_back({double(px), own[px].x, own[px].y, own[px].z});
    if (e.table.rows.empty()) e.table.rows.push_back({-1, 0, 0, 0}); // nothing seen
    e.relTol = kLocalRel;
    e.absTol = kLocalFloor * double(largest);
    e.note = "the hybrid's local L_o (float32 sums of profile-table taps): 1e-4 relative + 1e-6 "
             "of the largest";
    if (forReplay && !shown.empty()) {
        e.conditioning.columns = e.table.columns;
        for (const glm::vec3& s : p.localSpread(shown))
            e.conditioning.rows.push_back({0.0, s.x, s.y, s.z});
        e.conditioningNote = "how far the local term moves with the light-view map drawn 1/16 "
                             "texel aside and read 2^-10 texel aside (along either axis or "
                             "both), tap by tap, summed over the taps (another rasteriser snaps "
                             "each vertex its own way; the taps' float places)";
    }
    return e;
}

} // namespace

// Captures (format v1, captures/README.md):
//   texture_space.texels   csv, exact   K, layout size, UVs or atlas, covered texels, triangles
//                                       with texels, largest stretch
//   texture_space.eprime_unshadowed  csv, tol  E′_u (RGB) of every 8th covered texel, E′ =
//                                              E′_u · V (GPU irradiance; directional and
//                                              filtered light; scene_capture.cpp says why)
//   texture_space.visibility  csv, tol  V of the same texels (the same lights; on replay with
//                                       the allowance of scene.visibility)
//   texture_space.eprime   csv, tol     E′ (RGB) of those texels: recorded for the other lights
//                                       (occluded IBL: a replay allows each value 2^-7 of its
//                                       unshadowed E′); made for the replay of older captures
//                                       otherwise
//   texture_space.irradiance  exr_input  E_t per texel (K x K) as the CDF, the draws and the
//                                       render read it; a replay gives the recorded one to them
//                                       (hash checked) while the E′ entries compare its own
//   texture_space.samples  csv, exact   the first 256 texels of sample set 0 (the GPU descent)
//   texture_space.local_radiance  exr_input  the hybrid's local L_o per pixel as the render adds
//                                       it; a replay gives the recorded one to the render
//   texture_space.local    csv, tol     the hybrid's own local L_o at every 4th surface pixel (on
//                                       replay allowing another driver's light-view map)
//   texture_space.render   exr_stat     the render averaged over its sample sets (a replay traces
//                                       the recorded scene.gbuffer_* and, with the hybrid, adds
//                                       the recorded local term)
void TextureSpaceStage::capture(const TextureSpaceInputs& in, CaptureEntries& out) {
    if (!in.scene || !in.scene->settings().enabled || !in.settings.enabled) return;
    // On replay the draws and the render read the recorded E_t (this run's own is what the E′
    // entries compare): E_t's visibility is a sampler's choice within 2^-7. The render (and the
    // hybrid's local term) trace the recorded G-buffer of the scene's view, which is this view:
    // another rasteriser's sub-pixel placement moves the silhouette (SceneStage::capture checks
    // the recorded one by the raster rule).
    const int k = in.settings.sampling.textureSize;
    std::optional<std::vector<glm::vec3>> given =
        recordedRgb(out, kIrradianceInput, "irradiance", k, k,
                    "settings.texture_space.sampling.texture_size is " + std::to_string(k));
    std::optional<render::Gbuffer> gbuffer = SceneStage::recordedGbuffer(out);
    // The hybrid's render adds the recorded local term (this run's own is what
    // texture_space.local compares): another driver's light-view map moves it at edges.
    const render::Settings& view = in.scene->settings().render;
    std::optional<std::vector<glm::vec3>> local =
        in.settings.sampling.hybrid
            ? recordedRgb(out, kLocalInput, "local term", view.width, view.height,
                          "settings.scene.render renders " + std::to_string(view.width) + "x" +
                              std::to_string(view.height))
            : std::nullopt;
    struct Restore {
        TextureSpaceStage& s;
        bool irradiance, gbuffer, local;
        ~Restore() {
            if (irradiance) s.setGivenIrradiance(std::nullopt);
            if (gbuffer) s.setGivenGbuffer(std::nullopt);
            if (local) s.setGivenLocalRadiance(std::nullopt);
        }
    } restore{*this, given.has_value(), gbuffer.has_value(), local.has_value()};
    if (local) {
        out.notes.push_back("texture space: the hybrid's render adds the recorded local term "
                            "(texture_space.local_radiance); this run's own is compared with it");
        setGivenLocalRadiance(std::move(local));
    }
    if (given) setGivenIrradiance(std::move(given));
    if (gbuffer) {
        out.notes.push_back("texture space: the render reads the recorded G-buffer "
                            "(scene.gbuffer_position, scene.gbuffer_normal)");
        setGivenGbuffer(std::move(gbuffer));
    }
    finish(in);
    const texspace::Pipeline& p = *pipeline();
    const texspace::Texels& t = p.texels();
    const texspace::Parameterization& param = p.parameterization();
    CaptureEntry tx = captureEntry(CaptureEntry::Kind::Csv, "texture_space.texels");
    tx.note = "CPU (parameterisation and rasterisation in double): exact";
    tx.table.comments = {"texture side K, atlas layout side, 1 = the mesh's UVs, covered texels, "
                         "triangles with a texel, largest stretch sigma1/sigma2"};
    tx.table.columns = {"K", "layout", "from_mesh", "covered", "triangles", "max_stretch"};
    std::vector<char> hasTexel(param.uv.size(), 0);
    for (int32_t f : t.triangle)
        if (f >= 0) hasTexel[size_t(f)] = 1;
    double worst = 1;
    for (double x : param.stretch)
        worst = std::max(worst, x);
    tx.table.rows.push_back({double(t.size), double(p.layoutSize()), param.fromMesh ? 1.0 : 0.0,
                             double(t.covered),
                             double(std::count(hasTexel.begin(), hasTexel.end(), 1)), worst});
    out.entries.push_back(std::move(tx));

    CaptureEntry ep = captureEntry(CaptureEntry::Kind::Csv, "texture_space.eprime", "texel");
    ep.absTol = kEprimeAbs;
    ep.relTol = kEprimeRel;
    ep.note = "GPU irradiance (float32) times the area ratio: 2e-5 relative + 1e-7";
    ep.table.columns = {"texel", "R", "G", "B"};
    std::vector<size_t> shown; // every 8th covered texel
    for (size_t texel = 0, k = 0; texel < t.triangle.size(); ++texel)
        if (t.triangle[texel] >= 0 && k++ % 8 == 0) shown.push_back(texel);
    const std::vector<glm::vec3> e = p.eprime();
    for (size_t texel : shown)
        ep.table.rows.push_back({double(texel), e[texel].x, e[texel].y, e[texel].z});
    out.entries.push_back(irradianceInput(p));
    const irradiance::Settings& lightSettings = in.scene->settings().light;
    const bool factored = irradiance::hasVisibilityFactor(lightSettings.mode);
    ep.recorded = !factored;
    if (lightSettings.mode == irradiance::LightMode::OccludedIbl && out.forReplay)
        addOcclusionAllowance(ep, p.eprimeUnshadowedOccluded(shown),
                              pipeline()->eprimeOccludedRasterSpread(shown));
    out.entries.push_back(std::move(ep));
    if (factored) {
        const texspace::Pipeline::EprimeFactors f = pipeline()->eprimeFactors();
        CaptureEntry eu =
            captureEntry(CaptureEntry::Kind::Csv, "texture_space.eprime_unshadowed", "texel");
        // filtered light: plus what T(uv)'s bilinear weights may move on another driver, times
        // the largest area ratio recorded (E′ = E · A_S/A_T)
        double ratio = 0;
        for (size_t texel : shown)
            ratio = std::max(ratio, t.areaRatio[texel]);
        const double spread =
            pipeline()->irradianceStage().unshadowedSpread(in.scene->settings().light) * ratio;
        eu.absTol = kEprimeAbs + spread;
        eu.relTol = kEprimeRel;
        eu.note = "GPU irradiance without shadows (float32) times the area ratio: 2e-5 "
                  "relative + 1e-7" +
                  projectedSpreadNote(spread);
        eu.table.columns = {"texel", "R", "G", "B"};
        CaptureEntry v = visibilityEntry("texture_space.visibility", "texel");
        for (size_t texel : shown) {
            const glm::vec3& u = f.unshadowed[texel];
            eu.table.rows.push_back({double(texel), u.x, u.y, u.z});
            v.table.rows.push_back({double(texel), f.visibility[texel]});
        }
        if (out.forReplay) addRasterAllowance(v, pipeline()->visibilitySpread(shown));
        out.entries.push_back(std::move(eu));
        out.entries.push_back(std::move(v));
    }

    CaptureEntry sm = captureEntry(CaptureEntry::Kind::Csv, "texture_space.samples", "draw");
    sm.note = "the GPU descent of Algorithm 3.1 over the float CDF the CPU builds from E_t (on "
              "replay the recorded texture_space.irradiance), by correctly rounded subtractions "
              "and comparisons (precise): exact on any driver that keeps denormals";
    sm.table.columns = {"draw", "texel"};
    const texspace::SampleSet first =
        p.drawSet(std::min(256, in.settings.sampling.samples), in.settings.sampling.seed, 0);
    for (size_t d = 0; d < first.draws.size(); ++d)
        sm.table.rows.push_back({double(d), double(first.draws[d])});
    if (sm.table.rows.empty()) sm.table.rows.push_back({-1, 0}); // no light: no draws
    out.entries.push_back(std::move(sm));

    if (in.settings.sampling.hybrid) {
        out.entries.push_back(localInput(p));
        out.entries.push_back(localEntry(*pipeline(), out.forReplay));
    }

    // The render (seed 004): the mean over its sample sets with the variance of the mean per
    // pixel.
    CaptureEntry render = captureEntry(CaptureEntry::Kind::ExrStat, "texture_space.render");
    render.image = radiance();
    render.alpha = kMonteCarloAlpha;
    render.note = "Monte Carlo image: per-pixel z-test, Bonferroni over all pixels and channels; "
                  "on replay traced from the recorded scene.gbuffer_*";
    out.entries.push_back(std::move(render));
}

} // namespace app
