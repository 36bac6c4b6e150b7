// bssrdf-workbench: command line + frame loop entry. Subcommands: gui (default), screenshot,
// profile, invert, record, replay. Everything but a windowed `gui` runs without a display.
#include "bench.h"
#include "capture_io.h"
#include "cli.h"
#include "cli_estimate.h"
#include "cli_image.h"
#include "cli_integrate.h"
#include "cli_options.h"
#include "cli_pointcloud.h"
#include "cli_probe.h"
#include "cli_render.h"
#include "cli_slab.h"
#include "compare.h"
#include "core/core.h"
#include "gl/gl.h"
#include "gui.h"
#include "model_probe_process.h"
#include "settings_json.h"
#include "workbench.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>

namespace fs = std::filesystem;

namespace {

// Project root (holds materials/ and shaders/): --root, $BSSRDF_WORKBENCH_ROOT, the installed
// layout beside the executable (<prefix>/share/bssrdf-workbench for <prefix>/bin/...), the
// nearest folder above the executable that holds both (a build inside the source tree), or
// the current directory. Never a tree found only by where the binary was built: a copied
// build must say it found nothing rather than silently read another checkout.
fs::path findRoot(const std::string& given) {
    auto ok = [](const fs::path& p) {
        std::error_code ec;
        return fs::is_directory(p / "materials", ec) && fs::is_directory(p / "shaders", ec);
    };
    if (!given.empty()) {
        if (!ok(given))
            throw core::Error(given, 0, "--root: expected a folder with materials/ and shaders/");
        return fs::absolute(given).lexically_normal();
    }
    if (const char* env = std::getenv("BSSRDF_WORKBENCH_ROOT"); env && *env) {
        if (!ok(env))
            throw core::Error(env, 0,
                              "$BSSRDF_WORKBENCH_ROOT: expected a folder with materials/ and "
                              "shaders/");
        return fs::absolute(env).lexically_normal();
    }
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path bin = exe.parent_path();
        if (ok(bin.parent_path() / "share" / "bssrdf-workbench"))
            return bin.parent_path() / "share" / "bssrdf-workbench";
        for (fs::path d = bin; !d.empty(); d = d.parent_path()) {
            if (ok(d)) return d;
            if (d == d.root_path()) break;
        }
    }
    if (ok(fs::current_path())) return fs::current_path();
    throw core::Error(exe.empty() ? "bssrdf-workbench" : exe.string(), 0,
                      "cannot find materials/ and shaders/ beside the executable or in the "
                      "current folder; pass --root DIR (or set $BSSRDF_WORKBENCH_ROOT)");
}

bool parseSize(const std::string& s, int& w, int& h, int minSide = 64) {
    char tail = 0;
    return std::sscanf(s.c_str(), "%dx%d%c", &w, &h, &tail) == 2 && w >= minSide && h >= minSide &&
           w <= 8192 && h <= 8192;
}

int runHeadlessDefault(const fs::path& root, const std::string& outDir) {
    fs::path out = outDir.empty() ? fs::path("out") / "default" : fs::path(outDir);
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) throw core::Error(out.string(), 0, "cannot create output folder: " + ec.message());
    auto ctx = gl::createHeadlessContext();
    std::printf("GL: %s | %s\n", ctx->renderer().c_str(), ctx->version().c_str());
    app::Workbench wb(root, false, {root / "materials" / "dipole.bssrdf"});
    // the mesh pipeline too (a small cloud and image keep the capture quick to replay)
    app::SceneSettings& scene = wb.scene().settings();
    scene.enabled = true;
    scene.useCache = false;
    scene.points.points = 3000;
    scene.render.width = 160;
    scene.render.height = 90;
    app::recordCaptureTo(wb, out / "capture", "default", 80, 45);
    std::string text;
    int rc = app::replayCapture(out / "capture", root, false, text);
    std::printf("%s", text.c_str());
    app::GuiOptions opt;
    opt.persistLayout = false;
    opt.screenshotPath = (out / "workbench.png").string();
    app::Workbench full(root, false);
    rc |= app::runGui(full, *ctx, opt);
    std::printf("outputs:\n  capture    %s\n  screenshot %s\n",
                fs::absolute(out / "capture").string().c_str(),
                fs::absolute(out / "workbench.png").string().c_str());
    return rc;
}

} // namespace

