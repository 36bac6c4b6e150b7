// Pencil plot panel (thesis 3.6.3): radial profiles of every loaded model on the semi-infinite
// slab under a normally incident pencil beam; y axis linear/log/sqrt, optional r·R(r),
// channel R/G/B/luminance, solo mode, hover readout, CSV and PNG export.
#include "gui/export_buttons.h"
#include "gui/panels/panels.h"
#include "gui/widgets.h"
#include "pipeline/pencil_series.h"

#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"
#include "plot/plot_draw.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace app {

namespace {
// Path-traced reference: on/off, path budget, bins, seed, progress, paths/s, cancel.
void drawReferenceControls(Workbench& wb) {
    ReferenceSettings& rs = wb.referenceSettings();
    ImGui::Checkbox("path-traced reference", &rs.enabled);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Volumetric path tracer on the slab (MCML convention), renormalised\n"
            "to unit power entering: R_d(r) / (1 - R_sp). Band: +-2 standard errors.");
    if (!rs.enabled) return;
    int millions = int(rs.paths / 100000);
    sameLineItem(110, "x1e5 paths/ch");
    if (inputIntCommitted("x1e5 paths/ch", &millions, 5))
        rs.paths = uint64_t(std::clamp(millions, 1, 100000)) * 100000;
    sameLineItem(90, "bins");
    if (inputIntCommitted("bins", &rs.bins, 25)) rs.bins = std::clamp(rs.bins, 10, 5000);
    int seed = int(rs.seed);
    sameLineItem(80, "seed");
    if (inputIntCommitted("seed", &seed)) rs.seed = uint64_t(std::max(seed, 0));
    enumCombo("estimator", rs.estimator, 110);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("implicit: absorption by weight (default)\nanalog: absorption by "
                          "roulette (thesis Algorithm 1; the CPU walk splits radially)\n"
                          "connections: every collision connected to every bin (seed 001; CPU "
                          "only)");
    exitSamplesInput(rs.exitSamples);
    enumCombo("device", rs.device, 70);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("gpu: GL compute tracer (shaders/pathtrace_slab.comp, hot-reloaded), a "
                          "slice per frame\ncpu: CPU tracer in a background thread\nauto: the "
                          "GPU where it measured faster than the CPU here (once per run)");
    ReferenceSnapshot snap = wb.reference().snapshot();
    if (!snap.problem.empty()) {
        colouredText(ImVec4(1, 0.45f, 0.45f, 1), "%s", snap.problem.c_str());
        return;
    }
    const float frac =
        snap.pathsTarget ? float(double(snap.pathsDone) / double(snap.pathsTarget)) : 0.0f;
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%llu / %llu paths per channel",
                  (unsigned long long)snap.pathsDone, (unsigned long long)snap.pathsTarget);
    if (!snap.energy.empty())
        colouredText(ImVec4(1, 0.45f, 0.45f, 1), "reference %s", snap.energy.c_str());
    ImGui::ProgressBar(frac, ImVec2(fittingWidth(320), 0), overlay);
    sameLineIfFits(200);
    hintText("%s %.3g paths/s | sigma of %s", snap.device.c_str(), snap.pathsPerSecond,
             wb.reference().model().c_str());
    if (const std::string choice = wb.reference().deviceChoice();
        !choice.empty() && ImGui::IsItemHovered())
        ImGui::SetTooltip("device auto, measured once at start: %s", choice.c_str());
    sameLineIfFits(buttonWidth(snap.running ? "cancel" : "restart"));
    if (snap.running) {
        if (ImGui::SmallButton("cancel")) wb.reference().cancel();
    } else if (ImGui::SmallButton("restart")) {
        wb.reference().restart();
    }
}
} // namespace

