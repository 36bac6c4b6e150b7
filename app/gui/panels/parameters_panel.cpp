// Parameters panel (thesis 3.6.1): σa/σs with logarithmic sliders or the R_dr/l_d
// parametrisation, g, η, scale, presets, colour swatches; shared by all models or per model.
#include "gui/panels/panels.h"
#include "gui/preset_combo.h"
#include "gui/widgets.h"

#include <imgui.h>

#include <cmath>

namespace app {

namespace {
bool sliderRgb(const char* label, glm::dvec3& v, float lo, float hi, bool logarithmic,
               const char* fmt) {
    bool changed = false;
    ImGui::PushID(label);
    ImGui::TextUnformatted(label);
    const char* ch[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        float f = static_cast<float>(v[c]);
        ImGui::SetNextItemWidth(-28);
        if (ImGui::SliderFloat(ch[c], &f, lo, hi, fmt,
                               logarithmic ? ImGuiSliderFlags_Logarithmic : 0)) {
            v[c] = f;
            changed = true;
        }
    }
    ImGui::PopID();
    return changed;
}

void swatchButton(const char* label, const glm::dvec3& rgb) {
    glm::dvec3 s = material::swatch(rgb);
    ImGui::ColorButton(label,
                       ImVec4(float(std::min(s.r, 1.0)), float(std::min(s.g, 1.0)),
                              float(std::min(s.b, 1.0)), 1.0f),
                       ImGuiColorEditFlags_NoTooltip, ImVec2(40, 18));
    ImGui::SameLine();
    ImGui::TextDisabled("%s", label);
}
} // namespace

void drawParametersPanel(Workbench& wb, ParametersPanelState& ps, UiShared&) {
    // Which settings are edited: the shared ones or a model's own.
    std::string& target = ps.target; // display path; empty = shared
    std::string targetLabel = target.empty() ? "all models (shared)" : target;
    if (ImGui::BeginCombo("applies to", targetLabel.c_str())) {
        if (ImGui::Selectable("all models (shared)", target.empty())) target.clear();
        for (auto& e : wb.library().entries())
            if (ImGui::Selectable(e.displayPath.c_str(), target == e.displayPath)) {
                target = e.displayPath;
                wb.view(target).override = true;
            }
        ImGui::EndCombo();
    }
    if (!target.empty() && !wb.library().find(target)) target.clear();
    MaterialSettings& s = target.empty() ? wb.shared() : wb.view(target).own;
    if (!target.empty()) {
        ImGui::Checkbox("override shared parameters", &wb.view(target).override);
        if (!wb.view(target).override) hintText("(editing values not in use)");
    }

    presetCombo("preset", wb, s);
    drawArtistMapping(wb, s, ps.artist);

    int mode = static_cast<int>(s.mode);
    ImGui::RadioButton("sigma_a, sigma_s", &mode, 0);
    sameLineIfFits(checkboxWidth("R_dr, l_d"));
    ImGui::RadioButton("R_dr, l_d", &mode, 1);
    s.mode = static_cast<ParamMode>(mode);
    // models without a closed form integrate their profile: say so
    if (s.mode == ParamMode::RdrLd)
        for (auto& e : wb.library().entries())
            if (e.model && !e.hasInversion())
                hintText("%s: R_dr from its profile, integrated numerically (no "
                         "diffuseReflectance section)",
                         e.model->name.c_str());

    auto& p = s.params;
    if (s.mode == ParamMode::Sigma) {
        if (sliderRgb("sigma_a [1/mm]", p.sigmaA, 0.0f, 10.0f, true, "%.5g")) s.preset.clear();
        if (sliderRgb("sigma_s [1/mm]", p.sigmaS, 1e-3f, 100.0f, true, "%.4g")) s.preset.clear();
    } else {
        sliderRgb("R_dr (total diffuse reflectance)", s.rdr, 0.0f, 1.0f, false, "%.4f");
        sliderRgb("l_d [mm] (diffuse mean free path)", s.ld, 0.01f, 100.0f, true, "%.4g");
    }
    float g = float(p.g), eta = float(p.eta), scale = float(p.scale);
    if (ImGui::SliderFloat("g", &g, -0.99f, 0.99f, "%.3f")) p.g = g, s.preset.clear();
    if (ImGui::SliderFloat("eta", &eta, 1.0f, 2.5f, "%.3f")) p.eta = eta, s.preset.clear();
    if (ImGui::SliderFloat("scale", &scale, 0.1f, 1000.0f, "%.3g mm/unit",
                           ImGuiSliderFlags_Logarithmic))
        p.scale = scale;
    ImGui::Separator();
    swatchButton("sigma_a", p.sigmaA);
    swatchButton("sigma_s", p.sigmaS);

    ImGui::Separator();
    ImGui::TextUnformatted("In use per model:");
    for (auto& e : wb.library().entries()) {
        auto& v = wb.view(e.displayPath);
        if (!e.model) continue;
        if (!v.effective) {
            colouredText(ImVec4(1, 0.5f, 0.5f, 1), "%s: %s", e.model->name.c_str(),
                         v.materialProblem.c_str());
            continue;
        }
        const auto& q = *v.effective;
        glm::dvec3 ap = material::reducedAlbedo(q), ld = material::diffuseMeanFreePath(q);
        wrappedText("%s%s", e.model->name.c_str(), v.override ? " (own)" : ""); // a long name too
        // as wide as the panel (without an outer width ImGui 1.86 widens the panel to the
        // columns' natural widths, and the whole panel scrolls sideways); where a name and
        // three values do not fit in a row (a narrow column: 800x600), each name on a row of
        // its own above its values, rather than values cut at the columns' edges
        const float avail = ImGui::GetContentRegionAvail().x;
        const ImGuiStyle& style = ImGui::GetStyle();
        const float cell = ImGui::CalcTextSize("0.00000").x + 2 * style.CellPadding.x;
        const bool nameBeside =
            avail >= ImGui::CalcTextSize("l_d [mm]").x + 2 * style.CellPadding.x + 3 * cell;
        if (ImGui::BeginTable("inuse", nameBeside ? 4 : 3, ImGuiTableFlags_SizingStretchSame,
                              ImVec2(avail, 0))) {
            auto row = [nameBeside](const char* name, const glm::dvec3& x, const char* fmt) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextDisabled("%s", name);
                if (!nameBeside) ImGui::TableNextRow();
                for (int c = 0; c < 3; ++c) {
                    ImGui::TableNextColumn();
                    ImGui::TextDisabled(fmt, x[c]);
                }
            };
            row("sigma_a", q.sigmaA, "%.4g");
            row("sigma_s", q.sigmaS, "%.4g");
            row("alpha'", ap, "%.5f");
            row("l_d [mm]", ld, "%.4g");
            ImGui::EndTable();
        }
    }
}

} // namespace app
