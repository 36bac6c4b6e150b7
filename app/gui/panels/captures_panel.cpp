// Captures panel: the captures under captures/, replayed in a child process (ReplayProcess)
// with progress and cancel; the report line by line (PASS / FAIL / NOTE / INPUT coloured) and,
// for every failing image stage, its recorded | replayed | difference picture (written by the
// replay beside the capture, captures/README.md).
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "capture/capture.h"
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
    for (const std::string& n : ps.names)
        if (ImGui::Selectable(n.c_str(), ps.selected == n)) ps.selected = n;
    ImGui::EndChild();
    ImGui::SameLine();
    ImGui::BeginChild("replay", ImVec2(0, 0), false, ImGuiWindowFlags_HorizontalScrollbar);
    const bool running = ps.proc && !ps.proc->done();
    if (running) {
        ImGui::Text("replaying %s ... %.1f s", ps.replaying.c_str(),
                    core::secondsSinceStart() - ps.started);
        ImGui::SameLine();
        if (ImGui::SmallButton("Cancel")) ps.proc->cancel();
    } else if (!ps.selected.empty()) {
        if (ImGui::Button(("Replay " + ps.selected).c_str())) {
            try {
                startReplay(wb, ps, ps.selected);
            } catch (const core::Error& e) {
                wb.reportActionError(std::string("replay: ") + e.what());
            }
        }
    } else {
        hintText("select a capture to replay it: every stage recomputed and compared");
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
        ImGui::PushStyleColor(ImGuiCol_Text, lineColor(line));
        ImGui::TextUnformatted(line.c_str());
        ImGui::PopStyleColor();
    }
    for (const auto& p : ps.pictures) {
        ImGui::Separator();
        ImGui::TextUnformatted(fs::path(p.file).filename().c_str());
        if (!p.problem.empty()) {
            ImGui::TextColored(ImVec4(1, 0.45f, 0.45f, 1), "%s", p.problem.c_str());
            continue;
        }
        hintText("recorded | replayed | difference (colour ramp over 0 to 2x the tolerance)");
        const float w = std::max(120.0f, ImGui::GetContentRegionAvail().x);
        ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(p.tex.id())),
                     ImVec2(w, w * float(p.height) / float(std::max(1, p.width))));
    }
    ImGui::EndChild();
}

} // namespace app
