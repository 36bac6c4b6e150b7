#include "gui/preset_combo.h"

#include "pipeline/workbench.h"

#include <imgui.h>

namespace app {

bool presetCombo(const char* label, Workbench& wb, MaterialSettings& s) {
    bool chosen = false;
    const material::Preset* current = material::findPreset(wb.presets(), s.preset);
    if (ImGui::BeginCombo(label, s.preset.empty() ? "(custom)" : s.preset.c_str())) {
        std::string table;
        for (const auto& p : wb.presets()) {
            if (p.table != table) { // a heading per publication
                table = p.table;
                ImGui::Separator();
                ImGui::TextDisabled("%s", p.tableName.c_str());
            }
            ImGui::BeginDisabled(!p.unusable.empty());
            const std::string item = p.disputed ? p.name + " (disputed value)" : p.name;
            if (ImGui::Selectable((item + "##" + p.name).c_str(), p.name == s.preset)) {
                wb.applyPreset(s, p.name);
                chosen = true;
            }
            ImGui::EndDisabled();
            if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
                ImGui::SetTooltip("%s%s%s%s%s", p.source.c_str(), p.note.empty() ? "" : "\n\n",
                                  p.note.c_str(),
                                  p.unusable.empty() ? "" : "\n\nNot usable: ", p.unusable.c_str());
        }
        ImGui::EndCombo();
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("%s", current ? (current->tableName + ": " + current->source).c_str()
                                        : "measured media from materials/presets.json, grouped "
                                          "by publication (sigma in 1/mm)");
    return chosen;
}

} // namespace app
