// CLI subcommands on a headless GL context: profile (pencil-beam CSV), invert (R_dr/l_d → σ),
// record and replay (captures).
#include "cli.h"
#include "cli_output.h"
#include "cli_slab.h"
#include "core/fields.h"
#include "core/text.h"

#include "capture_io.h"
#include "core/core.h"
#include "gl/gl.h"
#include "workbench.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include <unistd.h>

namespace app {
namespace fs = std::filesystem;

glm::dvec3 parseRgb(const std::string& text, const std::string& argName) {
    std::vector<double> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        double d = std::strtod(item.c_str(), &end);
        if (item.empty() || end == item.c_str() || *end != '\0')
            throw core::Error(argName, 0, "'" + item + "' is not a number (expected R,G,B)");
        v.push_back(d);
    }
    if (v.size() == 1) return glm::dvec3(v[0]);
    if (v.size() != 3)
        throw core::Error(argName, 0,
                          "expected 3 comma-separated values R,G,B (or one for all), got " +
                              std::to_string(v.size()));
    return {v[0], v[1], v[2]};
}

namespace {
std::string rgb(const glm::dvec3& v) {
    return core::formatNumber(v.x) + " " + core::formatNumber(v.y) + " " + core::formatNumber(v.z);
}

} // namespace

fs::path resolveModel(const fs::path& root, const std::string& model) {
    fs::path p = model;
    if (!fs::exists(p) && fs::exists(root / p)) p = root / p;
    if (!fs::exists(p)) throw core::Error(model, 0, "--model: no such file");
    return p;
}

MaterialSettings settingsFromArgs(Workbench& wb, const std::string& preset,
                                  const std::string& sigmaA, const std::string& sigmaS,
                                  std::optional<double> g, std::optional<double> eta) {
    MaterialSettings s;
    if (g) s.params.g = *g;
    if (!preset.empty()) {
        if (!sigmaA.empty() || !sigmaS.empty())
            throw core::Error("--preset", 0, "give either --preset or --sigma-a/--sigma-s");
        wb.applyPreset(s, preset); // σs = σ′s/(1−g), η from the preset
    } else {
        if (sigmaA.empty() || sigmaS.empty())
            throw core::Error("--sigma-a", 0, "give --preset NAME or both --sigma-a and --sigma-s");
        s.params.sigmaA = parseRgb(sigmaA, "--sigma-a");
        s.params.sigmaS = parseRgb(sigmaS, "--sigma-s");
        s.preset.clear();
        s.params.eta = 1.3;
    }
    if (eta) s.params.eta = *eta;
    material::validate(s.params, "arguments");
    return s;
}

int runProfile(const fs::path& root, const ProfileArgs& a) {
    if (a.samples < 2) throw core::Error("--samples", 0, "must be >= 2");
    if (a.rMax && !(*a.rMax > 0 && std::isfinite(*a.rMax)))
        throw core::Error("--rmax", 0, "must be a positive length in mm");
    fs::path model = resolveModel(root, a.model);
    checkWritable(a.out, "--out");
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, {model});
    auto& e = wb.library().entries().at(0);
    if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    wb.shared() = settingsFromArgs(wb, a.preset, a.sigmaA, a.sigmaS, a.g, a.eta);
    wb.plotSettings().samples = a.samples;
    if (a.rMax) {
        wb.plotSettings().fixedRange = true;
        wb.plotSettings().rMaxMm = *a.rMax;
    }
    wb.update();
    auto& v = wb.view(e.displayPath);
    if (!v.effective) throw core::Error(e.displayPath, 0, v.materialProblem);
    const auto& p = *v.effective;
    std::ostringstream out;
    out << "# bssrdf-workbench profile " << BW_VERSION << "\n"
        << "# model " << e.displayPath << " (" << e.model->hash << ")\n"
        << "# preset " << (wb.shared().preset.empty() ? "(none)" : wb.shared().preset) << "\n"
        << "# sigma_a " << rgb(p.sigmaA) << " 1/mm\n"
        << "# sigma_s " << rgb(p.sigmaS) << " 1/mm\n"
        << "# g " << core::formatNumber(p.g) << "\n# eta " << core::formatNumber(p.eta) << "\n"
        << "# r_max_mm " << core::formatNumber(wb.rMaxMm()) << "\n# samples " << a.samples << "\n";
    for (const auto& [k, val] : e.values)
        out << "# param " << k << " " << core::formatNumber(val[0]) << " "
            << core::formatNumber(val[1]) << " " << core::formatNumber(val[2]) << "\n";
    out << "# " << Workbench::normalisationNote() << "\n";
    if (!v.profileProblem.empty()) out << "# invalid " << v.profileProblem << "\n";
    out << "r_mm,R,G,B\n";
    for (size_t i = 0; i < v.profile.r.size(); ++i)
        out << core::formatNumber(v.profile.r[i]) << ',' << core::formatNumber(v.profile.value[i].x)
            << ',' << core::formatNumber(v.profile.value[i].y) << ','
            << core::formatNumber(v.profile.value[i].z) << '\n';
    core::writeFile(a.out, out.str());
    std::cerr << "wrote " << a.out << " (" << v.profile.r.size() << " radii up to "
              << core::formatNumber(wb.rMaxMm()) << " mm)\n";
    if (!v.profileProblem.empty()) { // written, but not a valid reflectance: say so, status 3
        std::cerr << "error: " << e.displayPath << ": " << v.profileProblem << "\n";
        return kEnergyCheckFailed;
    }
    return 0;
}

