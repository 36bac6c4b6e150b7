// "From albedo and length" in the Parameters panel: a surface albedo and a length per channel,
// turned into σ by a chosen artist mapping (pipeline/param_mappings.h), with the σ it gives at
// once and, on request, what the path tracer measures for that σ (the parameterization lab's
// measurement, pipeline/params_lab.h, run on a worker thread so the panel keeps drawing).
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "core/text.h"
#include "pipeline/workbench.h"

#include <imgui.h>

#include <thread>

namespace app {

namespace {

bool rgbRow(const char* label, glm::dvec3& v, float lo, float hi, bool logarithmic) {
    bool changed = false;
    ImGui::PushID(label);
    ImGui::TextUnformatted(label);
    for (int c = 0; c < 3; ++c) {
        float f = float(v[c]);
        ImGui::SetNextItemWidth(-28);
        const char* channel[3] = {"R", "G", "B"};
        if (ImGui::SliderFloat(channel[c], &f, lo, hi, "%.4g",
                               logarithmic ? ImGuiSliderFlags_Logarithmic : 0)) {
            v[c] = f;
            changed = true;
        }
    }
    ImGui::PopID();
    return changed;
}

} // namespace

void drawArtistMapping(Workbench& wb, MaterialSettings& s, ArtistMappingState& st) {
    const bool open = ImGui::CollapsingHeader("From albedo and length");
    st.header = lastItem();
    if (!open) return;
    const ParamMapping* m = findParamMapping(st.mapping);
    if (!m) m = &paramMappings().front(), st.mapping = m->id;
    if (ImGui::BeginCombo("mapping", m->name.c_str())) {
        for (const ParamMapping& k : paramMappings()) {
            if (ImGui::Selectable(k.name.c_str(), k.id == st.mapping)) st.mapping = k.id;
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("%s\nd = %s", k.source.c_str(), k.length.c_str());
        }
        ImGui::EndCombo();
        m = findParamMapping(st.mapping);
    }
    rgbRow("surface albedo A", st.albedo, 0.01f, 0.99f, false);
    rgbRow(("d [mm]: " + m->length).c_str(), st.lengthMm, 0.01f, 100.0f, true);

    material::MaterialParams p;
    st.problem.clear();
    try {
        p = mapArtistParams(*m, st.albedo, st.lengthMm, s.params.g, s.params.eta,
                            m->model.empty() ? nullptr : wb.library().find(m->model));
        p.scale = s.params.scale;
    } catch (const core::Error& e) {
        st.problem = e.what();
    }
    if (!st.problem.empty()) {
        colouredText(ImVec4(1, 0.5f, 0.5f, 1), "%s", st.problem.c_str());
        return;
    }
    ImGui::TextDisabled("sigma_a %.4g %.4g %.4g /mm", p.sigmaA.x, p.sigmaA.y, p.sigmaA.z);
    hintText("sigma_s %.4g %.4g %.4g /mm (g %.3g, eta %.3g)", p.sigmaS.x, p.sigmaS.y, p.sigmaS.z,
             p.g, p.eta);
    if (ImGui::Button("Apply")) {
        s.params = p;
        s.mode = ParamMode::Sigma;
        s.preset.clear();
    }
    st.applyButton = lastItem();
    ImGui::SameLine();
    const std::string key = core::keyOf(st.mapping, st.albedo.x, st.albedo.y, st.albedo.z,
                                        st.lengthMm.x, st.lengthMm.y, st.lengthMm.z, p.g, p.eta);
    const bool running = st.measurement && !st.measurement->done.load();
    ImGui::BeginDisabled(running);
    if (ImGui::Button(running ? "Measuring..." : "Measure")) {
        if (st.measurement) st.measurement->cancel = true;
        auto job = std::make_shared<ArtistMeasurement>();
        job->cases.resize(3);
        for (int c = 0; c < 3; ++c) {
            LabCase& lc = job->cases[size_t(c)];
            lc.mapping = st.mapping;
            lc.eta = p.eta;
            lc.g = p.g;
            lc.albedo = st.albedo[c];
            lc.lengthMm = st.lengthMm[c];
        }
        std::thread([job, p, paths = st.measurePaths] {
            for (int c = 0; c < 3 && !job->cancel.load(); ++c) {
                material::MaterialParams one = p;
                one.sigmaA = glm::dvec3(p.sigmaA[c]);
                one.sigmaS = glm::dvec3(p.sigmaS[c]);
                try {
                    measureLabCase(one, paths, job->cases[size_t(c)]);
                } catch (const core::Error& e) {
                    job->cases[size_t(c)].problem = e.what();
                }
            }
            job->done = true;
        }).detach();
        st.measurement = job;
        st.measuredKey = key;
    }
    ImGui::EndDisabled();
    st.measureButton = lastItem();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("path trace the slab for this sigma (10^5 paths per channel) and show "
                          "the albedo and radius it really gives");
    if (st.measurement && st.measurement->done.load()) {
        if (st.measuredKey != key) ImGui::TextDisabled("(measured for earlier values)");
        if (ImGui::BeginTable("measured", 4, ImGuiTableFlags_SizingStretchSame)) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextDisabled("measured");
            for (const char* ch : {"R", "G", "B"}) {
                ImGui::TableNextColumn();
                ImGui::TextDisabled("%s", ch);
            }
            // a value and, on a line of its own, its standard error (a narrow column cut
            // "0.804 +- 0.003" to "0.804 +- 0.00"); names wrap
            auto row = [&](const char* name, auto value, auto se) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::PushStyleColor(ImGuiCol_Text,
                                      ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
                ImGui::TextWrapped("%s", name);
                ImGui::PopStyleColor();
                for (const LabCase& c : st.measurement->cases) {
                    ImGui::TableNextColumn();
                    if (!c.problem.empty()) {
                        ImGui::TextDisabled("-");
                        continue;
                    }
                    ImGui::TextUnformatted(value(c).c_str());
                    if (const std::string e = se(c); !e.empty())
                        ImGui::TextDisabled("+- %s", e.c_str());
                }
            };
            const auto none = [](const LabCase&) { return std::string(); };
            row(
                "A", [](const LabCase& c) { return core::formatNumber(c.measured, 3); },
                [](const LabCase& c) { return core::formatNumber(c.measuredSe, 1); });
            row(
                "A / asked",
                [](const LabCase& c) { return core::formatNumber(c.measured / c.albedo, 3); },
                none);
            row(
                "A diffuse light",
                [](const LabCase& c) { return core::formatNumber(c.diffuse, 3); },
                [](const LabCase& c) { return core::formatNumber(c.diffuseSe, 1); });
            row(
                "mean r / d",
                [](const LabCase& c) { return core::formatNumber(c.meanRadiusMm / c.lengthMm, 3); },
                none);
            ImGui::EndTable();
        }
        for (const LabCase& c : st.measurement->cases)
            if (!c.problem.empty()) colouredText(ImVec4(1, 0.5f, 0.5f, 1), "%s", c.problem.c_str());
    }
}

} // namespace app
