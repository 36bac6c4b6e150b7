// capture record/replay helpers: file hashes, writing and comparing CSV stages, input checks
// and the replay report the CLI prints.
#include "capture.h"

#include <algorithm>

#include "core/core.h"

#include <cmath>

namespace capture {

std::string hashFile(const std::filesystem::path& path) {
    return core::hashHex(core::readFile(path));
}

StageOutput writeCsvStage(const std::filesystem::path& captureDir, const std::string& stage,
                          const std::string& file, const Table& table, double absTol, double relTol,
                          const std::string& tolNote) {
    const std::filesystem::path path = captureDir / file;
    if (!isValidName(stage))
        throw core::Error(path.string(), 0, "'" + stage + "' is not a valid stage name");
    std::string problem = relativePathProblem(file);
    if (!problem.empty()) throw core::Error(path.string(), 0, problem);
    if (!(absTol >= 0) || !(relTol >= 0) || !std::isfinite(absTol) || !std::isfinite(relTol))
        throw core::Error(path.string(), 0, "tolerances must be finite and >= 0");
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec)
        throw core::Error(path.parent_path().string(), 0, "cannot create folder: " + ec.message());
    writeCsv(path, table);
    StageOutput out;
    out.stage = stage;
    out.file = file;
    out.kind = "csv";
    out.absTol = absTol;
    out.relTol = relTol;
    out.tolNote = tolNote;
    out.hash = hashFile(path);
    return out;
}

StageOutput describeFileStage(const std::filesystem::path& captureDir, const std::string& stage,
                              const std::string& file, const std::string& kind, double alpha,
                              const std::string& tolNote) {
    const std::filesystem::path path = captureDir / file;
    if (!isValidName(stage))
        throw core::Error(path.string(), 0, "'" + stage + "' is not a valid stage name");
    std::string problem = relativePathProblem(file);
    if (!problem.empty()) throw core::Error(path.string(), 0, problem);
    auto kinds = knownOutputKinds();
    if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end())
        throw core::Error(path.string(), 0, "unknown output kind '" + kind + "'");
    if (isStatisticalKind(kind) && !(alpha > 0 && alpha < 1))
        throw core::Error(path.string(), 0, "alpha must lie in (0, 1)");
    StageOutput out;
    out.stage = stage;
    out.file = file;
    out.kind = kind;
    out.alpha = isStatisticalKind(kind) ? alpha : 0;
    out.tolNote = tolNote;
    out.hash = hashFile(path);
    return out;
}

StageOutput writeCsvStatStage(const std::filesystem::path& captureDir, const std::string& stage,
                              const std::string& file, const Table& table, double alpha,
                              const std::string& tolNote) {
    if (!(alpha > 0 && alpha < 1))
        throw core::Error((captureDir / file).string(), 0, "alpha must lie in (0, 1)");
    StageOutput out = writeCsvStage(captureDir, stage, file, table, 0, 0, tolNote);
    out.kind = "csv_stat";
    out.alpha = alpha;
    return out;
}

Comparison compareCsvStage(const StageOutput& output, const std::filesystem::path& captureDir,
                           const Table& actual, const std::string& keyColumn,
                           const Table* conditioning, const std::string& conditioningNote) {
    Comparison failed;
    failed.stage = output.stage;
    failed.absTol = output.absTol;
    failed.relTol = output.relTol;
    if (output.kind != "csv" && output.kind != "csv_stat") {
        failed.message = "output kind is '" + output.kind + "', not csv or csv_stat";
        return failed;
    }
    Table expected;
    try {
        expected = readCsv(captureDir / output.file);
    } catch (const core::Error& e) {
        failed.message = std::string("cannot read the recorded output: ") + e.what();
        return failed;
    }
    if (output.kind == "csv_stat")
        return compareStatTables(output.stage, expected, actual, output.alpha, keyColumn);
    return compareTables(output.stage, expected, actual, output.absTol, output.relTol, keyColumn,
                         conditioning, conditioningNote);
}

