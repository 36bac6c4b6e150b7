// Models panel: every loaded .bssrdf, its attributes, visibility, a problem marker with the
// error on hover, and the model's own parameters (sliders/checkboxes/colour pickers).
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include <imgui.h>

namespace app {

namespace {
void drawModelParams(bssrdf::ModelEntry& e) {
    for (const auto& p : e.model->params) {
        auto& v = e.values[p.name];
        // ImGui's default field width (two thirds of the panel), narrowed so that a long
        // parameter name beside it does not make the panel scroll sideways
        if (p.type != bssrdf::ParamType::Bool) setItemWidth(ImGui::CalcItemWidth(), p.name.c_str());
        switch (p.type) {
        case bssrdf::ParamType::Float:
            ImGui::SliderFloat(p.name.c_str(), &v[0], p.min, p.max, "%.4g");
            break;
        case bssrdf::ParamType::Bool: {
            bool b = v[0] != 0.0f;
            if (ImGui::Checkbox(p.name.c_str(), &b)) v[0] = b ? 1.0f : 0.0f;
            break;
        }
        case bssrdf::ParamType::Color:
            ImGui::ColorEdit3(p.name.c_str(), v.data(), ImGuiColorEditFlags_Float);
            break;
        }
    }
}
} // namespace

void drawModelsPanel(Workbench& wb, UiShared& ui) {
    auto& entries = wb.library().entries();
    if (entries.empty()) ImGui::TextDisabled("no .bssrdf files in materials/");
    for (auto& e : entries) {
        ImGui::PushID(e.displayPath.c_str());
        auto& view = wb.view(e.displayPath);
        const std::string name = e.model ? e.model->name : e.file.stem().string();
        ImGui::Checkbox("##visible", &view.visible);
        ImGui::SameLine();
        if (e.problem) {
            ImGui::TextColored(ImVec4(1, 0.35f, 0.35f, 1), "(!)");
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", e.problem->text().c_str());
            ImGui::SameLine();
        }
        // a long name is cut to the panel's width (the whole of it in the tooltip): the tree
        // node's label would make the panel scroll sideways
        const std::string shown =
            cutToWidth(name, visibleWidth() - ImGui::GetTreeNodeToLabelSpacing());
        bool open = ImGui::TreeNodeEx("model", ImGuiTreeNodeFlags_DefaultOpen, "%s", shown.c_str());
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("%s\n%s", name.c_str(), e.displayPath.c_str());
        if (open) {
            if (e.problem) {
                ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.5f, 0.5f, 1));
                wrappedText("%s%s", e.problem->text().c_str(),
                            e.model ? "\n(showing the last good version)" : "");
                ImGui::PopStyleColor();
            }
            if (e.checking())
                hintText("checking the new version's first evaluation%s",
                         e.model ? " (showing the last good version)" : "");
            if (e.model) {
                const auto& a = e.model->attrs;
                ImGui::PushStyleColor(ImGuiCol_Text,
                                      ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
                wrappedText("%s%s%s%s | R_dr/l_d: %s", a.analytic ? "analytic" : "",
                            a.radial ? " radial" : "", a.noWi ? " no_wi" : "",
                            a.noWo ? " no_wo" : "",
                            e.hasInversion() ? "yes" : "numeric (2 pi int R r dr)");
                ImGui::PopStyleColor();
                drawModelParams(e);
                // a default edited in the file leaves the value in use: say so, and offer it
                if (const auto off = bssrdf::valuesOffTheDefaults(*e.model, e.values);
                    !off.empty()) {
                    std::string names;
                    for (const auto& n : off)
                        names += (names.empty() ? "" : ", ") + n;
                    ImGui::PushStyleColor(ImGuiCol_Text,
                                          ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
                    wrappedText("not the file's default: %s", names.c_str());
                    ImGui::PopStyleColor();
                    if (ImGui::SmallButton("reset to the file's defaults"))
                        e.values = bssrdf::defaultValues(*e.model);
                    const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
                    ui.resetDefaults = {lo.x, lo.y, hi.x, hi.y};
                }
                ImGui::Checkbox("own parameters", &view.override);
                if (ImGui::IsItemHovered())
                    ImGui::SetTooltip("own material parameters: this model uses its own "
                                      "sigma_a, sigma_s, g, eta (edit them in Parameters)");
                if (!view.materialProblem.empty()) {
                    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.6f, 0.3f, 1));
                    wrappedText("%s", view.materialProblem.c_str());
                    ImGui::PopStyleColor();
                }
            }
            ImGui::TreePop();
        }
        ImGui::PopID();
    }
}

} // namespace app
