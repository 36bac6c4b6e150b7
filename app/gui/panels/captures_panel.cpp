// Captures panel: the captures under captures/, replayed in a child process (ReplayProcess)
// with progress and cancel; the report line by line (PASS / FAIL / NOTE / INPUT coloured) and,
// for every failing image stage, its recorded | replayed | difference picture (written by the
// replay beside the capture, captures/README.md). A double click on a capture replays it; Open
// in a window starts `gui --capture NAME` (captures/open_capture.h) as a child: the recorded
// state in a second window, this one untouched.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "capture/capture.h"
#include "captures/capture_io.h"
#include "captures/open_capture.h"
#include "core/core.h"

#include <stb_image.h>

#include <imgui.h>

#include <sstream>

namespace app {
namespace fs = std::filesystem;

namespace {

std::vector<std::string> listCaptures(const fs::path& dir) {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string name = e.path().filename().string();
        // hidden folders: captures being recorded (renamed into place when complete)
        if (!name.empty() && name[0] != '.' && e.is_directory(ec) &&
            fs::exists(e.path() / capture::kManifestFileName, ec))
            out.push_back(name);
    }
    std::sort(out.begin(), out.end());
    return out;
}

// The difference pictures a finished replay names ("...: PATH.diff.png; replayed image: ...").
std::vector<std::string> differencePictures(const std::string& report) {
    std::vector<std::string> out;
    std::istringstream in(report);
    const std::string tag = "tolerance): ";
    for (std::string line; std::getline(in, line);) {
        const size_t at = line.find(tag);
        if (at == std::string::npos) continue;
        const size_t end = line.find(".diff.png", at);
        if (end != std::string::npos)
            out.push_back(line.substr(at + tag.size(), end + 9 - at - tag.size()));
    }
    return out;
}

void loadPicture(const std::string& file, CapturesPanelState::Picture& p) {
    int w = 0, h = 0, n = 0;
    unsigned char* px = stbi_load(file.c_str(), &w, &h, &n, 4);
    p.file = file;
    if (!px) {
        p.problem = std::string("cannot read ") + file + ": " + stbi_failure_reason();
        return;
    }
    gl::uploadRGBA8(p.tex, w, h, px);
    stbi_image_free(px);
    p.width = w;
    p.height = h;
}

// What a child that failed said: its last "error" line, else its whole output.
std::string errorLine(const std::string& output) {
    std::string last;
    std::istringstream in(output);
    for (std::string line; std::getline(in, line);)
        if (line.rfind("error", 0) == 0) last = line;
    return last.empty() ? output : last;
}

ImVec4 lineColor(const std::string& line) {
    if (line.rfind("PASS", 0) == 0 || line.rfind("replay PASS", 0) == 0)
        return ImVec4(0.5f, 0.9f, 0.5f, 1);
    if (line.rfind("FAIL", 0) == 0 || line.rfind("replay FAIL", 0) == 0 ||
        line.rfind("error", 0) == 0 || line.rfind("ERROR", 0) == 0)
        return ImVec4(1, 0.45f, 0.45f, 1);
    if (line.rfind("NOTE", 0) == 0 || line.rfind("INPUT", 0) == 0) return ImVec4(1, 0.8f, 0.4f, 1);
    return ImGui::GetStyleColorVec4(ImGuiCol_Text);
}

} // namespace

void startReplay(Workbench& wb, CapturesPanelState& ps, const std::string& name) {
    ps.pictures.clear();
    ps.report.clear();
    ps.replaying = name;
    ps.started = core::secondsSinceStart();
    ps.proc = std::make_unique<ReplayProcess>(ps.exe.empty() ? selfExecutable() : ps.exe, wb.root(),
                                              wb.root() / "captures" / name);
}

std::string lastStage(const std::string& output, const std::string& what) {
    const std::string tag = what + ": stage ";
    const size_t at = output.rfind(tag);
    if (at == std::string::npos) return "";
    const size_t end = output.find('\n', at);
    return output.substr(at + tag.size(),
                         end == std::string::npos ? std::string::npos : end - at - tag.size());
}

void startRecording(Workbench& wb, CapturesPanelState& ps, const std::string& name) {
    if (ps.recorder && !ps.recorder->done())
        throw core::Error(name, 0, "a recording is under way (" + ps.recording + ")");
    const fs::path request = writeRecordRequest(wb, name);
    ps.recordRequest = request;
    ps.recording = name;
    ps.recordOutcome.clear();
    ps.recordStarted = core::secondsSinceStart();
    ps.recorder = std::make_unique<ChildProcess>(
        std::vector<std::string>{(ps.exe.empty() ? selfExecutable() : ps.exe).string(), "--root",
                                 wb.root().string(), "record", "--name", name, "--force",
                                 "--from-request", request.string()},
        "record " + name);
}