void drawPencilPanel(Workbench& wb, PencilPanelState& own, UiShared& ui) {
    PlotSettings& ps = wb.plotSettings();
    int scale = static_cast<int>(ps.yScale);
    setItemWidth(90, "y axis");
    ImGui::Combo("y axis", &scale, "linear\0log\0sqrt\0");
    ps.yScale = static_cast<plot::Scale>(scale);
    sameLineIfFits(checkboxWidth("r * R(r)"));
    ImGui::Checkbox("r * R(r)", &ps.rTimesR);
    sameLineItem(100, "channel");
    ImGui::Combo("channel", &ps.channel, "red\0green\0blue\0luminance\0");
    sameLineItem(160, "solo");
    if (ImGui::BeginCombo("solo", ps.solo.empty() ? "(all models)" : ps.solo.c_str())) {
        if (ImGui::Selectable("(all models)", ps.solo.empty())) ps.solo.clear();
        for (auto& e : wb.library().entries())
            if (ImGui::Selectable(e.displayPath.c_str(), ps.solo == e.displayPath))
                ps.solo = e.displayPath;
        ImGui::EndCombo();
    }
    setItemWidth(90, "samples");
    // The ranges are the settings' own (PlotSettings' description), as on the CLI and in captures.
    static const core::Limits samplesLim = core::limitsOf<PlotSettings>("samples"),
                              rMaxLim = core::limitsOf<PlotSettings>("r_max_mm"),
                              rangeLim = core::limitsOf<PlotSettings>("range_ld");
    if (inputIntCommitted("samples", &ps.samples, 256))
        ps.samples = std::clamp(ps.samples, int(samplesLim.lo), int(samplesLim.hi));
    sameLineIfFits(checkboxWidth("fixed range"));
    ImGui::Checkbox("fixed range", &ps.fixedRange);
    sameLineItem(120, ps.fixedRange ? "r max [mm]" : "x largest l_d");
    if (ps.fixedRange) {
        float r = float(ps.rMaxMm);
        if (ImGui::DragFloat("r max [mm]", &r, 0.1f, float(rMaxLim.lo), float(rMaxLim.hi), "%.3g",
                             ImGuiSliderFlags_AlwaysClamp))
            ps.rMaxMm = r;
    } else {
        float k = float(ps.rangeLd);
        if (ImGui::DragFloat("x largest l_d", &k, 0.05f, float(rangeLim.lo), float(rangeLim.hi),
                             "%.2f", ImGuiSliderFlags_AlwaysClamp))
            ps.rangeLd = k;
    }
    char range[64];
    std::snprintf(range, sizeof range, "r in [0, %.3g] mm", wb.rMaxMm());
    sameLineIfFits(ImGui::CalcTextSize(range).x);
    ImGui::TextDisabled("%s", range);

    // Values, or each curve relative to the path-traced reference or to a model's curve.
    setItemWidth(200, "show");
    const char* relNames[] = {"values", "ratio", "difference"};
    comboEnum("show", ps.relation, relNames);
    const bool toModel = comparesWithModel(wb);
    std::string baseName = "path-traced reference";
    if (toModel)
        for (const auto& e : wb.library().entries())
            if (e.displayPath == ps.compareWith) baseName = e.model ? e.model->name : e.displayPath;
    if (ps.relation != plot::Relation::Values && ps.solo.empty()) {
        sameLineItem(200, "to");
        if (ImGui::BeginCombo("to", baseName.c_str())) {
            if (ImGui::Selectable("path-traced reference", ps.compareWith.empty()))
                ps.compareWith.clear();
            for (const auto& e : wb.library().entries()) {
                const auto v = wb.views().find(e.displayPath);
                if (v == wb.views().end() || !v->second.visible) continue;
                const std::string label =
                    (e.model ? e.model->name : e.displayPath) + "##" + e.displayPath;
                if (ImGui::Selectable(label.c_str(), ps.compareWith == e.displayPath))
                    ps.compareWith = e.displayPath;
            }
            ImGui::EndCombo();
        }
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("what every curve is shown relative to: the path-traced reference, "
                              "or one model's curve (the references then relative to it too)");
    }
    auto series = plotSeries(wb);
    const bool hasReference = std::any_of(series.begin(), series.end(),
                                          [](const plot::Series& s) { return s.compareTo >= 0; });
    const bool relative = ps.relation != plot::Relation::Values && hasReference;
    if (ps.relation != plot::Relation::Values && !hasReference) {
        ImGui::SameLine();
        hintText(ps.compareWith.empty() || !ps.solo.empty()
                     ? "needs the path-traced reference (below)"
                     : "needs the path-traced reference (below) or a shown model to compare with");
    }
    if (relative) series = plot::relativeTo(series, ps.relation);

    // what is shown, as CSV or as the picture; each asks where (the file dialog)
    if (auto path = drawExportButtons("Export pencil plot", own.exportName, sizeof own.exportName,
                                      {".csv", ".png"}, own.exporter, &own.exportButtons)) {
        if (path->extension() == ".png") {
            own.plotPngRequest = path->string(); // read back after the frame is drawn
        } else {
            try {
                plot::writeCsv(path->string(), series, "r_mm");
                ui.status = "wrote " + path->string();
                core::logInfo("pencil plot: wrote " + path->string());
            } catch (const core::Error& e) {
                wb.reportActionError(std::string("export CSV: ") + e.what());
            }
        }
    }

    drawReferenceControls(wb);

    plot::Axis x{0.0, wb.rMaxMm(), plot::Scale::Linear, "r [mm]"};
    const bool difference = relative && ps.relation == plot::Relation::Difference;
    // a difference changes sign: always a linear axis
    plot::Axis y =
        plot::autoRange(series, difference ? plot::Scale::Linear : ps.yScale, true, 12.0);
    y.label = ps.rTimesR ? "r * R(r) [1/mm]" : "R(r) [1/mm^2]";
    if (relative) {
        const std::string q = ps.rTimesR ? "r R" : "R";
        const std::string base = q + (toModel ? " of " + baseName : "_ref");
        y.label = difference ? q + " - " + base + (ps.rTimesR ? " [1/mm]" : " [1/mm^2]")
                             : q + " / " + base;
    }
    const char* chName[4] = {"red", "green", "blue", "luminance"};
    std::string title = "Pencil beam on a semi-infinite slab - " +
                        std::string(ps.solo.empty() ? chName[ps.channel] : "R, G, B of " + ps.solo);
    plot::PlotState st =
        plot::drawPlot("pencil", ImVec2(-1, -1), series, x, y, title, normalisationNote());
    // R_p of the hybrid for the selected model (the soloed one, else the Render panel's): where
    // its importance R·2πr last meets the lower bound (seed 004 §3.3.1)
    if (!relative && x.hi > x.lo) {
        ImDrawList* dl = ImGui::GetWindowDrawList();
        float line = 0;
        for (const RpMarker& m : hybridRpMarkers(wb)) {
            const float sx = st.plotMin.x +
                             float((m.rMm - x.lo) / (x.hi - x.lo)) * (st.plotMax.x - st.plotMin.x);
            if (sx < st.plotMin.x || sx > st.plotMax.x) continue;
            for (float y0 = st.plotMin.y; y0 < st.plotMax.y; y0 += 8.0f) // dashed
                dl->AddLine(ImVec2(sx, y0), ImVec2(sx, std::min(y0 + 4.0f, st.plotMax.y)), m.color,
                            1.5f);
            char text[48];
            std::snprintf(text, sizeof text, "%s %.3g mm", m.label.c_str(), m.rMm);
            dl->AddText(ImVec2(sx + 3, st.plotMin.y + 2 + 14.0f * line++), m.color, text);
        }
    }
    if (!own.plotPngRequest.empty()) {
        ui.pngExportPath = own.plotPngRequest;
        own.plotPngRequest.clear();
        ui.pngRect[0] = st.min.x;
        ui.pngRect[1] = st.min.y;
        ui.pngRect[2] = st.max.x;
        ui.pngRect[3] = st.max.y;
    }
}

} // namespace app
