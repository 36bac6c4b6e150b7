// Capture record/replay for the workbench stages (material, pencil_plot).
#include "captures/capture_io.h"

#include "captures/scene_outputs.h"

#include "capture/capture.h"
#include "core/color.h"
#include "core/core.h"
#include "core/fields.h"
#include "core/text.h"
#include "gl/gl.h"
#include "pathtrace/image_io.h"
#include "captures/settings_json.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {
constexpr const char* kExternalPrefix = "external/";

struct StageTable {
    std::string stage, file, key;
    capture::Table table;
    double absTol, relTol;
    std::string note;
    double alpha = 0; // > 0: Monte Carlo output compared by z-test (kind csv_stat)
};

// GPU float32 evaluation: GLSL guarantees exp/pow to (3 + 2|x|) ulp; with |x| up to ~30 in
// the profile's tail that is ~63 ulp, i.e. 63 · 2^-24 ≈ 3.8e-6 relative, plus the same again
// for the arithmetic around it. 1e-5 relative covers a different driver; on the same driver
// replays are bit-exact.
constexpr double kProfileRelTol = 1e-5;
// σ from R_dr/l_d: the bisection brackets α′ to 2^-27; float32 DiffuseReflectance moves the
// root by ~1 ulp of α′ ≈ 6e-8, amplified by 1/(1−α′) in σa (≤ ~1e3 for the presets).
constexpr double kInvertedRelTol = 1e-4;

std::string gpuString(GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? reinterpret_cast<const char*>(s) : "";
}

// The path-traced reference (when enabled): raw MCML-convention R_d per channel with its
// standard errors, compared statistically on replay. The last row (r_mm = -1) holds the
// total diffuse reflectance per channel.
constexpr double kReferenceAlpha = 1e-3;
std::optional<capture::Table> referenceTable(Workbench& wb) {
    if (!wb.referenceSettings().enabled) return std::nullopt;
    ReferenceSnapshot snap = wb.finishReference();
    if (!snap.problem.empty()) throw core::Error("reference", 0, snap.problem);
    if (snap.pathsDone == 0) return std::nullopt;
    capture::Table t;
    t.comments = {"path-traced reference, sigma of " + wb.reference().model(),
                  "R_d per unit area per incident photon (MCML convention), 1/mm^2",
                  "paths per channel " + std::to_string(snap.pathsDone),
                  "last row (r_mm = -1): total diffuse reflectance per channel"};
    t.columns = {"r_mm", "R", "R_stderr", "G", "G_stderr", "B", "B_stderr"};
    for (size_t i = 0; i < snap.channel[0].rMid.size(); ++i) {
        std::vector<double> row{snap.channel[0].rMid[i]};
        for (int c = 0; c < 3; ++c) {
            row.push_back(snap.channel[c].rd[i]);
            row.push_back(snap.channel[c].rdStderr[i]);
        }
        t.rows.push_back(std::move(row));
    }
    std::vector<double> totals{-1};
    for (int c = 0; c < 3; ++c) {
        totals.push_back(snap.channel[c].totalRd);
        totals.push_back(snap.channel[c].totalRdStderr);
    }
    t.rows.push_back(std::move(totals));
    return t;
}

