// `record` and `replay`: captures of the workbench state, headless (captures/capture_io.h).
#include "cli/capture_commands.h"

#include "captures/capture_io.h"
#include "cli/args.h"
#include "cli/command.h"
#include "cli/output.h"
#include "core/core.h"
#include "core/fields.h"
#include "core/text.h"
#include "gl/gl.h"
#include "pipeline/workbench.h"

#include <cstdio>
#include <functional>
#include <iostream>
#include <memory>

namespace app {
namespace fs = std::filesystem;

namespace {
// "record: stage reference" on stderr as each stage's outputs are made (the GUI shows the last).
std::function<void(const std::string&)> printStage(const char* what) {
    return [what](const std::string& stage) {
        std::fprintf(stderr, "%s: stage %s\n", what, stage.c_str());
        std::fflush(stderr);
    };
}
} // namespace

int runRecord(const fs::path& root, const RecordArgs& a) {
    const fs::path dir = a.outDir.empty() ? root / "captures" / a.name : fs::path(a.outDir);
    const std::string flag = a.outDir.empty() ? "--name" : "--out";
    std::error_code ec;
    if (fs::exists(dir, ec) && !a.force)
        throw core::Error(
            flag, 0, "capture folder '" + dir.string() + "' exists; give --force to replace it");
    const fs::path parent = dir.parent_path().empty() ? fs::path(".") : dir.parent_path();
    fs::create_directories(parent, ec);
    checkWritable((parent / ".bw-record-probe").string(), flag);
    if (!a.fromRequest.empty()) { // the GUI's state, recorded here so the GUI never waits
        auto ctx = gl::createHeadlessContext(false);
        recordFromRequest(a.fromRequest, root, dir, a.name, printStage("record"));
        std::printf("recorded %s\n", dir.string().c_str());
        return 0;
    }
    std::vector<fs::path> models;
    for (const auto& m : a.models)
        models.push_back(resolveModel(root, m));
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, models);
    if (!a.preset.empty()) wb.applyPreset(wb.shared(), a.preset);
    if (a.referencePaths > 0) {
        wb.referenceSettings().enabled = true;
        wb.referenceSettings().paths = a.referencePaths;
        if (a.referenceBins) wb.referenceSettings().bins = *a.referenceBins;
    }
    if (a.sliceThetaI &&
        !(std::isfinite(*a.sliceThetaI) && *a.sliceThetaI >= 0 && *a.sliceThetaI < 90))
        throw core::Error("--slice-theta-i", 0,
                          "the incidence angle must lie in [0, 90) degrees, got " +
                              core::formatNumber(*a.sliceThetaI, 6));
    if (a.slicePaths > 0) {
        wb.sliceSettings().enabled = true;
        wb.sliceSettings().paths = a.slicePaths;
        if (a.sliceThetaI) wb.sliceSettings().thetaIDeg = *a.sliceThetaI;
    }
    if (a.litSphereSize > 0) {
        auto& ls = wb.litSphereSettings();
        ls.enabled = true;
        ls.size = a.litSphereSize;
        ls.pathSpp = 8;
        ls.integratedSpp = 1024;
        if (!a.litMesh.empty()) {
            fs::path mesh = resolveModel(root, a.litMesh, "--lit-mesh"); // absolute or under root
            ls.mesh = core::relativeTo(mesh, root);
        }
        if (!a.litSampling.empty())
            ls.sampling =
                core::enumFromName<integrate::Sampling>(a.litSampling, "--lit-sampling", "");
        if (!a.litAxes.empty())
            ls.axes = core::enumFromName<sampling::AxisScheme>(a.litAxes, "--lit-axes", "");
    }
    int traceX = -1, traceY = -1;
    if (a.scenePoints > 0) {
        SceneSettings& s = wb.scene().settings();
        s.enabled = true;
        s.useCache = false;
        s.meshFile = a.sceneMesh;
        s.points.points = a.scenePoints;
        s.render.width = a.sceneWidth;
        s.render.height = a.sceneHeight;
        traceX = a.traceX >= 0 ? a.traceX : a.sceneWidth / 2;
        traceY = a.traceY >= 0 ? a.traceY : a.sceneHeight / 2;
    }
    if (a.hybrid && a.textureSpace == 0)
        throw core::Error("--hybrid", 0, "needs --texture-space (the hybrid's global part)");
    if (a.textureSpace > 0) {
        if (a.scenePoints == 0)
            throw core::Error("--texture-space", 0, "needs --scene-points (the scene's mesh)");
        TextureSpaceSettings& ts = wb.textureSpaceSettings();
        ts.enabled = true;
        ts.sampling.textureSize = a.textureSpace;
        ts.sampling.samples = a.textureSamples;
        ts.sampling.sampleSets = a.textureSets;
        ts.sampling.hybrid = a.hybrid;
        try {
            texspace::validateSettings(ts.sampling);
        } catch (const core::Error& e) {
            throw core::Error("--texture-space", 0, e.what());
        }
    }
    // applied, recorded into a temporary folder and renamed when complete (recordCaptureTo)
    recordCaptureTo(wb, dir, a.name, traceX, traceY, printStage("record"));
    std::printf("recorded %s\n", dir.string().c_str());
    return 0;
}

