// Menu bar: File (open model, reload all, record capture, quit) and View (toggle panels).
#include "panels.h"

#include "core/core.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

namespace app {

void drawMenuBar(Workbench& wb, UiState& ui) {
    if (ImGui::BeginMainMenuBar()) {
        if (ImGui::BeginMenu("File")) {
            if (ImGui::MenuItem("Open model...", "Ctrl+O")) ui.openModelPopup = true;
            if (ImGui::MenuItem("Reload all", "F5")) wb.reloadAll();
            if (ImGui::MenuItem("Record capture...", "Ctrl+R")) ui.recordPopup = true;
            ImGui::Separator();
            if (ImGui::MenuItem("Quit", "Ctrl+Q")) ui.quit = true;
            ImGui::EndMenu();
        }
        if (ImGui::BeginMenu("View")) {
            ImGui::MenuItem("Models", nullptr, &ui.showModels);
            ImGui::MenuItem("Parameters", nullptr, &ui.showParameters);
            ImGui::MenuItem("Pencil plot", nullptr, &ui.showPencil);
            ImGui::MenuItem("Errors / Log", nullptr, &ui.showErrors);
            ImGui::MenuItem("Timings", nullptr, &ui.showTimings);
            ImGui::MenuItem("Lit spheres", nullptr, &ui.showLitSpheres);
            ImGui::Separator();
            ImGui::MenuItem("Point cloud", nullptr, &ui.showPointCloud);
            ImGui::MenuItem("Octree", nullptr, &ui.showOctree);
            ImGui::MenuItem("Irradiance", nullptr, &ui.showIrradiance);
            ImGui::MenuItem("Render", nullptr, &ui.showRender);
            ImGui::MenuItem("Traversal debugger", nullptr, &ui.showTraversal);
            ImGui::EndMenu();
        }
        const size_t n = wb.errors().size();
        ImGui::SameLine(ImGui::GetWindowWidth() - 360);
        if (n > 0)
            ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%zu problem%s", n, n == 1 ? "" : "s");
        else
            ImGui::TextDisabled("no problems");
        ImGui::SameLine();
        ImGui::TextDisabled("| %s", wb.watching() ? "hot reload on" : "hot reload off");
        if (!ui.status.empty()) {
            ImGui::SameLine();
            ImGui::TextDisabled("| %s", ui.status.c_str());
        }
        ImGui::EndMainMenuBar();
    }
    // ImGui 1.86 indexes io.KeysDown by the platform key code (GLFW_KEY_* here).
    ImGuiIO& io = ImGui::GetIO();
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_O)) ui.openModelPopup = true;
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_R)) ui.recordPopup = true;
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Q)) ui.quit = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_F5)) wb.reloadAll();

    if (ui.openModelPopup) {
        ImGui::OpenPopup("Open model");
        ui.openModelPopup = false;
    }
    if (ImGui::BeginPopupModal("Open model", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("Path of a .bssrdf file (absolute or relative to the project):");
        ImGui::InputText("##path", ui.pathBuffer, sizeof ui.pathBuffer);
        if (ImGui::Button("Open")) {
            std::filesystem::path p = ui.pathBuffer;
            if (p.is_relative()) p = wb.root() / p;
            try {
                wb.openModel(p);
                ui.status = "opened " + p.filename().string();
            } catch (const core::Error& e) {
                wb.reportActionError(std::string("open model: ") + e.what());
            }
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    if (ui.recordPopup) {
        ImGui::OpenPopup("Record capture");
        ui.recordPopup = false;
    }
    if (ImGui::BeginPopupModal("Record capture", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::TextUnformatted("Capture name (folder under captures/):");
        ImGui::InputText("##name", ui.nameBuffer, sizeof ui.nameBuffer);
        if (ImGui::Button("Record")) {
            try {
                ui.status = "recorded " + recordCapture(wb, ui.nameBuffer);
            } catch (const core::Error& e) {
                wb.reportActionError(std::string("record capture: ") + e.what());
            }
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
}

} // namespace app
