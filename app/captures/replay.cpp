// Replaying a capture (capture_io.h): the recorded inputs (models, params, settings) loaded into
// a fresh workbench, every stage's outputs made again (Workbench::capture) and each recorded
// output compared with the new one as its kind says: tables value by value or by z-tests,
// images pixel by pixel (with pictures of a failure) or by per-pixel z-tests. --update rewrites
// the recorded outputs instead.
#include "captures/capture_io.h"

#include "capture/capture.h"
#include "captures/image_difference.h"
#include "captures/manifest.h"
#include "captures/settings_json.h"
#include "core/core.h"
#include "core/text.h"
#include "pathtrace/image_io.h"

#include <algorithm>
#include <atomic>

#include <unistd.h>

namespace app {
namespace fs = std::filesystem;

namespace {

bool isImage(CaptureEntry::Kind k) {
    return k == CaptureEntry::Kind::Exr || k == CaptureEntry::Kind::ExrStat ||
           k == CaptureEntry::Kind::ExrInput;
}

// One recorded output against this run's: compared, or with `update` rewritten from it.
capture::Comparison replayStage(capture::StageOutput& rec, const fs::path& captureDir,
                                const CaptureEntries& captured, bool update) {
    const bool recordedImage =
        rec.kind == "exr" || rec.kind == "exr_stat" || capture::isInputKind(rec.kind);
    auto it =
        std::find_if(captured.entries.begin(), captured.entries.end(), [&](const CaptureEntry& e) {
            return e.stage == rec.stage && isImage(e.kind) == recordedImage;
        });
    capture::Comparison c;
    c.stage = rec.stage;
    if (it == captured.entries.end()) {
        c.message = "stage not produced by this run";
        if (rec.kind == "exr")
            c.message += " (scene off?)";
        else if (rec.kind == "exr_stat")
            c.message += " (lit spheres off?)";
        else
            for (const auto& s : captured.missing)
                c.message += "; " + s;
        return c;
    }
    if (update) {
        if (capture::isInputKind(rec.kind)) {
            rec = writeCaptureEntry(captureDir, *it);
        } else if (rec.kind == "exr") {
            pathtrace::writeExr(captureDir / rec.file, it->image);
            rec = capture::describeFileStage(captureDir, rec.stage, rec.file, rec.kind, 0,
                                             rec.tolNote);
            rec.absTol = it->absTol;
            rec.relTol = it->relTol;
        } else if (rec.kind == "exr_stat") {
            pathtrace::writeExr(captureDir / rec.file, it->image);
            rec = capture::describeFileStage(captureDir, rec.stage, rec.file, rec.kind, rec.alpha,
                                             rec.tolNote);
        } else {
            rec = writeCaptureEntry(captureDir, *it);
        }
        c.pass = true;
        c.message = "updated";
        return c;
    }
    if (capture::isInputKind(rec.kind)) { // given to the stage, not made again: unchanged?
        try {
            const std::string now = capture::hashFile(captureDir / rec.file);
            c.pass = now == rec.hash;
            c.message = c.pass ? "recorded input, given to the stage (hash matches)"
                               : "recorded input changed since it was recorded (hash " + now +
                                     ", recorded " + rec.hash + ")";
        } catch (const core::Error& e) {
            c.message = std::string("cannot read the recorded input: ") + e.what();
        }
        return c;
    }
    if (!recordedImage)
        return capture::compareCsvStage(rec, captureDir, it->table, it->key,
                                        it->conditioning.rows.empty() ? nullptr : &it->conditioning,
                                        it->conditioningNote);
    try {
        const pathtrace::Image recorded = pathtrace::readExr(captureDir / rec.file);
        if (rec.kind == "exr_stat")
            return capture::compareStatTables(rec.stage, imageTable(recorded),
                                              imageTable(it->image), rec.alpha);
        c = capture::compareTables(
            rec.stage, renderTable(recorded), renderTable(it->image), rec.absTol, rec.relTol, "",
            it->conditioning.rows.empty() ? nullptr : &it->conditioning, it->conditioningNote);
        if (!c.pass && c.message.empty())
            c.artifacts = writeImageDifference(captureDir, rec.stage, recorded, it->image,
                                               rec.absTol, rec.relTol);
    } catch (const core::Error& e) {
        c.message = std::string("cannot read the recorded image: ") + e.what();
    }
    return c;
}

} // namespace

void checkCaptureInputFiles(Workbench& wb, const fs::path& captureDir, const std::string& where) {
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

ExternalModels::ExternalModels() {
    static std::atomic<int> count{0}; // two at once in one process get two folders
    dir = fs::temp_directory_path() /
          ("bw_external_models_" + std::to_string(::getpid()) + "_" + std::to_string(count++));
}

ExternalModels::~ExternalModels() {
    std::error_code ec;
    fs::remove_all(dir, ec);
}

std::unique_ptr<Workbench> workbenchFromInputs(const capture::Manifest& m, const fs::path& root,
                                               const fs::path& externalDir,
                                               const std::string& where, int& traceX, int& traceY,
                                               bool watch) {
    std::vector<fs::path> models;
    for (const auto& mf : m.models) {
        if (fs::path(mf.path).extension() != ".bssrdf") continue;
        if (mf.path.rfind(kExternalPrefix, 0) == 0) {
            const fs::path file = externalDir / fs::path(mf.path).filename();
            fs::create_directories(externalDir);
            core::writeFile(file, mf.source);
            models.push_back(file);
        } else if (fs::exists(root / mf.path)) {
            models.push_back(root / mf.path);
        }
    }
    auto wb = std::make_unique<Workbench>(root, watch, models);
    applyParams(*wb, m.params, where);
    if (!m.settings.contains("plot")) throw core::Error(where, 0, "settings.plot missing");
    applySettingsJson(*wb, m.settings, where, traceX, traceY);
    // a capture's scene is generated, never read from this machine's point-cloud cache: no
    // cache hides a change on replay, and recording from a request writes none
    wb->scene().settings().useCache = false;
    return wb;
}

int replayCapture(const fs::path& captureDir, const fs::path& root, bool update, std::string& out,
                  const std::function<void(const std::string&)>& onStage) {
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
    const std::string where = (captureDir / capture::kManifestFileName).string();
    const ExternalModels external;
    try {
        int traceX = -1, traceY = -1;
        std::unique_ptr<Workbench> owned =
            workbenchFromInputs(m, root, external.dir, where, traceX, traceY);
        Workbench& wb = *owned;
        checkCaptureInputFiles(wb, captureDir, where);
        CaptureEntries captured;
        captured.traceX = traceX;
        captured.traceY = traceY;
        captured.forReplay = true;
        if (!update) // --update rewrites from this driver's own rasterisation
            captured.recordedImage =
                [&](const std::string& stage) -> std::optional<pathtrace::Image> {
                for (const capture::StageOutput& rec : m.outputs)
                    if (rec.stage == stage && capture::isInputKind(rec.kind))
                        return pathtrace::readExr(captureDir / rec.file);
                return std::nullopt;
            };
        if (!update)
            captured.recordedTable =
                [&](const std::string& stage) -> std::optional<capture::Table> {
                for (const capture::StageOutput& rec : m.outputs)
                    if (rec.stage == stage && rec.kind == "csv")
                        return capture::readCsv(captureDir / rec.file);
                return std::nullopt;
            };
        wb.capture(captured, onStage);
        report.inputNotes.insert(report.inputNotes.end(), captured.notes.begin(),
                                 captured.notes.end());
        for (auto& rec : m.outputs)
            report.stages.push_back(replayStage(rec, captureDir, captured, update));
        if (update) // outputs this program makes that the capture lacks are added
            for (const CaptureEntry& e : captured.entries) {
                const bool listed = std::any_of(m.outputs.begin(), m.outputs.end(),
                                                [&](const capture::StageOutput& o) {
                                                    return o.stage == e.stage && o.file == e.file;
                                                });
                if (!e.recorded || listed) continue;
                m.outputs.push_back(writeCaptureEntry(captureDir, e));
                capture::Comparison c;
                c.stage = e.stage;
                c.pass = true;
                c.message = "added";
                report.stages.push_back(c);
            }
        if (update) {
            m.glRenderer = glRendererString();
            m.glVersion = glVersionString();
            for (auto& mf : m.models) // the hash and the recorded text, as `record` writes them
                if (fs::exists(root / mf.path)) {
                    mf.hash = capture::hashFile(root / mf.path);
                    if (mf.source.empty()) continue;
                    const std::string text = core::readFile(root / mf.path);
                    // a mesh is recorded by its size only (lit_sphere_stage, scene_capture)
                    mf.source = mf.source.rfind("(mesh, ", 0) == 0
                                    ? "(mesh, " + std::to_string(text.size()) + " bytes)"
                                    : text;
                }
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