int main(int argc, char** argv) {
    CLI::App cli{"bssrdf-workbench " BW_VERSION
                 " — develop, inspect and validate analytic BSSRDF models"};
    cli.require_subcommand(0, 1);
    std::string rootArg;
    bool verbose = false;
    cli.add_option("--root", rootArg, "project root holding materials/ and shaders/");
    cli.add_flag("-v,--verbose", verbose, "echo info messages to stderr");

    bool headless = false;
    std::string headlessOut;
    cli.add_flag("--headless", headless,
                 "no window: record + replay the default capture and save a screenshot");
    cli.add_option("--out-dir", headlessOut, "where --headless writes (default out/default)");

    auto* gui = cli.add_subcommand("gui", "interactive workbench (default)");
    gui->add_flag("--headless", headless, "same as the top-level --headless");

    auto* shot = cli.add_subcommand("screenshot", "run the full GUI headless and save a PNG");
    std::string shotOut, shotSize = "1600x1000";
    int shotFrames = 3;
    shot->add_option("--out", shotOut, "PNG file")->required();
    shot->add_option("--frames", shotFrames, "frames to run before saving")
        ->check(CLI::Range(1, 10000));
    shot->add_option("--size", shotSize, "WxH in pixels");

    auto* prof = cli.add_subcommand("profile", "pencil-beam profile of a model as CSV");
    app::ProfileArgs pa;
    prof->add_option("--model", pa.model, ".bssrdf file")->required();
    prof->add_option("--preset", pa.preset, "Jensen et al. 2001 preset (sigma_s', sigma_a)");
    prof->add_option("--sigma-a", pa.sigmaA, "absorption R,G,B in 1/mm");
    prof->add_option("--sigma-s", pa.sigmaS, "scattering R,G,B in 1/mm");
    const material::MaterialParams materialDefaults;
    const app::PlotSettings plotDefaults;
    pa.samples = plotDefaults.samples;
    prof->add_option("--g", pa.g,
                     "mean cosine (default " + app::defaultText(materialDefaults.g) + ")");
    prof->add_option("--eta", pa.eta,
                     "relative index of refraction (default " +
                         app::defaultText(materialDefaults.eta) + ")");
    // the plot's own ranges (PlotSettings' description), as in the GUI and in captures
    app::addNumberOption(prof, "--rmax", pa.rMax,
                         "largest radius in mm (default " + app::defaultText(plotDefaults.rangeLd) +
                             " x largest l_d)",
                         core::limitsOf<app::PlotSettings>("r_max_mm"));
    app::addCountOption(prof, "--samples", pa.samples,
                        "number of radii (default " + std::to_string(plotDefaults.samples) + ")",
                        core::limitsOf<app::PlotSettings>("samples"));
    prof->add_option("--out", pa.out, "CSV file: # header, then r_mm,R,G,B")->required();

    auto* inv = cli.add_subcommand("invert", "R_dr / l_d -> sigma_a, sigma_s (1/mm)");
    app::InvertArgs ia;
    inv->add_option("--model", ia.model, ".bssrdf file with a diffuseReflectance section")
        ->required();
    inv->add_option("--rdr", ia.rdr, "total diffuse reflectance R,G,B in [0,1]")->required();
    inv->add_option("--ld", ia.ld, "diffuse mean free path R,G,B in mm")->required();
    inv->add_option("--g", ia.g,
                    "mean cosine (default " + app::defaultText(materialDefaults.g) + ")");
    inv->add_option("--eta", ia.eta,
                    "relative index of refraction (default " +
                        app::defaultText(materialDefaults.eta) + ")");

    auto* rec = cli.add_subcommand("record", "record a capture of the default state headless");
    app::RecordArgs ra;
    rec->add_option("--name", ra.name, "capture name (folder under captures/)")->required();
    rec->add_option("--model", ra.models, "model files (default: every materials/*.bssrdf)");
    rec->add_option("--preset", ra.preset, "material preset (default Marble)");
    rec->add_option("--out", ra.outDir, "folder (default captures/NAME)");
    rec->add_option("--reference-paths", ra.referencePaths,
                    "also record the path-traced pencil-beam reference with this many paths per "
                    "channel (default 0: off)");
    rec->add_option("--slice-paths", ra.slicePaths,
                    "also record the BSSRDF slice (path-traced table and every model on its "
                    "bins) with this many paths (default 0: off)");
    rec->add_option("--slice-theta-i", ra.sliceThetaI,
                    "incidence angle of the slice, degrees (default " +
                        app::defaultText(app::SliceSettings{}.thetaIDeg) + ")");
    rec->add_option("--lit-spheres", ra.litSphereSize,
                    "also record the lit-sphere images (path traced and BSSRDF integrated) at "
                    "this size in pixels (default 0: off)")
        ->check(CLI::Range(0, 1024));
    rec->add_option("--lit-mesh", ra.litMesh,
                    "with --lit-spheres: path trace this OBJ (a file under the project root) "
                    "instead of the sphere");
    rec->add_option("--lit-sampling", ra.litSampling,
                    "with --lit-spheres: BSSRDF integration uniform or disk (default " +
                        std::string(core::nameOf(app::LitSphereSettings{}.sampling)) + ")");
    rec->add_option("--lit-axes", ra.litAxes,
                    "with --lit-sampling disk: probe axes uniform, pbrt, normal or all (default " +
                        std::string(core::nameOf(app::LitSphereSettings{}.axes)) + ")");
    rec->add_option("--reference-bins", ra.referenceBins,
                    "radial bins of the reference (default " +
                        std::to_string(app::ReferenceSettings{}.bins) + ")")
        ->check(CLI::Range(1, 100000));

    rec->add_option("--scene-points", ra.scenePoints,
                    "also record the mesh pipeline (point cloud, octree, irradiance, render, one "
                    "traversal trace) with this many points (default 0: off)");
    rec->add_option("--scene-mesh", ra.sceneMesh,
                    "with --scene-points: the OBJ (under the root; default the bunny)");
    rec->add_option("--scene-width", ra.sceneWidth, "render width (default 160)")
        ->check(CLI::Range(1, 4096));
    rec->add_option("--scene-height", ra.sceneHeight, "render height (default 90)")
        ->check(CLI::Range(1, 4096));
    rec->add_option("--texture-space", ra.textureSpace,
                    "with --scene-points: also record the texture-space stages (texels, E', "
                    "the first draws, the render over its sets) at this texture size K "
                    "(default 0: off)");
    rec->add_option("--texture-samples", ra.textureSamples,
                    "with --texture-space: N per sample set (default 256)");
    rec->add_option("--texture-sets", ra.textureSets,
                    "with --texture-space: sample sets averaged (default 16)");
    rec->add_option("--trace-x", ra.traceX, "traced pixel x (default: centre)");
    rec->add_option("--trace-y", ra.traceY, "traced pixel y (default: centre)");
    rec->add_flag("--force", ra.force, "replace an existing capture folder");

    auto* defaultsCmd = cli.add_subcommand(
        "defaults", "print every setting's default (GUI, CLI and captures) as a Markdown table");

    auto* rep = cli.add_subcommand("replay", "recompute a capture headless and compare");
    std::string repDir;
    bool repUpdate = false;
    rep->add_option("capture", repDir, "capture folder, e.g. captures/dipole_marble")->required();
    rep->add_flag("--update", repUpdate, "rewrite the recorded outputs from this run");

    auto* slab = cli.add_subcommand(
        "slab", "path-traced pencil beam on a semi-infinite slab: R_d(r) with standard errors");
    app::SlabArgs sa;
    app::addSlabOptions(slab, sa);
    auto* estimateCmd = cli.add_subcommand(
        "estimate", "the whole BSSRDF of the slab at oblique incidence (seed 001) as a table");
    app::EstimateArgs ea;
    app::addEstimateOptions(estimateCmd, ea);
    auto* compareCmd = cli.add_subcommand(
        "compare", "score every model against the path-traced reference (scoreboard)");
    app::CompareArgs ca;
    compareCmd->add_option("--models", ca.models,
                           "model files (default: every materials/*.bssrdf)");
    compareCmd->add_option("--presets", ca.presets, "preset names (default: all)");
    app::addCountOption(compareCmd, "--paths", ca.paths,
                        "reference paths per preset and channel (default " +
                            std::to_string(ca.paths) + ")",
                        core::Limits{1000, 1e12});
    compareCmd
        ->add_option("--theta-i", ca.thetaI,
                     "incidence angles in degrees, [0, 90): DEG[,DEG...]; 0 scores the radial "
                     "profile, others the whole BSSRDF (default 0)")
        ->delimiter(',');
    compareCmd->add_flag("!--no-plots", ca.plots, "reports without the PNG plots");
    compareCmd->add_option("--baseline", ca.baseline, "an earlier scores.json to compare with");
    app::addNumberOption(compareCmd, "--fail-if-worse", ca.failIfWorse,
                         "with --baseline: exit 1 when a rel_l2 grew by more than PCT %",
                         core::Limits{0, 1e6});
    compareCmd->add_option("--out", ca.out, "output folder: scores.json, report.md, report.html")
        ->required();

    auto* mergeCmd =
        cli.add_subcommand("merge", "merge table shards (estimate --shard) into one table");
    app::MergeArgs ma;
    app::addMergeOptions(mergeCmd, ma);

    // sphere / mesh: the path-traced lit object (radiant exitance per pixel, EXR with variance)
    app::ImageArgs ima;
    // defaults: the GUI's lit-sphere settings and the tracer's default medium
    const app::LitSphereSettings litDefaults;
    const pathtrace::Medium mediumDefaults;
    std::string imSigmaA = app::defaultText(mediumDefaults.sigmaA),
                imSigmaS = app::defaultText(mediumDefaults.sigmaS),
                imLight = app::defaultText(litDefaults.lightDir),
                imSize = std::to_string(litDefaults.size) + "x" + std::to_string(litDefaults.size);
    ima.g = mediumDefaults.g;
    ima.eta = mediumDefaults.eta;
    ima.radiusMm = litDefaults.radiusMm;
    ima.spp = uint64_t(litDefaults.pathSpp);
    ima.seed = litDefaults.seed;
    auto addImageOptions = [&](CLI::App* c) {
        const auto dflt = [](const std::string& v) { return " (default " + v + ")"; };
        c->add_option("--sigma-a", imSigmaA,
                      "absorption R,G,B (or one value) in 1/mm" + dflt(imSigmaA));
        c->add_option("--sigma-s", imSigmaS,
                      "scattering R,G,B (or one value) in 1/mm" + dflt(imSigmaS));
        c->add_option("--g", ima.g,
                      "Henyey-Greenstein mean cosine" + dflt(app::defaultText(ima.g)));
        c->add_option("--eta", ima.eta,
                      "relative index of refraction" + dflt(app::defaultText(ima.eta)));
        c->add_option("--radius", ima.radiusMm,
                      "sphere radius in mm; mesh: half its longest axis" +
                          dflt(app::defaultText(ima.radiusMm)));
        c->add_option("--light", imLight, "direction towards the light x,y,z" + dflt(imLight));
        c->add_option("--size", imSize, "image WxH" + dflt(imSize));
        c->add_option("--spp", ima.spp, "paths per covered pixel" + dflt(std::to_string(ima.spp)));
        c->add_option("--seed", ima.seed, "random seed" + dflt(std::to_string(ima.seed)));
        app::addCountOption(c, "--threads", ima.threads,
                            "worker threads, 0 … 1024 (default 0: all cores)", app::kThreadLimits);
        c->add_option("--out", ima.out, "EXR file: R,G,B exitance and varR,varG,varB")->required();
    };
    auto* sphere = cli.add_subcommand("sphere", "path-traced lit sphere (thesis 3.6.2) as EXR");
    addImageOptions(sphere);
    auto* meshCmd = cli.add_subcommand("mesh", "path-traced lit mesh (Embree) as EXR");
    addImageOptions(meshCmd);
    meshCmd->add_option("--mesh", ima.mesh, "closed, outward-facing triangle mesh (OBJ)")
        ->required();

    auto* integrateCmd = cli.add_subcommand(
        "integrate", "BSSRDF-integrated lit sphere or mesh, uniform or disk importance sampling, "
                     "as EXR");
    app::IntegrateArgs integ;
    app::addIntegrateOptions(integrateCmd, integ);

    auto* pcCmd = cli.add_subcommand(
        "pointcloud", "even point cloud on a mesh (thesis 2.6.4) as binary PLY, with metrics");
    app::PointCloudArgs pca;
    app::addPointCloudOptions(pcCmd, pca);

    auto* renderCmd = cli.add_subcommand(
        "render", "mesh rendered by the hierarchical point-cloud method (thesis 3.3) as EXR");
    app::RenderArgs ra2;
    app::addRenderOptions(renderCmd, ra2);

    auto* bench = cli.add_subcommand("bench", "benchmarks (print measured ratios; not tests)");
    bench->require_subcommand(1);
    auto* benchReload = bench->add_subcommand("reload", "hot reload: save -> new pixels latency");
    int reloadRuns = 10;
    benchReload->add_option("--runs", reloadRuns, "edits to time (default 10)")
        ->check(CLI::Range(1, 1000));
    auto* benchPt = bench->add_subcommand("pathtrace", "path tracer: paths/s and time to 1% error");
    double benchSeconds = 4.0;
    benchPt->add_option("--seconds", benchSeconds, "seconds per case and tracer (default 4)")
        ->check(CLI::Range(0.5, 600.0));

    auto* benchSamp = bench->add_subcommand(
        "sampling", "BSSRDF integration: equal-time error of disk importance vs uniform sampling");
    double sampSeconds = 2.0, sampReference = 10.0;
    int sampSize = 48;
    benchSamp->add_option("--seconds", sampSeconds, "seconds per method and case (default 2)")
        ->check(CLI::Range(0.05, 600.0));
    benchSamp->add_option("--size", sampSize, "image side in pixels (default 48)")
        ->check(CLI::Range(4, 1024));
    benchSamp
        ->add_option("--reference-factor", sampReference,
                     "the reference runs this many times longer (default 10)")
        ->check(CLI::Range(1.0, 1000.0));

    auto* benchConv = bench->add_subcommand(
        "convergence", "error against time of the Render panel's renderers, log-log plot");
    app::ConvergenceBenchOptions cbo;
    benchConv->add_option("--preset", cbo.preset, "material preset (default Marble)");
    benchConv->add_option("--width", cbo.width, "frame width (default 160)")
        ->check(CLI::Range(8, 4096));
    benchConv->add_option("--height", cbo.height, "frame height (default 90)")
        ->check(CLI::Range(8, 4096));
    benchConv->add_option("--points", cbo.points, "point-cloud points (default 50000)")
        ->check(CLI::Range(100, 10000000));
    benchConv
        ->add_option("--reference-spp", cbo.referenceSpp,
                     "samples per pixel of the converged image (default 1024)")
        ->check(CLI::Range(1, 1000000));
    benchConv->add_option("--max-spp", cbo.maxSpp, "last Monte Carlo point (default 256)")
        ->check(CLI::Range(1, 1000000));
    benchConv->add_option("--out", cbo.out, "folder for convergence.csv and convergence.png");

    auto* benchTs = bench->add_subcommand(
        "texture-space", "texture-space sampling vs the hierarchical render at equal error");
    app::TextureSpaceBenchOptions tbo;
    benchTs->add_option("--presets", tbo.presets, "material presets (default Marble Skin1)");
    benchTs->add_option("--scales", tbo.scalesMm, "model sizes in mm (default 10 50)");
    benchTs->add_option("--samples", tbo.samples, "N values (default 49 100 400 900 1600 2500)");
    benchTs->add_option("--textures", tbo.textures, "texture sizes (default 16 64 256 1024)");
    benchTs->add_option("--eps", tbo.eps, "hierarchical eps values (default 64 … 1)");
    benchTs->add_option("--points", tbo.points, "point-cloud points (default 50000)")
        ->check(CLI::Range(100, 10000000));
    benchTs->add_option("--width", tbo.width, "frame width (default 160)")
        ->check(CLI::Range(8, 4096));
    benchTs->add_option("--height", tbo.height, "frame height (default 90)")
        ->check(CLI::Range(8, 4096));
    benchTs->add_option("--sets", tbo.sets, "sample sets per case (default 4)")
        ->check(CLI::Range(1, 10000));

    auto* benchHier = bench->add_subcommand(
        "hierarchy", "hierarchical vs brute-force render, point-cloud generation vs Turk");
    app::HierarchyBenchOptions hbo;
    benchHier->add_option("--points", hbo.points, "points (default 100000)");
    app::addEnumOption(benchHier, "--method", hbo.method,
                       std::string("point-cloud method (default ") +
                           pointcloud::methodName(hbo.method) + ")");
    benchHier->add_option("--width", hbo.width, "image width (default 640)");
    benchHier->add_option("--height", hbo.height, "image height (default 360)");
    benchHier->add_option("--frames", hbo.frames, "hierarchical frames per eps (default 5)")
        ->check(CLI::Range(1, 1000));
    benchHier->add_option("--brute-frames", hbo.bruteFrames, "brute-force frames (default 3)")
        ->check(CLI::Range(1, 1000));
    benchHier
        ->add_option("--turk-iterations", hbo.turkIterations,
                     "Turk repulsion iterations of the reference cloud (default 500, 0: skip)")
        ->check(CLI::Range(0, 100000));
    benchHier->add_option("--eps", hbo.eps,
                          "solid-angle criterion eps values (default 0.8 0.4 0.2 0.1)");
    benchHier->add_option("--box-eps", hbo.boxEps,
                          "bounding-box criterion eps values (default 12.8 6.4 3.2 1.6)");

    // The check of a new model in a child process (model_probe_process.h); hidden from --help.
    auto* probeCmd = cli.add_subcommand("probe-model", "check a model's first evaluation");
    app::ProbeModelArgs pma;
    app::addProbeModelOptions(probeCmd, pma);
    // The same check kept warm, one request after another on stdin (cli_probe.h); hidden.
    auto* probeServerCmd = cli.add_subcommand("probe-server", "check models sent on stdin");
    probeServerCmd->group("");

    // Command-line errors in the one form every error takes, `error: <argument>: message`, with
    // exit status 2 (usage); help and version exit 0 as the parser prints them.
    app::refuseNonFiniteNumbers(cli);
    try {
        cli.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return cli.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return cli.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "error: %s\n(run with --help for the options)\n", e.what());
        return app::kUsageError;
    }
    if (verbose) core::setLogEchoLevel(core::LogLevel::Info);
    // Every model a Workbench loads is first evaluated by this executable in a child process.
    app::setModelProbeExecutable(app::selfExecutable());

    if (*defaultsCmd) {
        std::fputs(app::defaultsTable().c_str(), stdout);
        return 0;
    }
    try {
        // Commands that read no project file run anywhere; the rest find the root first.
        if (*probeServerCmd) return app::runProbeServer();
        if (*pcCmd) return app::runPointCloudCli(pca);
        if (*estimateCmd && !ea.gpu) return app::runEstimateCli(ea);
        if (*mergeCmd) return app::runMergeCli(ma);
        if (*slab && !sa.gpu) return app::runSlabCli(sa);
        const fs::path root = findRoot(rootArg);
        if (*probeCmd) return app::runProbeModel(root, pma);
        if (*prof) return app::runProfile(root, pa);
        if (*inv) return app::runInvert(root, ia);
        if (*rec) return app::runRecord(root, ra);
        if (*rep) return app::runReplay(root, repDir, repUpdate);
        if (*benchReload) return app::benchReload(root, reloadRuns);
        if (*compareCmd) return app::runCompareCli(root, ca);
        if (*benchPt) return app::benchPathtrace(root, benchSeconds);
        if (*benchTs) {
            for (int k : tbo.textures)
                if (k < 16 || k > 2048 || (k & (k - 1)) != 0)
                    throw core::Error("--textures", 0, "each must be a power of two in [16, 2048]");
            for (int n : tbo.samples)
                if (n < 1 || n > (1 << 20))
                    throw core::Error("--samples", 0, "each must lie in [1, 1048576]");
            return app::benchTextureSpace(root, tbo);
        }
        if (*benchHier) return app::benchHierarchy(root, hbo);
        if (*benchConv) return app::benchConvergence(root, cbo);
        if (*benchSamp) return app::benchSampling(root, sampSeconds, sampSize, sampReference);
        if (*sphere || *meshCmd) {
            const glm::dvec3 sa = app::parseRgb(imSigmaA, "--sigma-a");
            const glm::dvec3 ss = app::parseRgb(imSigmaS, "--sigma-s");
            const glm::dvec3 light = app::parseRgb(imLight, "--light");
            for (int c = 0; c < 3; ++c) {
                ima.sigmaA[c] = sa[c];
                ima.sigmaS[c] = ss[c];
                ima.light[c] = light[c];
            }
            if (!parseSize(imSize, ima.width, ima.height, 1))
                throw core::Error("--size", 0,
                                  "expected WxH between 1 and 8192, got '" + imSize + "'");
            return *sphere ? app::runSphereCli(ima) : app::runMeshCli(ima);
        }
        if (*renderCmd) return app::runRenderCli(root, ra2);
        if (*integrateCmd) return app::runIntegrateCli(root, integ);
        if (*slab) return app::runSlabGpuCli(root, sa);
        if (*estimateCmd) return app::runEstimateCli(ea, root);
        if (*shot) {
            app::GuiOptions opt;
            if (!parseSize(shotSize, opt.width, opt.height))
                throw core::Error("--size", 0,
                                  "expected WxH between 64 and 8192, got '" + shotSize + "'");
            opt.frames = shotFrames;
            opt.screenshotPath = shotOut;
            opt.persistLayout = false;
            auto ctx = gl::createHeadlessContext();
            app::Workbench wb(root, false);
            int rc = app::runGui(wb, *ctx, opt);
            if (rc == 0) std::printf("wrote %s\n", shotOut.c_str());
            return rc;
        }
        if (!headless && !gl::displayAvailable()) {
            std::printf("no display found (DISPLAY/WAYLAND_DISPLAY unset or unreachable): "
                        "running the default capture headless\n");
            headless = true;
        }
        if (headless) return runHeadlessDefault(root, headlessOut);
        std::fprintf(stderr, "resources: %s\n", root.c_str());
        auto ctx = gl::createWindowContext(1600, 1000, "BSSRDF Workbench");
        app::Workbench wb(root, true);
        app::GuiOptions opt;
        return app::runGui(wb, *ctx, opt);
    } catch (const core::Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
