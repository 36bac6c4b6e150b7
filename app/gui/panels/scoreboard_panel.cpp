// Scoreboard panel, two tabs. Profiles: the table of `compare` for the current parameters
// (scoreboard_stage.h),
// every model ranked against the pencil plot's path-traced reference per channel, ties within
// the noise marked "=", rel_err cells coloured from green (0) to red (>= 30 %), each header and
// rel_err cell explaining itself in a tooltip. A click on a
// row solos that model in the pencil plot on that channel and brings the plot to the front;
// the preset combo applies a preset to the shared parameters (the table follows). Geometry: the
// scores of `compare --geometry` (scoreboard_geometry.cpp). An MCML run opened as a reference
// (File → Open MCML reference) gets its own table above, the rows of `compare --mco`.
#include "gui/panels/panels.h"
#include "gui/preset_combo.h"
#include "gui/widgets.h"
#include "pipeline/pencil_series.h"

#include "core/text.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace app {

namespace {

std::string num(double v, int digits = 3) {
    return std::isfinite(v) ? core::formatNumber(v, digits) : "-";
}

ImU32 relColour(double rel) {
    const double t = std::clamp(rel / 0.3, 0.0, 1.0);
    const int red = int(std::lround(255 * std::min(1.0, 2 * t)));
    const int green = int(std::lround(200 * std::min(1.0, 2 * (1 - t))));
    return IM_COL32(red, green, 96, 160);
}

} // namespace