// The BSSRDF slice (when enabled): the path-traced table with its standard errors (z-tested
// on replay; the last row, bin -1, holds the total diffuse reflectance), and every model on its
// bins (float32 GPU evaluations summed in double).
void sliceTables(Workbench& wb, std::vector<StageTable>& out) {
    if (!wb.sliceSettings().enabled) return;
    const SliceSnapshot snap = wb.finishSlice();
    if (!snap.problem.empty()) throw core::Error("slice", 0, snap.problem);
    if (!snap.slice) return;
    const pathtrace::BssrdfBins& b = snap.settings.bins;
    const pathtrace::BssrdfSlice& s = *snap.slice;
    const std::vector<double> edges = b.rEdges();
    const size_t cells = b.dirBins() > 1 ? size_t(b.dirBins()) : 0;
    auto geometry = [&](size_t bin) {
        const int ir = int(bin) / b.thetaSBins, it = int(bin) % b.thetaSBins;
        const double dth = 180.0 / b.thetaSBins;
        return std::vector<double>{double(bin), edges[size_t(ir)], edges[size_t(ir) + 1], it * dth,
                                   (it + 1) * dth};
    };
    const std::vector<std::string> geomColumns{"bin", "r_lo_mm", "r_hi_mm", "theta_s_lo_deg",
                                               "theta_s_hi_deg"};
    StageTable ref{"slice",
                   "slice.csv",
                   "bin",
                   {},
                   0,
                   0,
                   "Monte Carlo: per-value z-test, Bonferroni over all bins and cells",
                   kReferenceAlpha};
    ref.table.comments = {"BSSRDF slice (seed 001), sigma of " + wb.slice().model() + ", channel " +
                              std::string(1, "RGB"[std::clamp(wb.sliceSettings().channel, 0, 2)]) +
                              ", theta_i " + core::formatNumber(s.thetaIDeg, 6) + " deg, " +
                              std::to_string(snap.pathsDone) + " paths",
                          "R per incident photon (MCML), 1/mm^2; S_k in exit cell k, 1/(mm^2 sr)",
                          "last row (bin -1): total diffuse reflectance"};
    ref.table.columns = geomColumns;
    ref.table.columns.insert(ref.table.columns.end(), {"R", "R_stderr"});
    for (size_t k = 0; k < cells; ++k) {
        ref.table.columns.push_back("S" + std::to_string(k));
        ref.table.columns.push_back("S" + std::to_string(k) + "_stderr");
    }
    for (size_t bin = 0; bin < s.R.size(); ++bin) {
        std::vector<double> row = geometry(bin);
        row.insert(row.end(), {s.R[bin], s.RStderr[bin]});
        for (size_t k = 0; k < cells; ++k)
            row.insert(row.end(), {s.S[bin * cells + k], s.SStderr[bin * cells + k]});
        ref.table.rows.push_back(std::move(row));
    }
    std::vector<double> total{-1, 0, 0, 0, 0, s.totalRd, s.totalRdStderr};
    total.resize(ref.table.columns.size(), 0.0);
    ref.table.rows.push_back(std::move(total));
    out.push_back(std::move(ref));
    for (const auto& [path, r] : wb.slice().models()) {
        if (!r.slice) continue;
        const std::string name = fs::path(path).stem().string();
        StageTable m{"slice_model." + name,
                     "slice_model_" + name + ".csv",
                     "bin",
                     {},
                     0,
                     kProfileRelTol,
                     "float32 GPU evaluation of Bssrdf(), averaged in double"};
        m.table.comments = {"model " + path + " on the slice's bins, own sigma",
                            "R per incident photon, 1/mm^2; S_k in exit cell k, 1/(mm^2 sr)"};
        m.table.columns = geomColumns;
        m.table.columns.push_back("R");
        for (size_t k = 0; k < cells; ++k)
            m.table.columns.push_back("S" + std::to_string(k));
        for (size_t bin = 0; bin < r.slice->R.size(); ++bin) {
            std::vector<double> row = geometry(bin);
            row.push_back(r.slice->R[bin]);
            for (size_t k = 0; k < cells; ++k)
                row.push_back(r.slice->S[bin * cells + k]);
            m.table.rows.push_back(std::move(row));
        }
        out.push_back(std::move(m));
    }
}

