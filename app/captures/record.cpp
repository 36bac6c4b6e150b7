// Recording a capture (capture_io.h): the manifest (models with their text, params, settings,
// the GL driver) and every stage's outputs as the stages give them (Workbench::capture), each
// written as its kind says.
#include "captures/capture_io.h"

#include "capture/capture.h"
#include "captures/manifest.h"
#include "captures/settings_json.h"
#include "core/core.h"
#include "pathtrace/image_io.h"

#include <unistd.h>

namespace app {
namespace fs = std::filesystem;

capture::StageOutput writeCaptureEntry(const fs::path& dir, const CaptureEntry& e) {
    switch (e.kind) {
    case CaptureEntry::Kind::Csv:
        return capture::writeCsvStage(dir, e.stage, e.file, e.table, e.absTol, e.relTol, e.note);
    case CaptureEntry::Kind::CsvStat:
        return capture::writeCsvStatStage(dir, e.stage, e.file, e.table, e.alpha, e.note);
    case CaptureEntry::Kind::Exr: {
        pathtrace::writeExr(dir / e.file, e.image);
        capture::StageOutput o = capture::describeFileStage(dir, e.stage, e.file, "exr", 0, e.note);
        o.absTol = e.absTol;
        o.relTol = e.relTol;
        return o;
    }
    case CaptureEntry::Kind::ExrInput:
        pathtrace::writeExr(dir / e.file, e.image);
        return capture::describeFileStage(dir, e.stage, e.file, "exr_input", 0, e.note);
    case CaptureEntry::Kind::ExrStat:
        pathtrace::writeExr(dir / e.file, e.image);
        return capture::describeFileStage(dir, e.stage, e.file, "exr_stat", e.alpha, e.note);
    }
    throw core::Error(e.stage, 0, "unknown capture entry kind");
}

capture::Manifest captureInputs(Workbench& wb, const std::string& name, int traceX, int traceY) {
    if (const std::string problem = capture::nameProblem(name); !problem.empty())
        throw core::Error(name, 0, "invalid capture name: " + problem);
    capture::Manifest m;
    m.name = name;
    m.createdUtc = capture::utcNow();
    m.programVersion = BW_VERSION;
    m.glRenderer = glRendererString();
    m.glVersion = glVersionString();
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
    m.params = paramsJson(wb);
    m.settings = settingsJson(wb, traceX, traceY);
    return m;
}

void recordCaptureTo(Workbench& wb, const fs::path& dir, const std::string& name, int traceX,
                     int traceY, const std::function<void(const std::string&)>& onStage) {
    // Settings the stages complete as they apply them (a mesh's first load frames the camera:
    // SceneStage) go into the manifest as they will run: applied before it is written.
    wb.update();
    capture::Manifest m = captureInputs(wb, name, traceX, traceY);
    CaptureEntries captured;
    captured.traceX = traceX;
    captured.traceY = traceY;
    wb.capture(captured, onStage);
    if (captured.entries.empty())
        throw core::Error(dir.string(), 0, "nothing to record: no model produced output");
    for (auto& input : captured.inputs) // meshes: path and content hash
        m.models.push_back(std::move(input));
    for (const CaptureEntries::Resolved& r : captured.resolved) // `auto` → what ran
        if (m.settings.contains(r.section)) m.settings[r.section][r.key] = r.value;
    // Written into a temporary folder beside `dir` and renamed over it when complete: a capture
    // folder never exists without its manifest, a failed record leaves nothing behind, and a
    // capture recorded again holds none of the previous recording's files.
    const fs::path parent = dir.parent_path().empty() ? fs::path(".") : dir.parent_path();
    const fs::path tmp =
        parent / ("." + dir.filename().string() + ".recording-" + std::to_string(::getpid()));
    std::error_code ec;
    fs::remove_all(tmp, ec);
    fs::create_directories(tmp, ec);
    if (ec) throw core::Error(dir.string(), 0, "cannot create capture folder: " + ec.message());
    try {
        for (const CaptureEntry& e : captured.entries)
            if (e.recorded) m.outputs.push_back(writeCaptureEntry(tmp, e));
        capture::writeManifest(tmp, m);
        if (fs::exists(dir, ec)) fs::remove_all(dir);
        fs::rename(tmp, dir);
    } catch (...) {
        fs::remove_all(tmp, ec);
        throw;
    }
    for (const auto& s : captured.missing)
        core::logWarn("capture " + name + ": not recorded: " + s);
}

fs::path recordRequestPath(const fs::path& root, const std::string& name) {
    return root / "captures" / ("." + name + ".request") / "request.json";
}

fs::path writeRecordRequest(Workbench& wb, const std::string& name, int traceX, int traceY) {
    const capture::Manifest m = captureInputs(wb, name, traceX, traceY);
    const fs::path dir = recordRequestPath(wb.root(), name).parent_path();
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    if (ec) throw core::Error(dir.string(), 0, "cannot create the folder: " + ec.message());
    capture::writeInputs(dir / "request.json", m);
    return dir / "request.json";
}

void recordFromRequest(const fs::path& request, const fs::path& root, const fs::path& dir,
                       const std::string& name,
                       const std::function<void(const std::string&)>& onStage) {
    const capture::Manifest m = capture::readInputs(request);
    const std::string where = request.string();
    int traceX = -1, traceY = -1;
    const ExternalModels external;
    std::unique_ptr<Workbench> wb =
        workbenchFromInputs(m, root, external.dir, where, traceX, traceY);
    recordCaptureTo(*wb, dir, name, traceX, traceY, onStage);
}

std::string recordCapture(Workbench& wb, const std::string& name) {
    fs::path dir = wb.root() / "captures" / name;
    recordCaptureTo(wb, dir, name);
    return core::relativeTo(dir, wb.root());
}

} // namespace app
