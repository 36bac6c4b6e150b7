// Fit panel: pick a model and the parameters to free, fit them to the pencil plot's path-traced
// reference (Workbench::fit(), pipeline/fit_stage.h: the objective and search of `fit`) while the
// workbench runs; the objective's trace as it goes, then each parameter's start → fitted value
// and each channel's rel_err before → after; Apply keeps the fitted values in the model.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "core/core.h"
#include "core/text.h"
#include "plot/plot_draw.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace app {

namespace {

std::string pct(double v) {
    return std::isfinite(v) ? core::formatNumber(100 * v, 3) + " %" : std::string("-");
}

} // namespace

void drawFitPanel(Workbench& wb, FitPanelState& ps, UiShared& ui) {
    ReferenceSettings& rs = wb.referenceSettings();
    if (!rs.enabled) {
        hintText("The fit is made against the pencil plot's path-traced reference, which is off.");
        if (ImGui::Button("Start the reference")) rs.enabled = true;
        return;
    }
    // the model: by default the reference's own (its σ is the medium fitted against)
    if (ps.model.empty()) ps.model = wb.reference().model();
    setItemWidth(260, "model");
    if (ImGui::BeginCombo("model", ps.model.c_str())) {
        for (const auto& e : wb.library().entries())
            if (e.usable() && ImGui::Selectable(e.displayPath.c_str(), ps.model == e.displayPath)) {
                ps.model = e.displayPath;
                ps.params.clear();
            }
        ImGui::EndCombo();
    }
    const bssrdf::ModelEntry* e = wb.library().find(ps.model);
    if (!e || !e->usable()) {
        hintText("Choose a usable model.");
        return;
    }
    ImGui::TextUnformatted("free parameters (within their declared ranges):");
    int fittable = 0;
    for (const bssrdf::Param& p : e->model->params) {
        if (p.type == bssrdf::ParamType::Bool) continue;
        ++fittable;
        bool on = std::find(ps.params.begin(), ps.params.end(), p.name) != ps.params.end();
        sameLineIfFits(checkboxWidth(p.name.c_str()));
        if (ImGui::Checkbox(p.name.c_str(), &on)) {
            ps.params.erase(std::remove(ps.params.begin(), ps.params.end(), p.name),
                            ps.params.end());
            if (on) ps.params.push_back(p.name);
        }
    }
    if (fittable == 0) {
        hintText("This model declares no float or colour parameter to fit.");
        return;
    }
    const FitSnapshot snap = wb.fit().snapshot();
    if (snap.running) {
        wrappedText("fitting %s: %zu evaluations, best mean rel_err^2 %s%s", snap.model.c_str(),
                    snap.trace.size(),
                    snap.trace.empty() ? "-" : core::formatNumber(snap.trace.back(), 4).c_str(),
                    snap.restarts ? " (restarted after a reload)" : "");
        ImGui::SameLine();
        if (ImGui::SmallButton("Cancel")) wb.fit().cancel();
    } else {
        ImGui::BeginDisabled(ps.params.empty());
        if (ImGui::Button("Fit")) {
            try {
                wb.startFit(ps.model, ps.params);
            } catch (const core::Error& err) {
                wb.reportActionError(std::string("fit: ") + err.what());
            }
        }
        ps.fitButton = lastItem();
        ImGui::EndDisabled();
        sameLineIfFits(300);
        hintText("against the reference now: %s paths per channel of %s's medium",
                 core::formatNumber(double(wb.reference().snapshot().pathsDone), 3).c_str(),
                 wb.reference().model().c_str());
    }
    if (!snap.problem.empty()) colouredText(ImVec4(1, 0.45f, 0.45f, 1), "%s", snap.problem.c_str());

    if (snap.result) {
        const FitResult& r = *snap.result;
        wrappedText("%s: %d evaluations, %s", snap.model.c_str(), r.evaluations, r.status.c_str());
        if (ImGui::BeginTable("fitted", 3,
                              ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
            for (const char* h : {"parameter", "start", "fitted"})
                ImGui::TableSetupColumn(h);
            ImGui::TableHeadersRow();
            for (size_t i = 0; i < snap.vars.size() && i < r.best.size(); ++i) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(snap.vars[i].label.c_str());
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(core::formatNumber(r.start[i], 5).c_str());
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(core::formatNumber(r.best[i], 5).c_str());
            }
            ImGui::EndTable();
        }
        for (size_t t = 0; t < snap.targets.size() && t < r.relErrBest.size(); ++t)
            ImGui::Text("%s: rel_err %s -> %s", snap.targets[t].c_str(),
                        pct(r.relErrStart[t]).c_str(), pct(r.relErrBest[t]).c_str());
        for (const std::string& p : r.problems)
            colouredText(ImVec4(1, 0.6f, 0.3f, 1), "not finite at %s", p.c_str());
        if (ImGui::Button("Apply")) {
            if (wb.fit().apply(wb.library()))
                ui.status = "applied the fitted values to " + snap.model;
        }
        ps.applyButton = lastItem();
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("set the fitted values in %s (the file's defaults stay; the Models "
                              "panel says so and can reset them)",
                              snap.model.c_str());
    }
    // the objective's trace: the best mean rel_err² after each evaluation
    if (snap.trace.size() >= 2) {
        plot::Series s;
        s.label = "best mean rel_err^2";
        s.color = 0xff40c0ffu;
        for (size_t i = 0; i < snap.trace.size(); ++i) {
            s.x.push_back(double(i + 1));
            s.y.push_back(std::max(snap.trace[i], 1e-12));
        }
        plot::Axis x{1.0, double(snap.trace.size()), plot::Scale::Linear, "evaluation"};
        plot::Axis y = plot::autoRange({s}, plot::Scale::Log, true, 12.0);
        y.label = "mean rel_err^2";
        plot::drawPlot("fittrace", ImVec2(-1, std::max(160.0f, ImGui::GetContentRegionAvail().y)),
                       {s}, x, y, "Fit objective", "NLopt BOBYQA, restarts after a wall of NaN");
    }
}

} // namespace app
