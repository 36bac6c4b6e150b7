// A panel's export controls (export_buttons.h).
#include "gui/export_buttons.h"

#include "gui/widgets.h"

#include <imgui.h>

#include <cctype>
#include <cstdio>

namespace app {
namespace fs = std::filesystem;

std::optional<fs::path> drawExportButtons(const char* popupId, char* name, size_t nameSize,
                                          const std::vector<std::string>& extensions,
                                          ExportState& st,
                                          std::vector<std::array<float, 4>>* buttons) {
    ImGui::PushID(popupId);
    setItemWidth(160, "##exportname");
    ImGui::InputText("##exportname", name, nameSize);
    if (buttons) buttons->clear();
    for (const std::string& ext : extensions) {
        std::string upper = ext.substr(1);
        for (char& c : upper)
            c = char(std::toupper(static_cast<unsigned char>(c)));
        const std::string label = "Export " + upper;
        sameLineIfFits(buttonWidth(label.c_str()));
        const bool pressed = ImGui::Button(label.c_str());
        const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
        if (buttons) buttons->push_back({lo.x, lo.y, hi.x, hi.y});
        if (!pressed) continue;
        st.extension = ext;
        const fs::path dir = st.dialog.dir.empty() ? fs::current_path() : st.dialog.dir;
        setDialogFile(st.dialog, dir / (std::string(name) + ext));
        ImGui::OpenPopup(popupId);
    }
    std::optional<fs::path> chosen;
    if (ImGui::BeginPopupModal(popupId, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        if (auto file = drawFileDialog(st.dialog, st.extension, "Save")) {
            fs::path path = *file;
            if (path.extension().empty()) path += st.extension;
            chosen = fs::absolute(path).lexically_normal();
            std::snprintf(name, nameSize, "%s", chosen->stem().c_str());
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
        closeOnEscape();
        ImGui::EndPopup();
    }
    ImGui::PopID();
    return chosen;
}

} // namespace app
