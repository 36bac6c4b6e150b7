// Menu bar: File (new model, open model, open an MCML reference, reload all, record capture,
// quit) and View (toggle panels).
#include "captures/capture_io.h"
#include "gui/file_dialog.h"
#include "gui/panels/panels.h"
#include "gui/panels/registry.h"
#include "gui/widgets.h"
#include "pipeline/new_model.h"

#include "capture/capture.h"
#include "core/core.h"

#include <GLFW/glfw3.h>
#include <algorithm>
#include <imgui.h>

namespace app {
namespace fs = std::filesystem;

void openModelFile(Workbench& wb, UiShared& ui, const std::filesystem::path& file) {
    std::filesystem::path p = file;
    if (p.is_relative() && !std::filesystem::exists(p)) p = wb.root() / p;
    try {
        wb.openModel(p);
        rememberRecent(ui.recent, std::filesystem::absolute(p).lexically_normal().string());
        ui.status = "opened " + p.filename().string();
    } catch (const core::Error& e) {
        wb.reportActionError(std::string("open model: ") + e.what());
    }
}

void openMcmlFile(Workbench& wb, UiShared& ui, const std::filesystem::path& file) {
    try {
        wb.openMcmlReference(file);
        ui.status = "MCML reference " + file.filename().string();
    } catch (const core::Error& e) {
        wb.reportActionError(std::string("open MCML reference: ") + e.what());
    }
}

void togglePanel(UiShared& ui, PanelId id) {
    if (ui.isOpen(id))
        ui.isOpen(id) = false;
    else
        ui.show(id);
}

namespace {

// File → New model: a name (typed as the dialog appears; Enter creates), the model it starts
// from, why a name is refused; the model is written to materials/ and opened at once.
void drawNewModelDialog(Workbench& wb, UiState& ui) {
    MenuState& m = ui.menu;
    if (m.newModelPopup) {
        ImGui::OpenPopup("New model");
        m.newModelPopup = false;
    }
    if (!ImGui::BeginPopupModal("New model", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    ImGui::TextUnformatted("Name (materials/NAME.bssrdf):");
    if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
    const bool entered =
        ImGui::InputText("##newmodel", m.newModelName, sizeof m.newModelName,
                         ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    // the model it starts from: any loaded one, by default the template
    const fs::path templ = wb.root() / kNewModelTemplate;
    fs::path from = templ;
    for (const auto& e : wb.library().entries())
        if (e.displayPath == m.newModelFrom) from = e.file;
    const std::string shownFrom =
        from == templ ? std::string(kNewModelTemplate) : core::relativeTo(from, wb.root());
    setItemWidth(320, "starts from");
    if (ImGui::BeginCombo("starts from", shownFrom.c_str())) {
        for (const auto& e : wb.library().entries())
            if (ImGui::Selectable(e.displayPath.c_str(), e.file == from))
                m.newModelFrom = e.displayPath;
        ImGui::EndCombo();
    }
    const std::string problem = newModelProblem(wb.root(), m.newModelName);
    if (!problem.empty()) ImGui::TextColored(ImVec4(1, 0.45f, 0.45f, 1), "%s", problem.c_str());
    ImGui::TextDisabled("edit it in any editor: each save is loaded (an error goes to Errors)");
    ImGui::BeginDisabled(!problem.empty());
    const bool create = ImGui::Button("Create");
    ImGui::EndDisabled();
    if ((create || entered) && problem.empty()) {
        try {
            const fs::path file = createModel(wb.root(), m.newModelName, from);
            wb.openModel(file);
            const std::string abs = fs::absolute(file).lexically_normal().string();
            ui.shared.status = "created " + core::relativeTo(file, wb.root());
            core::logInfo("new model: wrote " + abs + " from " + from.string());
            ui.shared.show(PanelId::Models);
        } catch (const core::Error& e) {
            wb.reportActionError(std::string("new model: ") + e.what());
        }
        ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
    closeOnEscape();
    ImGui::EndPopup();
}

} // namespace

void drawMenuBar(Workbench& wb, UiState& ui) {
    pollRecording(wb, ui.captures, ui.shared);
    pollCaptureWindows(wb, ui.captures);
    if (ImGui::BeginMainMenuBar()) {
        if (ImGui::BeginMenu("File")) {
            if (ImGui::MenuItem("New model...", "Ctrl+N")) ui.menu.newModelPopup = true;
            if (ImGui::MenuItem("Open model...", "Ctrl+O")) ui.menu.openModelPopup = true;
            if (ImGui::BeginMenu("Open recent", !ui.shared.recent.empty())) {
                std::string pick;
                for (const std::string& r : ui.shared.recent)
                    if (ImGui::MenuItem(r.c_str())) pick = r;
                ImGui::EndMenu();
                if (!pick.empty()) openModelFile(wb, ui.shared, pick);
            }
            if (ImGui::MenuItem("Open MCML reference...")) ui.menu.mcmlPopup = true;
            if (ImGui::MenuItem("Clear MCML reference", nullptr, false,
                                wb.mcmlReference().has_value()))
                wb.clearMcmlReference();
            if (ImGui::MenuItem("Reload all", "F5")) wb.reloadAll();
            if (ImGui::MenuItem("Record capture...", "Ctrl+R")) ui.menu.recordPopup = true;
            ImGui::Separator();
            if (ImGui::MenuItem("Quit", "Ctrl+Q")) ui.shared.quit = true;
            ImGui::EndMenu();
        }
        if (ImGui::BeginMenu("View")) {
            int group = 0;
            for (const PanelEntry& p : panelRegistry()) {
                if (p.menuGroup != group) ImGui::Separator();
                group = p.menuGroup;
                if (ImGui::MenuItem(p.title, nullptr, ui.shared.isOpen(p.id)))
                    togglePanel(ui.shared, p.id);
            }
            ImGui::Separator();
            if (ImGui::BeginMenu("Float")) {
                for (const PanelEntry& p : panelRegistry()) {
                    bool& floating = ui.shared.workspace.floating[static_cast<size_t>(p.id)];
                    if (ImGui::MenuItem(p.title, nullptr, &floating)) ui.shared.show(p.id);
                }
                ImGui::EndMenu();
            }
            if (ImGui::MenuItem("Reset layout")) {
                ui.shared.workspace = WorkspaceState{};
                for (const PanelEntry& p : panelRegistry())
                    ui.shared.isOpen(p.id) = p.defaultOpen;
            }
            ImGui::EndMenu();
        }
        // At the bar's right end: the problem count, hot reload and the last status, ending at
        // the window's edge; a status longer than the room the menus leave is cut, and shown
        // whole on hover.
        const size_t n = wb.errors().size();
        const std::string problems =
            n > 0 ? std::to_string(n) + (n == 1 ? " problem" : " problems") : "no problems";
        const std::string reload = wb.watching() ? "| hot reload on" : "| hot reload off";
        const std::string status = ui.shared.status.empty() ? "" : "| " + ui.shared.status;
        const float gap = ImGui::GetStyle().ItemSpacing.x;
        ImGui::SameLine();
        const ImVec2 here = ImGui::GetCursorScreenPos(); // after the menus
        const float right =
            ImGui::GetWindowPos().x + ImGui::GetWindowWidth() - ImGui::GetStyle().WindowPadding.x;
        const float fixed =
            ImGui::CalcTextSize(problems.c_str()).x + gap + ImGui::CalcTextSize(reload.c_str()).x;
        const std::string shown =
            status.empty() ? status
                           : cutToWidth(status, std::max(0.0f, right - here.x - fixed - gap));
        const float width =
            fixed + (shown.empty() ? 0.0f : gap + ImGui::CalcTextSize(shown.c_str()).x);
        ImGui::SetCursorScreenPos(ImVec2(std::max(here.x, right - width), here.y));
        if (n > 0)
            ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", problems.c_str());
        else
            ImGui::TextDisabled("%s", problems.c_str());
        ImGui::SameLine();
        ImGui::TextDisabled("%s", reload.c_str());
        if (!shown.empty()) {
            ImGui::SameLine();
            ImGui::TextDisabled("%s", shown.c_str());
            if (shown != status && ImGui::IsItemHovered())
                ImGui::SetTooltip("%s", ui.shared.status.c_str());
        }
        ImGui::EndMainMenuBar();
    }
    // ImGui 1.86 indexes io.KeysDown by the platform key code (GLFW_KEY_* here).
    ImGuiIO& io = ImGui::GetIO();
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_N)) ui.menu.newModelPopup = true;
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_O)) ui.menu.openModelPopup = true;
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_R)) ui.menu.recordPopup = true;
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Q)) ui.shared.quit = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_F5)) wb.reloadAll();

    if (ui.menu.openModelPopup) {
        ImGui::OpenPopup("Open model");
        ui.menu.openModelPopup = false;
    }
    if (ImGui::BeginPopupModal("Open model", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        FileDialogState& d = ui.menu.openDialog;
        if (d.dir.empty()) d.dir = wb.root() / "materials";
        if (auto chosen = drawFileDialog(d, ".bssrdf")) {
            openModelFile(wb, ui.shared, *chosen);
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        closeOnEscape();
        ImGui::EndPopup();
    }
    if (ui.menu.mcmlPopup) {
        ImGui::OpenPopup("Open MCML reference");
        ui.menu.mcmlPopup = false;
    }
    if (ImGui::BeginPopupModal("Open MCML reference", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextDisabled("MCML 1.x output (.mco) of one semi-infinite layer: its R_d(r) is "
                            "drawn in the pencil plot");
        FileDialogState& d = ui.menu.mcmlDialog;
        if (d.dir.empty()) d.dir = wb.root(); // the project's, as Open model's (not the cwd)
        if (auto chosen = drawFileDialog(d, ".mco")) {
            openMcmlFile(wb, ui.shared, *chosen);
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        closeOnEscape();
        ImGui::EndPopup();
    }
    drawNewModelDialog(wb, ui);
    if (ui.menu.recordPopup) {
        ImGui::OpenPopup("Record capture");
        ui.menu.recordPopup = false;
    }
    if (ImGui::BeginPopupModal("Record capture", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("Capture name (folder under captures/):");
        // the name takes the keyboard (typed over) as the dialog appears; Enter records
        if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
        const bool entered = ImGui::InputText(
            "##name", ui.menu.nameBuffer, sizeof ui.menu.nameBuffer,
            ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
        const std::string problem = capture::nameProblem(ui.menu.nameBuffer);
        std::error_code ec;
        if (!problem.empty())
            ImGui::TextColored(ImVec4(1, 0.45f, 0.45f, 1), "%s", problem.c_str());
        else if (fs::exists(wb.root() / "captures" / ui.menu.nameBuffer, ec))
            ImGui::TextDisabled("(replaces the capture of that name)");
        const bool busy = ui.captures.recorder && !ui.captures.recorder->done();
        if (busy)
            ImGui::TextDisabled("(one recording at a time: %s is under way)",
                                ui.captures.recording.c_str());
        ImGui::BeginDisabled(busy || !problem.empty());
        const bool record = ImGui::Button("Record");
        ImGui::EndDisabled();
        if ((record || entered) && !busy && problem.empty()) {
            try {
                startRecording(wb, ui.captures, ui.menu.nameBuffer);
                ui.shared.status = "recording " + std::string(ui.menu.nameBuffer);
                ui.shared.show(PanelId::Captures);
            } catch (const core::Error& e) {
                wb.reportActionError(std::string("record capture: ") + e.what());
            }
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        closeOnEscape();
        ImGui::EndPopup();
    }
}

} // namespace app