std::vector<StageTable> stageTables(Workbench& wb, std::vector<std::string>& missing) {
    std::vector<StageTable> out;
    for (auto& e : wb.library().entries()) {
        const std::string name = e.model ? e.model->name : e.file.stem().string();
        auto& v = wb.view(e.displayPath);
        if (!e.usable() || !v.effective) {
            missing.push_back(name + ": " +
                              (e.problem                   ? e.problem->text()
                               : v.materialProblem.empty() ? "not computed"
                                                           : v.materialProblem));
            continue;
        }
        const MaterialSettings& s = v.override ? v.own : wb.shared();
        StageTable m{"material." + name, "material_" + name + ".csv", "channel", {}, 0, 0, ""};
        m.table.comments = {"model " + e.displayPath, "effective sigma in 1/mm"};
        m.table.columns = {"channel", "sigma_a", "sigma_s"};
        for (int c = 0; c < 3; ++c)
            m.table.rows.push_back({double(c), v.effective->sigmaA[c], v.effective->sigmaS[c]});
        if (s.mode == ParamMode::RdrLd) {
            m.relTol = kInvertedRelTol;
            m.note = "inverted from R_dr/l_d with float32 GPU DiffuseReflectance";
        } else {
            m.note = "copied from the inputs (exact)";
        }
        out.push_back(std::move(m));

        StageTable p{"pencil_plot." + name,
                     "pencil_plot_" + name + ".csv",
                     "r_mm",
                     {},
                     0,
                     kProfileRelTol,
                     "float32 GPU evaluation of Bssrdf(); GLSL exp <= (3+2|x|) ulp"};
        p.table.comments = {"model " + e.displayPath,
                            "Bssrdf(Xi=0, Wi=n, Xo=(r,0,0), Wo=n) in 1/mm^2"};
        p.table.columns = {"r_mm", "R", "G", "B"};
        for (size_t i = 0; i < v.profile.r.size(); ++i)
            p.table.rows.push_back(
                {v.profile.r[i], v.profile.value[i].x, v.profile.value[i].y, v.profile.value[i].z});
        out.push_back(std::move(p));
    }
    if (auto ref = referenceTable(wb))
        out.push_back({"reference", "reference.csv", "r_mm", std::move(*ref), 0, 0,
                       "Monte Carlo: per-value z-test, Bonferroni over all bins and channels",
                       kReferenceAlpha});
    sliceTables(wb, out);
    return out;
}

capture::StageOutput writeStage(const fs::path& dir, const StageTable& t) {
    if (t.alpha > 0)
        return capture::writeCsvStatStage(dir, t.stage, t.file, t.table, t.alpha, t.note);
    return capture::writeCsvStage(dir, t.stage, t.file, t.table, t.absTol, t.relTol, t.note);
}

// Lit-sphere images (when the stage is on): EXR with a variance per pixel, compared by
// per-pixel z-tests (kind exr_stat) on replay.
constexpr double kImageAlpha = 1e-3;
struct ImageStage {
    std::string stage, file;
    pathtrace::Image image;
};
std::vector<ImageStage> imageStages(Workbench& wb) {
    std::vector<ImageStage> out;
    if (wb.litSphereSettings().enabled) {
        wb.finishLitSpheres();
        // The real cause (a refused mesh, a bad setup), never a consequence such as an empty
        // image.
        if (const std::string problem = wb.litSpheres().problem(); !problem.empty())
            throw core::Error("lit spheres", 0, problem);
        if (!wb.litSphereSettings().mesh.empty()) // both renderings cover the mesh
            out = {{"lit_mesh.path_traced", "lit_mesh_path_traced.exr", wb.litSpheres().pathTracer().image()},
                   {"lit_mesh.integrated", "lit_mesh_integrated.exr", wb.litSpheres().integratedImage()}};
        else
            out = {{"lit_sphere.path_traced", "lit_sphere_path_traced.exr", wb.litSpheres().pathTracer().image()},
                   {"lit_sphere.integrated", "lit_sphere_integrated.exr", wb.litSpheres().integratedImage()}};
    }
    // The texture-space render (seed 004): the mean over its sample sets with the variance of
    // the mean per pixel.
    if (wb.scene().settings().enabled && wb.textureSpaceSettings().enabled) {
        wb.finishScene();
        wb.finishTextureSpace();
        out.push_back(
            {"texture_space.render", "texture_space_render.exr", wb.textureSpace().radiance()});
    }
    return out;
}
// x, y, then each channel with its standard error: the form compareStatTables reads.
capture::Table imageTable(const pathtrace::Image& img) {
    capture::Table t;
    t.columns = {"x", "y", "R", "R_stderr", "G", "G_stderr", "B", "B_stderr"};
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const size_t p = size_t(y) * size_t(img.width) + size_t(x);
            std::vector<double> row{double(x), double(y)};
            for (int c = 0; c < 3; ++c) {
                row.push_back(img.mean[3 * p + c]);
                row.push_back(std::sqrt(std::max(0.0, double(img.variance[3 * p + c]))));
            }
            t.rows.push_back(std::move(row));
        }
    return t;
}
// A model's path in a capture: its path under the root, or for a model opened from outside
// the project "external/FILE" (its text is in the manifest; replay loads it from there).
std::string capturePathOf(const bssrdf::ModelEntry& e) {
    if (!fs::path(e.displayPath).is_absolute()) return e.displayPath;
    return std::string(kExternalPrefix) + e.file.filename().string();
}