std::string modelTokens(std::string_view text) {
    std::string out;
    bool inSection = false, pendingSpace = false;
    size_t i = 0;
    auto emit = [&](char c) {
        if (pendingSpace && !out.empty()) out += ' ';
        pendingSpace = false;
        out += c;
    };
    bool lineStart = true;
    while (i < text.size()) {
        const char c = text[i];
        if (lineStart) {
            // section markers switch between the header (where # starts a comment) and GLSL
            size_t j = i;
            while (j < text.size() && (text[j] == ' ' || text[j] == '\t'))
                ++j;
            const std::string_view rest = text.substr(j);
            if (rest.substr(0, 7) == "::begin") inSection = true;
            if (rest.substr(0, 5) == "::end") inSection = false;
            if (!inSection && !rest.empty() && rest[0] == '#') {
                const size_t nl = text.find('\n', j);
                i = nl == std::string_view::npos ? text.size() : nl;
                continue;
            }
            lineStart = false;
        }
        if (c == '\n') {
            lineStart = true;
            pendingSpace = true;
            ++i;
        } else if (c == ' ' || c == '\t' || c == '\r') {
            pendingSpace = true;
            ++i;
        } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {
            const size_t nl = text.find('\n', i);
            i = nl == std::string_view::npos ? text.size() : nl;
        } else if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {
            const size_t end = text.find("*/", i + 2);
            i = end == std::string_view::npos ? text.size() : end + 2;
            pendingSpace = true;
        } else {
            emit(c);
            ++i;
        }
    }
    return out;
}

std::vector<std::string> checkInputs(const Manifest& manifest,
                                     const std::filesystem::path& captureDir,
                                     const std::filesystem::path& projectRoot,
                                     std::vector<std::string>* notes) {
    std::vector<std::string> problems;
    // Appends a problem when `path` is missing, unreadable or its hash differs from `recorded`.
    auto check = [&](const std::string& shown, const std::filesystem::path& path,
                     const std::string& recorded, const std::string& missing,
                     const std::string& changed) {
        std::error_code ec;
        if (!std::filesystem::exists(path, ec)) {
            problems.push_back(shown + ": " + missing);
            return;
        }
        std::string now;
        try {
            now = hashFile(path);
        } catch (const core::Error& e) {
            problems.push_back(shown + ": unreadable (" + e.message() + ")");
            return;
        }
        if (now != recorded)
            problems.push_back(shown + ": " + changed + " (recorded " + recorded + ", now " + now +
                               ")");
    };
    for (const ModelFile& m : manifest.models) {
        std::string bad = relativePathProblem(m.path);
        if (!bad.empty()) {
            problems.push_back(m.path + ": " + bad);
            continue;
        }
        // A model from outside the project is replayed from its recorded text: nothing on
        // disk to check.
        if (m.path.rfind("external/", 0) == 0) {
            if (notes)
                notes->push_back(m.path +
                                 ": opened from outside the project when recorded; replayed "
                                 "from the text in the manifest");
            continue;
        }
        // Only comments or whitespace changed: the same program, a note (the recorded text is
        // in the manifest to compare with).
        std::error_code ec;
        if (!m.source.empty() && std::filesystem::exists(projectRoot / m.path, ec)) {
            try {
                if (hashFile(projectRoot / m.path) != m.hash &&
                    modelTokens(core::readFile(projectRoot / m.path)) == modelTokens(m.source)) {
                    if (notes)
                        notes->push_back(m.path +
                                         ": only comments or whitespace changed since "
                                         "recording (the model compiles to the same program)");
                    continue;
                }
            } catch (const core::Error&) {
                // unreadable: reported by check() below
            }
        }
        check(m.path, projectRoot / m.path, m.hash, "missing", "content hash changed");
    }
    for (const StageOutput& o : manifest.outputs) {
        std::string bad = relativePathProblem(o.file);
        if (!bad.empty()) {
            problems.push_back(o.file + ": " + bad);
            continue;
        }
        check(o.file, captureDir / o.file, o.hash,
              "output of stage " + o.stage + " missing from the capture",
              "content hash changed since recording (re-record, or replay with --update)");
    }
    return problems;
}

bool ReplayReport::pass() const {
    if (!inputProblems.empty() || stages.empty()) return false;
    for (const Comparison& c : stages)
        if (!c.pass) return false;
    return true;
}

std::string ReplayReport::text() const {
    std::string out;
    for (const std::string& n : inputNotes)
        out += "NOTE " + n + "\n";
    for (const std::string& p : inputProblems)
        out += "INPUT " + p + "\n";
    size_t failed = 0;
    for (const Comparison& c : stages) {
        out += formatComparison(c) + "\n";
        if (!c.pass) ++failed;
    }
    std::string summary = pass() ? "replay PASS: " : "replay FAIL: ";
    if (stages.empty())
        summary += "no stages compared";
    else if (failed == 0)
        summary += std::to_string(stages.size()) + (stages.size() == 1 ? " stage" : " stages");
    else
        summary += std::to_string(failed) + " of " + std::to_string(stages.size()) +
                   (stages.size() == 1 ? " stage" : " stages") + " failed";
    if (!inputProblems.empty())
        summary += ", " + std::to_string(inputProblems.size()) +
                   (inputProblems.size() == 1 ? " input problem" : " input problems");
    return out + summary + "\n";
}

} // namespace capture