int runReplay(const fs::path& root, const std::string& dir, bool update) {
    auto ctx = gl::createHeadlessContext(false);
    std::string text;
    int rc = replayCapture(dir, root, update, text, printStage("replay"));
    std::printf("%s", text.c_str());
    if (!text.empty() && text.back() != '\n') std::printf("\n");
    if (rc == 1) // where a CI log says FAIL, the way to the state that failed
        std::printf("look at the recorded state: bssrdf-workbench gui --capture %s\n", dir.c_str());
    return rc;
}

Command recordCommand() {
    return {
        "record", "record a capture of the default state headless", false,
        [](CLI::App& cmd) -> CommandRun {
            auto a = std::make_shared<RecordArgs>();
            cmd.add_option("--name", a->name, "capture name (folder under captures/)")->required();
            cmd.add_option("--model", a->models, "model files (default: every materials/*.bssrdf)");
            cmd.add_option("--preset", a->preset, "material preset (default Marble)");
            cmd.add_option("--out", a->outDir, "folder (default captures/NAME)");
            auto* referencePaths = cmd.add_option(
                "--reference-paths", a->referencePaths,
                "also record the path-traced pencil-beam reference with this many paths per "
                "channel (default 0: off)");
            auto* slicePaths = cmd.add_option(
                "--slice-paths", a->slicePaths,
                "also record the BSSRDF slice (path-traced table and every model on its "
                "bins) with this many paths (default 0: off)");
            cmd.add_option("--slice-theta-i", a->sliceThetaI,
                           "incidence angle of the slice, degrees (default " +
                               core::defaultText(SliceSettings{}.thetaIDeg) + ")")
                ->needs(slicePaths);
            auto* litSpheres =
                cmd.add_option(
                       "--lit-spheres", a->litSphereSize,
                       "also record the lit-sphere images (path traced and BSSRDF integrated) at "
                       "this size in pixels (default 0: off)")
                    ->check(CLI::Range(0, 1024));
            cmd.add_option(
                   "--lit-mesh", a->litMesh,
                   "with --lit-spheres: path trace this OBJ (a file under the project root) "
                   "instead of the sphere")
                ->needs(litSpheres);
            cmd.add_option("--lit-sampling", a->litSampling,
                           "with --lit-spheres: BSSRDF integration uniform or disk (default " +
                               std::string(core::nameOf(LitSphereSettings{}.sampling)) + ")")
                ->needs(litSpheres);
            cmd.add_option(
                   "--lit-axes", a->litAxes,
                   "with --lit-sampling disk: probe axes uniform, pbrt, normal or all (default " +
                       std::string(core::nameOf(LitSphereSettings{}.axes)) + ")")
                ->needs(litSpheres);
            cmd.add_option("--reference-bins", a->referenceBins,
                           "radial bins of the reference (default " +
                               std::to_string(ReferenceSettings{}.bins) + ")")
                ->check(CLI::Range(1, 100000))
                ->needs(referencePaths);

            auto* scenePoints = cmd.add_option(
                "--scene-points", a->scenePoints,
                "also record the mesh pipeline (point cloud, octree, irradiance, render, one "
                "traversal trace) with this many points (default 0: off)");
            cmd.add_option("--scene-mesh", a->sceneMesh,
                           "with --scene-points: the OBJ (under the root; default the bunny)")
                ->needs(scenePoints);
            cmd.add_option("--scene-width", a->sceneWidth, "render width (default 160)")
                ->check(CLI::Range(1, 4096))
                ->needs(scenePoints);
            cmd.add_option("--scene-height", a->sceneHeight, "render height (default 90)")
                ->check(CLI::Range(1, 4096))
                ->needs(scenePoints);
            auto* textureSpace = cmd.add_option(
                "--texture-space", a->textureSpace,
                "with --scene-points: also record the texture-space stages (texels, E', "
                "the first draws, the render over its sets) at this texture size K "
                "(default 0: off)");
            cmd.add_option("--texture-samples", a->textureSamples,
                           "with --texture-space: N per sample set (default 256)")
                ->needs(textureSpace);
            cmd.add_option("--texture-sets", a->textureSets,
                           "with --texture-space: sample sets averaged (default 16)")
                ->needs(textureSpace);
            cmd.add_flag("--hybrid", a->hybrid,
                         "with --texture-space: render by the hybrid (the local term by the "
                         "light-view ring filter, recorded too)");
            cmd.add_option("--trace-x", a->traceX,
                           "with --scene-points: traced pixel x (default: centre)")
                ->needs(scenePoints);
            cmd.add_option("--trace-y", a->traceY,
                           "with --scene-points: traced pixel y (default: centre)")
                ->needs(scenePoints);
            cmd.add_flag("--force", a->force, "replace an existing capture folder");
            cmd.add_option("--from-request", a->fromRequest,
                           "record the state a GUI wrote to this manifest (File -> Record "
                           "capture records in a child process this way)");
            return [a](CommandContext& ctx) { return runRecord(ctx.root(), *a); };
        }};
}

Command replayCommand() {
    return {"replay", "recompute a capture headless and compare", false,
            [](CLI::App& cmd) -> CommandRun {
                struct Args {
                    std::string dir;
                    bool update = false;
                };
                auto a = std::make_shared<Args>();
                cmd.add_option("capture", a->dir, "capture folder, e.g. captures/dipole_marble")
                    ->required();
                cmd.add_flag("--update", a->update, "rewrite the recorded outputs from this run");
                return
                    [a](CommandContext& ctx) { return runReplay(ctx.root(), a->dir, a->update); };
            }};
}

} // namespace app