int runInvert(const fs::path& root, const InvertArgs& a) {
    fs::path model = resolveModel(root, a.model);
    MaterialSettings s;
    s.mode = ParamMode::RdrLd;
    s.rdr = parseRgb(a.rdr, "--rdr");
    s.ld = parseRgb(a.ld, "--ld");
    if (a.g) s.params.g = *a.g;
    s.params.eta = a.eta.value_or(1.3);
    for (int c = 0; c < 3; ++c) {
        if (!(s.rdr[c] >= 0 && s.rdr[c] <= 1))
            throw core::Error("--rdr", 0,
                              "R_dr must lie in [0, 1], got " + core::formatNumber(s.rdr[c]));
        if (!(s.ld[c] > 0) || !std::isfinite(s.ld[c]))
            throw core::Error("--ld", 0,
                              "l_d must be a positive length in mm, got " +
                                  core::formatNumber(s.ld[c]));
    }
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, {model});
    auto& e = wb.library().entries().at(0);
    if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    auto p = effectiveParams(e, s);
    std::printf("sigma_a %s\nsigma_s %s\n", rgb(p.sigmaA).c_str(), rgb(p.sigmaS).c_str());
    return 0;
}

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
            fs::path mesh = resolveModel(root, a.litMesh); // exists, absolute or under root
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
    if (a.textureSpace > 0) {
        if (a.scenePoints == 0)
            throw core::Error("--texture-space", 0, "needs --scene-points (the scene's mesh)");
        TextureSpaceSettings& ts = wb.textureSpaceSettings();
        ts.enabled = true;
        ts.sampling.textureSize = a.textureSpace;
        ts.sampling.samples = a.textureSamples;
        ts.sampling.sampleSets = a.textureSets;
        try {
            texspace::validateSettings(ts.sampling);
        } catch (const core::Error& e) {
            throw core::Error("--texture-space", 0, e.what());
        }
    }
    wb.update();
    // Recorded into a temporary folder beside the target and renamed when complete, so a
    // failed record leaves nothing behind and a replaced capture is never half old, half new.
    const fs::path tmp = dir.parent_path() / ("." + dir.filename().string() + ".recording-" +
                                              std::to_string(::getpid()));
    fs::remove_all(tmp, ec);
    try {
        recordCaptureTo(wb, tmp, a.name, traceX, traceY);
        if (fs::exists(dir, ec)) fs::remove_all(dir);
        fs::rename(tmp, dir);
    } catch (...) {
        fs::remove_all(tmp, ec);
        throw;
    }
    std::printf("recorded %s\n", dir.string().c_str());
    return 0;
}

int runReplay(const fs::path& root, const std::string& dir, bool update) {
    auto ctx = gl::createHeadlessContext(false);
    std::string text;
    int rc = replayCapture(dir, root, update, text);
    std::printf("%s", text.c_str());
    if (!text.empty() && text.back() != '\n') std::printf("\n");
    return rc;
}

} // namespace app