json paramsJson(Workbench& wb) {
    json models = json::object();
    for (auto& e : wb.library().entries()) {
        auto& v = wb.view(e.displayPath);
        models[capturePathOf(e)] = {{"visible", v.visible},
                                    {"override", v.override},
                                    {"own", core::toJson(v.own)},
                                    {"values", toJson(e.values)}};
    }
    return {{"shared", core::toJson(wb.shared())}, {"models", models}};
}

void applyParams(Workbench& wb, const json& params, const std::string& where) {
    // Every JSON type is checked here, so a hostile manifest gets a message with its JSON
    // path, never the JSON library's own exception text.
    if (!params.is_object() || !params.contains("shared") || !params.contains("models"))
        throw core::Error(where, 0, "params needs 'shared' and 'models'");
    wb.shared() = core::fromJson(params["shared"], where, "params.shared", MaterialSettings{});
    if (!params["models"].is_object())
        throw core::Error(where, 0, "params.models: expected an object");
    for (auto it = params["models"].begin(); it != params["models"].end(); ++it) {
        auto* e = wb.library().find(it.key());
        // an external model was loaded from a copy of its recorded text: find it by its file
        if (!e && it.key().rfind(kExternalPrefix, 0) == 0)
            for (auto& cand : wb.library().entries())
                if (capturePathOf(cand) == it.key()) e = &cand;
        if (!e) continue; // reported as an input problem / missing stage
        const std::string path = "params.models." + it.key();
        const std::string w = where + " (" + path + ")";
        if (!it->is_object() || !it->contains("own") || !it->contains("values"))
            throw core::Error(where, 0, path + ": needs 'own' and 'values'");
        auto flag = [&](const char* key, bool otherwise) {
            if (!it->contains(key)) return otherwise;
            if (!it->at(key).is_boolean())
                throw core::Error(where, 0, path + "." + key + ": expected true or false");
            return it->at(key).get<bool>();
        };
        auto& v = wb.view(e->displayPath);
        v.visible = flag("visible", true);
        v.override = flag("override", false);
        v.own = core::fromJson(it->at("own"), where, path + ".own", MaterialSettings{});
        auto values = valuesFromJson(it->at("values"), w);
        for (auto& [k, val] : values)
            if (e->values.count(k)) e->values[k] = val;
    }
}