namespace {

// The models against the MCML run opened as a reference (the rows of `compare --mco`); a click
// on a row solos that model in the pencil plot, where the run is drawn.
void drawMcmlScores(Workbench& wb, UiShared& ui) {
    const ScoreboardStage& sb = wb.scoreboard();
    const auto& run = wb.mcmlReference();
    if (sb.mcmlRows().empty() || !run) return;
    if (!ImGui::CollapsingHeader(("Against the MCML run " + sb.mcmlName()).c_str(),
                                 ImGuiTreeNodeFlags_DefaultOpen))
        return;
    hintText("Its own medium (sigma_a %s, sigma_s %s 1/mm, g %s, eta %s), one channel, as "
             "`compare --mco`.",
             num(run->medium.sigmaA, 4).c_str(), num(run->medium.sigmaS, 4).c_str(),
             num(run->medium.g, 3).c_str(), num(run->medium.eta, 3).c_str());
    const ImGuiTableFlags flags =
        ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingFixedFit;
    if (!ImGui::BeginTable("mcml scores", 6, flags)) return;
    for (const char* h : {"model", "rank", "rel_err", "@1 l_d", "@4 l_d", "total"})
        ImGui::TableSetupColumn(h);
    ImGui::TableHeadersRow();
    for (const ScoreboardRow& r : sb.mcmlRows()) {
        const capture::ScoreRow& s2 = r.score;
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        if (ImGui::Selectable(s2.model.c_str(), wb.plotSettings().solo == r.displayPath,
                              ImGuiSelectableFlags_SpanAllColumns)) {
            wb.plotSettings().solo = r.displayPath;
            ui.show(PanelId::Pencil);
        }
        ImGui::TableNextColumn();
        ImGui::Text("%s%d", s2.tie ? "=" : "", s2.rank);
        ImGui::TableNextColumn();
        ImGui::TableSetBgColor(ImGuiTableBgTarget_CellBg, relColour(s2.relErr));
        ImGui::Text("%s %% +- %s %%", num(100 * s2.relErr).c_str(),
                    num(100 * s2.relErrSe, 2).c_str());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(num(s2.ratio1).c_str());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(num(s2.ratio4).c_str());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(num(s2.totalRatio).c_str());
    }
    ImGui::EndTable();
}

void drawProfileScores(Workbench& wb, ScoreboardPanelState& ps, UiShared& ui) {
    drawMcmlScores(wb, ui);
    MaterialSettings& s = wb.shared();
    setItemWidth(160, "preset");
    presetCombo("preset", wb, s);
    sameLineItem(100, "channels");
    ImGui::Combo("channels", &ps.channel, "R\0G\0B\0all\0");
    ReferenceSettings& rs = wb.referenceSettings();
    if (!rs.enabled) {
        hintText("The scoreboard scores every model against the path-traced reference of the "
                 "pencil plot, which is off.");
        if (ImGui::Button("Start the reference")) rs.enabled = true;
        return;
    }
    const ScoreboardStage& sb = wb.scoreboard();
    const ReferenceSnapshot snap = wb.reference().snapshot();
    hintText("Against the reference of %s's medium: %s paths per channel%s. rel_err: RMS relative "
             "error over ln r in [0.1, 4] l_d (+- standard error); \"=\" ties within the noise. "
             "Hover a header or a rel_err for its definition; click a row to open the model in "
             "the pencil plot.",
             wb.reference().model().c_str(),
             core::formatNumber(double(sb.referencePaths()), 3).c_str(),
             snap.running ? " (running)" : "");
    for (const std::string& n : sb.notes())
        hintText("%s", n.c_str());
    const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                                  ImGuiTableFlags_ScrollX | ImGuiTableFlags_ScrollY |
                                  ImGuiTableFlags_SizingFixedFit;
    // the frozen columns (channel, model) stay within the panel: ImGui narrows them to it and
    // cuts a long name at the column's edge; cut here, with "...", it says it was cut (the
    // row's tooltip names the file)
    const float modelWidth = std::max(80.0f, 0.6f * ImGui::GetContentRegionAvail().x);
    if (!ImGui::BeginTable("scores", 8, flags)) return;
    ImGui::TableSetupScrollFreeze(2, 1);
    // short headers, so the table fits a 1280-wide window; each explains itself on hover
    static constexpr std::pair<const char*, const char*> kColumns[] = {
        {"ch", "colour channel: each is its own medium and its own reference"},
        {"model", "the model file (click a row to open it in the pencil plot)"},
        {"rank", "rank within the channel; \"=\" ties with the best of its group within "
                 "2 standard errors"},
        {"rel_err", "RMS relative error (model - reference) / reference over ln r in "
                    "[0.1, 4] l_d, the model averaged over each reference bin, the reference's "
                    "own noise removed; +- its standard error (as `compare`)"},
        {"@1 l_d", "model / reference over r within 5 % of 1 l_d"},
        {"@4 l_d", "model / reference over r within 5 % of 4 l_d"},
        {"total", "model's total diffuse reflectance 2 pi int R r dr over the reference's"},
        {">5 % at", "the first radius (l_d) from 0.1 l_d where the model is off by more than "
                    "5 % and 2 standard errors"}};
    for (const auto& [h, tip] : kColumns)
        ImGui::TableSetupColumn(h);
    ImGui::TableNextRow(ImGuiTableRowFlags_Headers);
    for (int c = 0; c < 8; ++c) {
        if (!ImGui::TableSetColumnIndex(c)) continue;
        ImGui::TableHeader(kColumns[c].first);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", kColumns[c].second);
    }
    int id = 0;
    ps.rowRects.clear();
    for (const ScoreboardRow& r : sb.rows()) {
        if (ps.channel < 3 && r.channel != ps.channel) continue;
        const capture::ScoreRow& s2 = r.score;
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::PushID(id++);
        const bool solo =
            wb.plotSettings().solo == r.displayPath && wb.plotSettings().channel == r.channel;
        if (ImGui::Selectable(s2.channel.c_str(), solo, ImGuiSelectableFlags_SpanAllColumns)) {
            wb.plotSettings().solo = r.displayPath;
            wb.plotSettings().channel = r.channel;
            ui.show(PanelId::Pencil);
        }
        const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
        ps.rowRects.push_back({lo.x, lo.y, hi.x, hi.y});
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("open %s in the pencil plot, channel %s", r.displayPath.c_str(),
                              s2.channel.c_str());
        ImGui::PopID();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(cutToWidth(s2.model, modelWidth).c_str());
        ImGui::TableNextColumn();
        ImGui::Text("%s%d", s2.tie ? "=" : "", s2.rank);
        ImGui::TableNextColumn();
        ImGui::TableSetBgColor(ImGuiTableBgTarget_CellBg, relColour(s2.relErr));
        ImGui::Text("%s %% +- %s %%", num(100 * s2.relErr).c_str(),
                    num(100 * s2.relErrSe, 2).c_str());
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", errorTooltip(r).c_str());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(num(s2.ratio1).c_str());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(num(s2.ratio4).c_str());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(num(s2.totalRatio).c_str());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(s2.rErr5Ld ? num(*s2.rErr5Ld).c_str() : "none");
    }
    ImGui::EndTable();
}

} // namespace

void drawScoreboardPanel(Workbench& wb, ScoreboardPanelState& ps, UiShared& ui) {
    ps.geometryTab = false;
    if (!ImGui::BeginTabBar("scoreboard tabs")) return;
    if (ImGui::BeginTabItem("Profiles")) {
        drawProfileScores(wb, ps, ui);
        ImGui::EndTabItem();
    }
    const bool geometry = ImGui::BeginTabItem("Geometry");
    ps.geometryTabRect = lastItem();
    if (geometry) {
        ps.geometryTab = true;
        drawGeometryScores(wb, ps);
        ImGui::EndTabItem();
    }
    ImGui::EndTabBar();
}

} // namespace app