void pollRecording(Workbench& wb, CapturesPanelState& ps, UiShared& ui) {
    if (!ps.recorder || !ps.recorder->poll() || !ps.recordOutcome.empty()) return;
    // ended: its request goes, and so does a half-written folder a killed child left
    std::error_code ec;
    fs::remove_all(ps.recordRequest.parent_path(), ec);
    const fs::path captures = wb.root() / "captures";
    for (const auto& e : fs::directory_iterator(captures, ec))
        if (e.path().filename().string().rfind("." + ps.recording + ".recording-", 0) == 0)
            fs::remove_all(e.path(), ec);
    const int code = ps.recorder->exitCode();
    if (code == 0) {
        ps.recordOutcome = "recorded captures/" + ps.recording;
        ui.status = ps.recordOutcome;
        core::logInfo("record capture: " + ps.recordOutcome);
    } else if (ps.recordOutcome.empty() && code == 128 + 9) {
        ps.recordOutcome = "recording of " + ps.recording + " cancelled";
        ui.status = ps.recordOutcome;
    } else {
        ps.recordOutcome = "recording of " + ps.recording + " failed";
        ui.status = ps.recordOutcome;
        wb.reportActionError("record capture " + ps.recording + ": " +
                             errorLine(ps.recorder->output()));
    }
    ps.listedAt = -1e9; // list the captures again
}

void startCaptureWindow(Workbench& wb, CapturesPanelState& ps, const std::string& name) {
    auto proc = std::make_unique<ChildProcess>(
        std::vector<std::string>{(ps.exe.empty() ? selfExecutable() : ps.exe).string(), "--root",
                                 wb.root().string(), "gui", "--capture", name},
        "window on capture " + name);
    core::logInfo("opened captures/" + name + " in a window of its own (pid " +
                  std::to_string(proc->pid()) + ")");
    ps.windows.push_back({name, std::move(proc)});
}

void pollCaptureWindows(Workbench& wb, CapturesPanelState& ps) {
    for (auto it = ps.windows.begin(); it != ps.windows.end();) {
        if (!it->proc->poll()) {
            ++it;
            continue;
        }
        if (it->proc->exitCode() == 0) {
            core::logInfo("the window on capture " + it->name + " closed");
        } else {
            wb.reportActionError("window on capture " + it->name + ": " +
                                 errorLine(it->proc->output()) + " (exit status " +
                                 std::to_string(it->proc->exitCode()) + ")");
        }
        it = ps.windows.erase(it);
    }
}

void showCapturedState(Workbench& wb, UiState& state, const std::string& name, int traceX,
                       int traceY) {
    UiShared& ui = state.shared;
    ui.status = "capture " + name;
    const render::Settings& r = wb.scene().settings().render;
    if (wb.scene().settings().enabled) {
        ui.show(PanelId::Render);
        if (traceX >= 0 && traceY >= 0 && traceX < r.width && traceY < r.height)
            ui.inspect.pendingPick = std::pair{(float(traceX) + 0.5f) / float(r.width),
                                               (float(traceY) + 0.5f) / float(r.height)};
    } else if (wb.litSphereSettings().enabled) {
        ui.show(PanelId::LitSpheres);
        state.litSpheres.view = SphereView::SideBySide; // both images it recorded
    } else if (wb.sliceSettings().enabled) {
        ui.show(PanelId::Slice);
    } else {
        ui.show(PanelId::Pencil);
    }
}

