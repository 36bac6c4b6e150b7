// A capture's recorded state opened in the window (open_capture.h).
#include "captures/open_capture.h"

#include "capture/capture.h"
#include "captures/manifest.h"
#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <map>

namespace app {
namespace fs = std::filesystem;

fs::path findCapture(const fs::path& root, const std::string& nameOrFolder) {
    std::error_code ec;
    if (nameOrFolder.empty()) throw core::Error("--capture", 0, "expected a capture's name");
    fs::path given = fs::path(nameOrFolder).lexically_normal();
    if (!given.has_filename() && given.has_parent_path()) given = given.parent_path(); // "x/"
    if (fs::is_regular_file(given / capture::kManifestFileName, ec)) return given;
    const fs::path inProject = root / "captures" / given;
    if (given.has_filename() && given.filename() == given &&
        fs::is_regular_file(inProject / capture::kManifestFileName, ec))
        return inProject;
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(root / "captures", ec)) {
        const std::string n = e.path().filename().string();
        if (!n.empty() && n[0] != '.' &&
            fs::is_regular_file(e.path() / capture::kManifestFileName, ec))
            names.push_back(n);
    }
    std::sort(names.begin(), names.end());
    std::string known;
    for (const std::string& n : names)
        known += (known.empty() ? "" : ", ") + n;
    throw core::Error(nameOrFolder, 0,
                      "no such capture: neither a folder with a " +
                          std::string(capture::kManifestFileName) + " nor a capture under " +
                          (root / "captures").string() +
                          (known.empty() ? " (there are none)" : " (there: " + known + ")"));
}

std::vector<std::string> describeCapture(const fs::path& root, const fs::path& folder) {
    const capture::Manifest m = capture::readManifest(folder);
    std::vector<std::string> lines;
    lines.push_back("recorded " + m.createdUtc + " by version " + m.programVersion +
                    (m.glRenderer.empty() ? std::string(", no GL")
                                          : " on " + core::printableText(m.glRenderer)));
    std::vector<std::string> notes;
    const std::vector<std::string> problems = capture::checkInputs(m, folder, root, &notes);
    const auto said = [](const std::vector<std::string>& list, const std::string& path) {
        const std::string prefix = path + ": ";
        for (const std::string& p : list)
            if (p.rfind(prefix, 0) == 0) return p.substr(prefix.size());
        return std::string();
    };
    for (const capture::ModelFile& mf : m.models) {
        std::string state = said(problems, mf.path);
        if (state.empty()) state = said(notes, mf.path);
        if (state.empty()) state = "as recorded";
        lines.push_back((fs::path(mf.path).extension() == ".bssrdf" ? "model " : "input ") +
                        mf.path + ": " + state);
    }
    if (m.params.is_object() && m.params.contains("shared") && m.params["shared"].is_object()) {
        const auto& shared = m.params["shared"];
        const auto preset = shared.find("preset");
        if (preset != shared.end() && preset->is_string() && !preset->get<std::string>().empty())
            lines.push_back("preset " + preset->get<std::string>());
    }
    if (m.settings.is_object() && m.settings.contains("scene") && m.settings["scene"].is_object() &&
        m.settings["scene"].contains("trace_pixel")) {
        const auto& t = m.settings["scene"]["trace_pixel"];
        if (t.is_array() && t.size() == 2 && t[0].is_number_integer() && t[0].get<int>() >= 0)
            lines.push_back("traced pixel (" + std::to_string(t[0].get<int>()) + ", " +
                            std::to_string(t[1].get<int>()) + ")");
    }
    std::map<std::string, int> kinds;
    for (const capture::StageOutput& o : m.outputs)
        ++kinds[o.kind];
    std::string stages = std::to_string(m.outputs.size()) + " stage outputs (";
    for (const auto& [kind, n] : kinds)
        stages += (stages.back() == '(' ? "" : ", ") + std::to_string(n) + " " + kind;
    lines.push_back(stages + ")");
    return lines;
}