// A failed image stage leaves pictures of the failure beside the capture, in
// <capture>.replay/: the replayed image (EXR) and a PNG of recorded | replayed | difference,
// the difference as each pixel's worst |a − b| / (absTol + relTol·|b|) on the colour ramp
// over [0, 2] (above 1: out of tolerance), the images tone-mapped alike. Returns the line that
// names them, or why they could not be written (the replay result stands either way).
std::string writeImageDifference(const fs::path& captureDir, const std::string& stage,
                                 const pathtrace::Image& recorded, const pathtrace::Image& replayed,
                                 double absTol, double relTol) {
    if (recorded.width != replayed.width || recorded.height != replayed.height)
        return "(no difference image: the sizes differ)";
    const fs::path dir = captureDir.parent_path() / (captureDir.filename().string() + ".replay");
    const int w = recorded.width, h = recorded.height;
    std::vector<unsigned char> rgba(size_t(3 * w) * size_t(h) * 4, 255);
    auto put = [&](int x, int y, glm::vec3 c) {
        unsigned char* p = &rgba[(size_t(y) * size_t(3 * w) + size_t(x)) * 4];
        for (int k = 0; k < 3; ++k)
            p[k] = (unsigned char)(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
    };
    auto tone = [](float v) {
        return std::pow(std::max(v, 0.0f) / (1.0f + std::max(v, 0.0f)), 1.0f / 2.2f);
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t p = size_t(y) * size_t(w) + size_t(x);
            float excess = 0;
            glm::vec3 a, b;
            for (int c = 0; c < 3; ++c) {
                a[c] = recorded.mean[3 * p + size_t(c)];
                b[c] = replayed.mean[3 * p + size_t(c)];
                const double d = std::abs(double(b[c]) - double(a[c]));
                const double lim = absTol + relTol * std::abs(double(a[c]));
                excess = std::max(excess, float(lim > 0 ? d / lim : (d > 0 ? 1e9 : 0.0)));
                if (!std::isfinite(a[c]) || !std::isfinite(b[c])) excess = 1e9f;
            }
            put(x, y, {tone(a.x), tone(a.y), tone(a.z)});
            put(x + w, y, {tone(b.x), tone(b.y), tone(b.z)});
            put(x + 2 * w, y, core::colorRamp(std::min(excess, 2.0f) / 2.0f));
        }
    try {
        fs::create_directories(dir);
        const fs::path png = dir / (stage + ".diff.png"), exr = dir / (stage + ".replayed.exr");
        gl::writePng(png, 3 * w, h, rgba);
        pathtrace::writeExr(exr, replayed);
        return "recorded | replayed | difference (ramp over 0..2x tolerance): " + png.string() +
               "; replayed image: " + exr.string();
    } catch (const std::exception& e) {
        return std::string("(no difference image: ") + e.what() + ")";
    }
}

} // namespace

void recordCaptureTo(Workbench& wb, const fs::path& dir, const std::string& name, int traceX,
                     int traceY) {
    if (!capture::isValidName(name))
        throw core::Error(name, 0, "invalid capture name (letters, digits, '_', '-', '.' only)");
    wb.update();
    std::vector<std::string> missing;
    auto tables = stageTables(wb, missing);
    if (tables.empty())
        throw core::Error(dir.string(), 0, "nothing to record: no model produced output");
    capture::Manifest m;
    m.name = name;
    m.createdUtc = capture::utcNow();
    m.programVersion = BW_VERSION;
    m.glRenderer = gpuString(GL_RENDERER);
    m.glVersion = gpuString(GL_VERSION);
    for (auto& e : wb.library().entries()) {
        std::string text = core::readFile(e.file);
        const std::string path = capturePathOf(e);
        for (const capture::ModelFile& other : m.models)
            if (other.path == path)
                throw core::Error(e.displayPath, 0,
                                  "two models opened from outside the project are both named " +
                                      e.file.filename().string() + "; rename one to record");
        m.models.push_back({path, core::hashHex(text), text});
    }
    const SceneSettings& scene = wb.scene().settings();
    if (scene.enabled) { // the scene's mesh is an input: path and content hash
        const fs::path meshPath = fs::path(scene.meshFile).is_absolute()
                                      ? fs::path(scene.meshFile)
                                      : wb.root() / scene.meshFile;
        std::string text = core::readFile(meshPath);
        m.models.push_back({scene.meshFile, core::hashHex(text),
                            "(mesh, " + std::to_string(text.size()) + " bytes)"});
    }
    if (const std::string& mesh = wb.litSphereSettings().mesh;
        !mesh.empty() && wb.litSphereSettings().enabled) {
        // the mesh is an input like the models: path (relative to the root) and content hash
        std::string text = core::readFile(wb.root() / mesh);
        m.models.push_back({mesh, core::hashHex(text),
                            text.size() < (1u << 20)
                                ? text
                                : "(mesh, " + std::to_string(text.size()) + " bytes)"});
    }
    m.params = paramsJson(wb);
    m.settings = settingsJson(wb, traceX, traceY);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw core::Error(dir.string(), 0, "cannot create capture folder: " + ec.message());
    for (auto& t : tables)
        m.outputs.push_back(writeStage(dir, t));
    for (auto& im : imageStages(wb)) {
        pathtrace::writeExr(dir / im.file, im.image);
        m.outputs.push_back(capture::describeFileStage(
            dir, im.stage, im.file, "exr_stat", kImageAlpha,
            "Monte Carlo image: per-pixel z-test, Bonferroni over all pixels and channels"));
    }
    SceneCapture sc = sceneOutputs(wb, traceX, traceY);
    for (auto& t : sc.tables)
        m.outputs.push_back(
            capture::writeCsvStage(dir, t.stage, t.file, t.table, t.absTol, t.relTol, t.note));
    if (sc.image) {
        pathtrace::writeExr(dir / sc.image->file, sc.image->image);
        capture::StageOutput o = capture::describeFileStage(dir, sc.image->stage, sc.image->file,
                                                            "exr", 0, sc.image->note);
        o.absTol = sc.image->absTol;
        o.relTol = sc.image->relTol;
        m.outputs.push_back(o);
    }
    capture::writeManifest(dir, m);
    for (const auto& s : missing)
        core::logWarn("capture " + name + ": not recorded: " + s);
}