void drawCapturesPanel(Workbench& wb, CapturesPanelState& ps, UiShared&) {
    // listed when the panel first shows and again every kCapturesListSeconds while it shows, so
    // a capture just recorded (File → Record capture, or from a shell) appears without Refresh
    const double now = core::secondsSinceStart();
    if (ImGui::SmallButton("Refresh") || now - ps.listedAt > kCapturesListSeconds) {
        ps.names = listCaptures(wb.root() / "captures");
        ps.listedAt = now;
    }
    ImGui::BeginChild("list", ImVec2(std::min(240.0f, ImGui::GetContentRegionAvail().x * 0.35f), 0),
                      true);
    if (ps.names.empty()) hintText("no captures under captures/ (File → Record capture)");
    bool replayNow = false; // a double click replays, as Replay does
    ps.nameRects.clear();
    for (const std::string& n : ps.names) {
        if (ImGui::Selectable(n.c_str(), ps.selected == n, ImGuiSelectableFlags_AllowDoubleClick)) {
            ps.selected = n;
            replayNow = ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left);
        }
        ps.nameRects.push_back(lastItem());
    }
    ImGui::EndChild();
    ImGui::SameLine();
    ImGui::BeginChild("replay", ImVec2(0, 0), false, ImGuiWindowFlags_HorizontalScrollbar);
    if (ps.recorder && !ps.recorder->done()) {
        const std::string stage = lastStage(ps.recorder->output(), "record");
        ImGui::Text("recording %s ... %s%.1f s", ps.recording.c_str(),
                    stage.empty() ? "" : ("stage " + stage + ", ").c_str(),
                    core::secondsSinceStart() - ps.recordStarted);
        ImGui::SameLine();
        if (ImGui::SmallButton("Cancel recording")) ps.recorder->cancel();
    } else if (!ps.recordOutcome.empty()) {
        hintText("%s", ps.recordOutcome.c_str());
    }
    const bool running = ps.proc && !ps.proc->done();
    if (running) {
        const std::string stage = lastStage(ps.proc->output(), "replay");
        ImGui::Text("replaying %s ... %s%.1f s", ps.replaying.c_str(),
                    stage.empty() ? "" : ("stage " + stage + ", ").c_str(),
                    core::secondsSinceStart() - ps.started);
        ImGui::SameLine();
        if (ImGui::SmallButton("Cancel")) ps.proc->cancel();
    } else if (!ps.selected.empty()) {
        if (ImGui::Button(("Replay " + ps.selected).c_str()) || replayNow) {
            try {
                startReplay(wb, ps, ps.selected);
            } catch (const core::Error& e) {
                wb.reportActionError(std::string("replay: ") + e.what());
            }
        }
    } else {
        hintText("select a capture to replay it (or double click it): every stage recomputed "
                 "and compared; or open its state in a window of its own");
    }
    ps.openWindow = {};
    if (!ps.selected.empty()) {
        sameLineIfFits(buttonWidth("Open in a window"));
        if (ImGui::Button("Open in a window")) {
            try {
                startCaptureWindow(wb, ps, ps.selected);
            } catch (const core::Error& e) {
                wb.reportActionError(std::string("open capture: ") + e.what());
            }
        }
        ps.openWindow = lastItem();
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("the state %s recorded (models, parameters, settings, traced pixel) "
                              "in a second workbench window, to look at and change; this window "
                              "stays as it is",
                              ps.selected.c_str());
    }
    if (!ps.selected.empty() &&
        (ps.described != ps.selected || now - ps.describedAt > kCapturesListSeconds)) {
        ps.described = ps.selected;
        ps.describedAt = now;
        try {
            ps.about = describeCapture(wb.root(), wb.root() / "captures" / ps.selected);
        } catch (const core::Error& e) {
            ps.about = {std::string("cannot read it: ") + e.what()};
        }
    }
    if (!ps.selected.empty()) {
        bool edited = false;
        for (const std::string& line : ps.about) {
            // a model that is not as recorded: the replay will say so too
            const bool differs = line.rfind("model ", 0) == 0 &&
                                 line.find(": as recorded") == std::string::npos &&
                                 line.find("only comments") == std::string::npos &&
                                 line.find("opened from outside") == std::string::npos;
            if (differs || line.rfind("cannot read", 0) == 0)
                colouredText(ImVec4(1, 0.8f, 0.4f, 1), "%s", line.c_str());
            else
                hintText("%s", line.c_str());
            edited = edited || differs;
        }
        if (edited)
            hintText("Open in a window shows the recorded text of a model beside today's file");
        ImGui::Separator();
    }
    if (ps.proc) {
        const bool finished = ps.proc->poll();
        ps.report = ps.proc->output();
        if (finished && ps.pictures.empty())
            for (const std::string& file : differencePictures(ps.report)) {
                ps.pictures.emplace_back();
                loadPicture(file, ps.pictures.back());
            }
        if (finished) ImGui::TextDisabled("exit status %d", ps.proc->exitCode());
    }
    std::istringstream in(ps.report);
    for (std::string line; std::getline(in, line);) {
        const size_t cr = line.rfind('\r'); // progress lines: the last state only
        if (cr != std::string::npos) line = line.substr(cr + 1);
        if (line.rfind("replay: stage ", 0) == 0) continue; // shown in the status line above
        ImGui::PushStyleColor(ImGuiCol_Text, lineColor(line));
        ImGui::TextUnformatted(line.c_str());
        ImGui::PopStyleColor();
    }
    for (const auto& p : ps.pictures) {
        ImGui::Separator();
        ImGui::TextUnformatted(fs::path(p.file).filename().c_str());
        if (!p.problem.empty()) {
            colouredText(ImVec4(1, 0.45f, 0.45f, 1), "%s", p.problem.c_str());
            continue;
        }
        hintText("recorded | replayed | difference (colour ramp over 0 to 2x the tolerance)");
        const float w = std::max(120.0f, visibleWidth());
        ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(p.tex.id())),
                     ImVec2(w, w * float(p.height) / float(std::max(1, p.width))));
    }
    ImGui::EndChild();
}

} // namespace app