namespace {
// The capture shows only the pencil plot (no scene, lit spheres or slice), as plain values.
bool showsThePencilPlotAsValues(Workbench& wb) {
    const PlotSettings& plot = wb.plotSettings();
    return !wb.scene().settings().enabled && !wb.litSphereSettings().enabled &&
           !wb.sliceSettings().enabled && plot.relation == plot::Relation::Values &&
           plot.solo.empty();
}
} // namespace

OpenedCapture openCapture(const fs::path& root, const fs::path& folder, bool watch) {
    OpenedCapture out;
    out.folder = folder;
    capture::Manifest m = capture::readManifest(folder); // throws, naming the manifest
    out.name = m.name;
    const std::string where = (folder / capture::kManifestFileName).string();
    // What differs from the recording: the project's models edited or gone since (the outputs'
    // own state is the replay's business, not the state's). Each such model's recorded text is
    // opened beside it as NAME.recorded, with the recorded parameters, so that the window shows
    // the state as recorded and today's model on the same plot.
    out.files = std::make_unique<ExternalModels>();
    std::vector<std::string> notes, entries;
    // the recorded texts of models edited since (their file is there), with their entry's index
    std::vector<std::pair<fs::path, size_t>> editedCopies;
    const std::vector<std::string> problems = capture::checkInputs(m, folder, root, &notes);
    const std::vector<capture::ModelFile> recorded = m.models;
    for (const capture::ModelFile& mf : recorded) {
        if (mf.path.rfind(kExternalPrefix, 0) == 0) continue;
        const std::string prefix = mf.path + ": ";
        auto problem = std::find_if(problems.begin(), problems.end(),
                                    [&](const std::string& p) { return p.rfind(prefix, 0) == 0; });
        if (problem == problems.end()) continue;
        std::string entry = "capture " + m.name + ": " + *problem;
        const fs::path path(mf.path);
        if (path.extension() == ".bssrdf" && !mf.source.empty()) {
            const std::string copy = path.stem().string() + ".recorded.bssrdf";
            capture::ModelFile beside = mf;
            beside.path = kExternalPrefix + copy;
            m.models.push_back(beside);
            if (m.params.is_object() && m.params.contains("models") &&
                m.params["models"].is_object() && m.params["models"].contains(mf.path))
                m.params["models"][beside.path] = m.params["models"][mf.path];
            if (fs::exists(root / mf.path))
                editedCopies.emplace_back(out.files->dir / copy, entries.size());
            entry += std::string("; the window shows ") +
                     (fs::exists(root / mf.path) ? "today's file and, beside it, " : "") +
                     "the recorded text as " + path.stem().string() + ".recorded (" +
                     (out.files->dir / copy).string() + ")";
        }
        entries.push_back(entry);
    }
    out.wb = workbenchFromInputs(m, root, out.files->dir, where, out.traceX, out.traceY, watch);
    checkCaptureInputFiles(*out.wb, folder, where);
    if (editedCopies.size() == 1 && showsThePencilPlotAsValues(*out.wb)) {
        // what the edit changed, at a glance: every curve relative to the recorded model's
        const fs::path copy = fs::weakly_canonical(editedCopies[0].first);
        for (const bssrdf::ModelEntry& e : out.wb->library().entries())
            if (fs::weakly_canonical(e.file) == copy) {
                PlotSettings& plot = out.wb->plotSettings();
                plot.relation = plot::Relation::Ratio;
                plot.compareWith = e.displayPath;
                entries[editedCopies[0].second] +=
                    "; the pencil plot shows every curve as its ratio to the "
                    "recorded one (show: values for the curves as recorded)";
            }
    }
    for (const std::string& e : entries)
        out.wb->reportActionError(e);
    for (const std::string& n : notes)
        if (n.rfind(kExternalPrefix, 0) != 0) core::logInfo("capture " + m.name + ": " + n);
    core::logInfo("opened capture " + m.name + " (" + folder.string() + ", recorded " +
                  m.createdUtc + " on " + core::printableText(m.glRenderer) + ")");
    return out;
}

} // namespace app