// The input files a replayed capture's settings name resolve inside the capture folder or the
// project (the root holding materials/ and shaders/), never elsewhere ("../../etc/passwd", an
// absolute path outside, a symlink out): checked before anything is read.
static void checkCaptureInputs(Workbench& wb, const fs::path& captureDir,
                               const std::string& where) {
    const std::vector<fs::path> folders = {captureDir, wb.root()};
    const SceneSettings& sc = wb.scene().settings();
    const std::pair<const char*, const std::string*> inputs[] = {
        {"settings.scene.mesh", &sc.meshFile},
        {"settings.scene.point_cloud_file", &sc.pointCloudFile},
        {"settings.scene.environment", &sc.environmentFile},
        {"settings.scene.projected_texture", &sc.projectedTextureFile},
        {"settings.lit_spheres.mesh", &wb.litSphereSettings().mesh}};
    for (const auto& [key, value] : inputs)
        if (std::string bad = capture::confinedInputProblem(*value, wb.root(), folders);
            !bad.empty())
            throw core::Error(where, 0,
                              std::string(key) + ": '" + core::printableText(*value) + "' " + bad);
}

std::string recordCapture(Workbench& wb, const std::string& name) {
    fs::path dir = wb.root() / "captures" / name;
    recordCaptureTo(wb, dir, name);
    return core::relativeTo(dir, wb.root());
}

