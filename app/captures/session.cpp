// The session kept between runs of the window (session.h).
#include "captures/session.h"

#include "capture/capture.h"
#include "captures/capture_io.h"
#include "captures/manifest.h"
#include "captures/settings_json.h"
#include "core/core.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kRequestFile = "request.json";
constexpr const char* kSessionFile = "session.json";
constexpr int kSessionFormat = 1;

std::string rootKey(const fs::path& root) {
    std::error_code ec;
    fs::path canonical = fs::weakly_canonical(fs::absolute(root), ec);
    return (ec ? fs::absolute(root).lexically_normal() : canonical).string();
}

// Builds the workbench; the session's problems become Errors entries.
std::unique_ptr<Workbench> restoreFrom(const fs::path& dir, const fs::path& root, bool watch,
                                       const json& session) {
    const std::string where = (dir / kRequestFile).string();
    std::vector<std::string> problems;
    capture::Manifest m;
    bool readable = true;
    try {
        m = capture::readInputs(dir / kRequestFile);
    } catch (const core::Error& e) {
        problems.push_back(std::string(e.what()) +
                           " (the parameters and settings are the defaults)");
        readable = false;
    }
    auto wb = std::make_unique<Workbench>(root, watch);
    const json external = session.value("external", json::object());
    for (auto it = external.begin(); it != external.end(); ++it) {
        if (!it->is_string()) continue;
        const fs::path file = it->get<std::string>();
        std::error_code ec;
        if (!fs::is_regular_file(file, ec)) {
            problems.push_back(file.string() +
                               ": no longer there (it was open when the window last closed)");
            continue;
        }
        try {
            wb->openModel(file);
        } catch (const core::Error& e) {
            problems.push_back(e.what());
        }
    }
    if (readable) {
        try {
            applyParams(*wb, m.params, where);
            int traceX = -1, traceY = -1;
            // a session is this machine's own: the point-cloud cache stays on (a capture's
            // replay turns it off, workbenchFromInputs)
            applySettingsJson(*wb, m.settings, where, traceX, traceY);
        } catch (const core::Error& e) {
            // part of it may be applied: start again from the defaults, with the models
            problems.push_back(std::string(e.what()) +
                               " (the parameters and settings are the defaults)");
            auto fresh = std::make_unique<Workbench>(root, watch);
            for (auto& entry : wb->library().entries()) {
                if (!fs::path(entry.displayPath).is_absolute()) continue;
                try {
                    fresh->openModel(entry.file);
                } catch (const core::Error& again) { // gone in between
                    problems.push_back(again.what());
                }
            }
            wb = std::move(fresh);
        }
    }
    for (const std::string& p : problems)
        wb->reportActionError("session: " + p);
    return wb;
}

} // namespace

fs::path sessionDir(const fs::path& configDir, const fs::path& root) {
    const std::string hash = core::hashHex(rootKey(root));
    return configDir / "sessions" / hash.substr(hash.find(':') + 1);
}

void saveSession(Workbench& wb, const fs::path& dir) {
    const capture::Manifest m = captureInputs(wb, "session");
    json external = json::object();
    for (const auto& e : wb.library().entries())
        if (fs::path(e.displayPath).is_absolute())
            external[capturePathOf(e)] = fs::absolute(e.file).lexically_normal().string();
    const json session = {
        {"format", kSessionFormat}, {"root", rootKey(wb.root())}, {"external", external}};
    // written beside `dir` and renamed over it: a session is whole or absent
    const fs::path tmp = dir.parent_path() /
                         ("." + dir.filename().string() + ".saving-" + std::to_string(::getpid()));
    std::error_code ec;
    fs::remove_all(tmp, ec);
    fs::create_directories(tmp, ec);
    if (ec) throw core::Error(dir.string(), 0, "cannot write the session there: " + ec.message());
    try {
        capture::writeInputs(tmp / kRequestFile, m);
        core::writeFile(tmp / kSessionFile, session.dump(2) + "\n");
        fs::remove_all(dir, ec);
        fs::rename(tmp, dir);
    } catch (...) {
        fs::remove_all(tmp, ec);
        throw;
    }
}

std::unique_ptr<Workbench> restoreSession(const fs::path& dir, const fs::path& root, bool watch) {
    std::error_code ec;
    if (!fs::exists(dir / kSessionFile, ec)) return nullptr;
    json session;
    std::string problem;
    try {
        session = json::parse(core::readFile(dir / kSessionFile));
        if (!session.is_object() || !session.value("root", json()).is_string() ||
            session.value("format", 0) != kSessionFormat)
            problem = "not a session of this program's version";
    } catch (const std::exception& e) {
        problem = e.what();
    }
    if (!problem.empty()) {
        auto wb = std::make_unique<Workbench>(root, watch);
        wb->reportActionError("session: " + (dir / kSessionFile).string() + ": " + problem +
                              " (started with the defaults)");
        return wb;
    }
    if (session["root"].get<std::string>() != rootKey(root)) return nullptr;
    return restoreFrom(dir, root, watch, session);
}

} // namespace app