int replayCapture(const fs::path& captureDir, const fs::path& root, bool update, std::string& out) {
    capture::Manifest m;
    try {
        m = capture::readManifest(captureDir);
    } catch (const core::Error& e) {
        out = std::string("ERROR ") + e.what() + "\n";
        return 2;
    }
    // A capture may come from someone else: its outputs stay plain files inside its folder
    // (read on replay, written by --update).
    for (size_t i = 0; i < m.outputs.size(); ++i)
        if (std::string bad = capture::outputPathProblem(captureDir, m.outputs[i].file);
            !bad.empty()) {
            out = "ERROR " + (captureDir / capture::kManifestFileName).string() + ": outputs[" +
                  std::to_string(i) + "].file '" + core::printableText(m.outputs[i].file) +
                  "': " + bad + "\n";
            return 2;
        }
    capture::ReplayReport report;
    if (!update)
        report.inputProblems = capture::checkInputs(m, captureDir, root, &report.inputNotes);
    std::vector<fs::path> models;
    // Models recorded from outside the project are replayed from their recorded text, written
    // to a temporary folder (removed when the replay ends).
    const fs::path external =
        fs::temp_directory_path() / ("bw_replay_external_" + std::to_string(::getpid()));
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{external};
    for (const auto& mf : m.models) {
        if (fs::path(mf.path).extension() != ".bssrdf") continue;
        if (mf.path.rfind(kExternalPrefix, 0) == 0) {
            const fs::path file = external / fs::path(mf.path).filename();
            fs::create_directories(external);
            core::writeFile(file, mf.source);
            models.push_back(file);
        } else if (fs::exists(root / mf.path)) {
            models.push_back(root / mf.path);
        }
    }
    const std::string where = (captureDir / capture::kManifestFileName).string();
    try {
        Workbench wb(root, false, models);
        applyParams(wb, m.params, where);
        if (!m.settings.contains("plot")) throw core::Error(where, 0, "settings.plot missing");
        int traceX = -1, traceY = -1;
        applySettingsJson(wb, m.settings, where, traceX, traceY);
        checkCaptureInputs(wb, captureDir, where);
        wb.update();
        std::vector<std::string> missing;
        auto tables = stageTables(wb, missing);
        auto images = imageStages(wb);
        SceneCapture sc = sceneOutputs(wb, traceX, traceY);
        for (auto& t : sc.tables)
            tables.push_back(
                {t.stage, t.file, t.key, std::move(t.table), t.absTol, t.relTol, t.note});
        for (auto& rec : m.outputs) {
            if (rec.kind == "exr") {
                capture::Comparison c;
                c.stage = rec.stage;
                if (!sc.image || sc.image->stage != rec.stage) {
                    c.message = "stage not produced by this run (scene off?)";
                } else if (update) {
                    pathtrace::writeExr(captureDir / rec.file, sc.image->image);
                    const double a = sc.image->absTol, r = sc.image->relTol;
                    rec = capture::describeFileStage(captureDir, rec.stage, rec.file, rec.kind, 0,
                                                     rec.tolNote);
                    rec.absTol = a;
                    rec.relTol = r;
                    c.pass = true;
                    c.message = "updated";
                } else {
                    try {
                        const pathtrace::Image recorded = pathtrace::readExr(captureDir / rec.file);
                        c = capture::compareTables(rec.stage, renderTable(recorded),
                                                   renderTable(sc.image->image), rec.absTol,
                                                   rec.relTol);
                        if (!c.pass && c.message.empty())
                            c.artifacts =
                                writeImageDifference(captureDir, rec.stage, recorded,
                                                     sc.image->image, rec.absTol, rec.relTol);
                    } catch (const core::Error& e) {
                        c.message = std::string("cannot read the recorded image: ") + e.what();
                    }
                }
                report.stages.push_back(c);
                continue;
            }
            if (rec.kind == "exr_stat") {
                auto im = std::find_if(images.begin(), images.end(),
                                       [&](const ImageStage& i) { return i.stage == rec.stage; });
                capture::Comparison c;
                c.stage = rec.stage;
                if (im == images.end()) {
                    c.message = "stage not produced by this run (lit spheres off?)";
                } else if (update) {
                    pathtrace::writeExr(captureDir / rec.file, im->image);
                    rec = capture::describeFileStage(captureDir, rec.stage, rec.file, rec.kind,
                                                     rec.alpha, rec.tolNote);
                    c.pass = true;
                    c.message = "updated";
                } else {
                    try {
                        c = capture::compareStatTables(
                            rec.stage, imageTable(pathtrace::readExr(captureDir / rec.file)),
                            imageTable(im->image), rec.alpha);
                    } catch (const core::Error& e) {
                        c.message = std::string("cannot read the recorded image: ") + e.what();
                    }
                }
                report.stages.push_back(c);
                continue;
            }
            auto it = std::find_if(tables.begin(), tables.end(),
                                   [&](const StageTable& t) { return t.stage == rec.stage; });
            if (it == tables.end()) {
                capture::Comparison c;
                c.stage = rec.stage;
                c.message = "stage not produced by this run";
                for (const auto& s : missing)
                    c.message += "; " + s;
                report.stages.push_back(c);
                continue;
            }
            if (update) {
                rec = writeStage(captureDir, *it);
                capture::Comparison c;
                c.stage = rec.stage;
                c.pass = true;
                c.message = "updated";
                report.stages.push_back(c);
            } else {
                report.stages.push_back(
                    capture::compareCsvStage(rec, captureDir, it->table, it->key));
            }
        }
        if (update) {
            m.glRenderer = gpuString(GL_RENDERER);
            m.glVersion = gpuString(GL_VERSION);
            for (auto& mf : m.models)
                if (fs::exists(root / mf.path)) mf.hash = capture::hashFile(root / mf.path);
            capture::writeManifest(captureDir, m);
        }
    } catch (const core::Error& e) {
        out = std::string("ERROR ") + e.what() + "\n";
        return 2;
    }
    out = report.text();
    return report.pass() ? 0 : 1;
}

} // namespace app
