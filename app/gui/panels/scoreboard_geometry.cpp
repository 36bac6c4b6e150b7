// The Scoreboard's geometry tab (pipeline/geometry_stage.h, the scores of `compare --geometry`):
// a preset, a channel and the suite's shapes to run; Run starts the path-traced references in the
// background (progress, Cancel) and integrates every model's image; a model × shape table
// coloured by rel_l2 (green 0 to red >= 30 %, "=" ties); a click on a cell shows reference |
// model | signed error for that shape, and a click on an image probes the pixel in all three.
#include "gui/panels/panels.h"
#include "gui/widgets.h"

#include "core/text.h"
#include "mesh/suite.h"
#include "pipeline/geometry_images.h"
#include "pipeline/geometry_scoring.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace app {

namespace {

ImU32 l2Colour(double rel) {
    const double t = std::clamp(rel / 0.3, 0.0, 1.0);
    const int red = int(std::lround(255 * std::min(1.0, 2 * t)));
    const int green = int(std::lround(200 * std::min(1.0, 2 * (1 - t))));
    return IM_COL32(red, green, 96, 160);
}

// One image of `side` pixels; a click picks its pixel (the same pixel in all three images).
void pickableImage(gl::Texture& tex, const RgbaImage& img, float side, ScoreboardPanelState& ps) {
    gl::uploadRGBA8(tex, img.width, img.height, img.rgba.data());
    const ImVec2 pos = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(tex.id())),
                 ImVec2(side, side));
    if (ImGui::IsItemClicked()) {
        const ImVec2 m = ImGui::GetMousePos();
        ps.pickX = std::clamp(int((m.x - pos.x) / side * float(img.width)), 0, img.width - 1);
        ps.pickY = std::clamp(int((m.y - pos.y) / side * float(img.height)), 0, img.height - 1);
    }
    if (ps.pickX >= 0 && ps.pickX < img.width && ps.pickY >= 0 && ps.pickY < img.height) {
        const float s = side / float(img.width);
        const ImVec2 a(pos.x + float(ps.pickX) * s, pos.y + float(ps.pickY) * s);
        ImGui::GetWindowDrawList()->AddRect(
            a, ImVec2(a.x + std::max(s, 3.0f), a.y + std::max(s, 3.0f)),
            IM_COL32(255, 255, 0, 255));
    }
}

void shapeChoice(GeometryTabSettings& t) {
    if (!ImGui::CollapsingHeader("shapes")) return;
    const std::vector<std::string> suite = mesh::defaultSuite();
    for (size_t k = 0; k < suite.size(); ++k) { // three columns
        const std::string& spec = suite[k];
        bool on = std::find(t.shapes.begin(), t.shapes.end(), spec) != t.shapes.end();
        if (k % 3) ImGui::SameLine(float(230 * (k % 3)));
        if (ImGui::Checkbox(spec.c_str(), &on)) {
            if (on) {
                t.shapes.push_back(spec);
            } else {
                t.shapes.erase(std::find(t.shapes.begin(), t.shapes.end(), spec));
            }
        }
    }
}

} // namespace

void drawGeometryScores(Workbench& wb, ScoreboardPanelState& ps) {
    GeometryTabSettings& t = wb.geometryTab();
    GeometryStage& st = wb.geometry();
    setItemWidth(160, "preset");
    if (ImGui::BeginCombo("preset", t.preset.c_str())) {
        for (const material::Preset& p : wb.presets())
            if (p.unusable.empty() && ImGui::Selectable(p.name.c_str(), p.name == t.preset))
                t.preset = p.name;
        ImGui::EndCombo();
    }
    sameLineItem(80, "channel");
    ImGui::Combo("channel", &t.channel, "R\0G\0B\0");
    const StageStatus status = st.status();
    sameLineIfFits(200);
    if (status.running) {
        if (ImGui::Button("Cancel")) t.enabled = false;
        ps.geometryRun = lastItem();
        ImGui::SameLine();
        ImGui::ProgressBar(float(status.progress), ImVec2(160, 0));
    } else {
        if (ImGui::Button("Run")) t.enabled = true;
        ps.geometryRun = lastItem();
    }
    shapeChoice(t);
    // l_d of the preset and channel chosen now, before a run and after a change of either (the
    // stage knows only its last run's)
    double ld = 0;
    try {
        ld = geometryLdMm(wb.presets(), t.preset, std::clamp(t.channel, 0, 2));
    } catch (const core::Error&) {
        ld = st.ldMm();
    }
    hintText("Each model's BSSRDF-integrated image of a shape (lengths in l_d of the channel: "
             "%s) against the mesh path tracer's image; rel_l2 over the object with both "
             "images' noise removed, as `compare --geometry`. Click a cell to see its images.",
             ld > 0 ? (core::formatNumber(ld, 3) + " mm").c_str() : "none, sigma_a = 0");
    for (const auto& [name, value] : status.stats) {
        ImGui::TextDisabled("%s %s", name.c_str(), value.c_str());
        ImGui::SameLine();
    }
    ImGui::NewLine();
    const std::vector<std::string>& shapes = st.shapes();
    ps.geometryCells.clear();
    const ImGuiTableFlags flags = ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                                  ImGuiTableFlags_ScrollX | ImGuiTableFlags_SizingFixedFit;
    // as tall as its rows (a horizontally scrolled table would otherwise take the whole height)
    const float height = (float(st.models().size()) + 1) * ImGui::GetFrameHeightWithSpacing() +
                         ImGui::GetStyle().ScrollbarSize + 4;
    if (!shapes.empty() &&
        ImGui::BeginTable("geometry", int(shapes.size()) + 1, flags, ImVec2(0, height))) {
        ImGui::TableSetupColumn("model");
        for (const std::string& s : shapes)
            ImGui::TableSetupColumn(s.c_str());
        ImGui::TableHeadersRow();
        for (const std::string& model : st.models()) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(model.substr(model.rfind('/') + 1).c_str());
            for (const std::string& shape : shapes) {
                ImGui::TableNextColumn();
                const GeometryCell* c = st.cell(model, shape);
                std::string text = "...";
                if (c && !c->score.problem.empty())
                    text = "no image";
                else if (c && c->image)
                    text = (c->tie ? "=" : "") + std::to_string(c->rank) + "  " +
                           core::formatNumber(100 * c->score.relL2, 3) + " %";
                if (c && c->image && c->score.problem.empty())
                    ImGui::TableSetBgColor(ImGuiTableBgTarget_CellBg, l2Colour(c->score.relL2));
                const bool selected = ps.geometryModel == model && ps.geometryShape == shape;
                ImGui::PushID((model + "|" + shape).c_str());
                if (ImGui::Selectable(text.c_str(), selected)) {
                    ps.geometryModel = model;
                    ps.geometryShape = shape;
                }
                ps.geometryCells.emplace_back(model + "|" + shape, lastItem());
                if (c && ImGui::IsItemHovered())
                    ImGui::SetTooltip(
                        "%s", c->score.problem.empty()
                                  ? ("rel_l2 " + core::formatNumber(100 * c->score.relL2, 3) +
                                     " % +- " + core::formatNumber(100 * c->score.relL2Se, 2) +
                                     " %, mean model / reference " +
                                     core::formatNumber(c->score.meanRatio, 4) + " +- " +
                                     core::formatNumber(c->score.meanRatioSe, 2))
                                        .c_str()
                                  : c->score.problem.c_str());
                ImGui::PopID();
            }
        }
        ImGui::EndTable();
    }
    const GeometryCell* sel = st.cell(ps.geometryModel, ps.geometryShape);
    const ChannelImage* ref = st.reference(ps.geometryShape);
    if (!sel || !ref || !sel->image) return;
    const float side = std::clamp((visibleWidth() - 16) / 3, 96.0f, 320.0f);
    const double white = whitePoint(*ref);
    wrappedText("%s on %s: reference | model | signed error (model - reference) / reference, "
                "+-%s %% saturates",
                sel->model.c_str(), sel->shape.c_str(),
                core::formatNumber(100 * kGeometryErrorRange, 2).c_str());
    pickableImage(ps.tex[0], toneMapped(*ref, white), side, ps);
    ImGui::SameLine();
    pickableImage(ps.tex[1], toneMapped(*sel->image, white), side, ps);
    ImGui::SameLine();
    pickableImage(ps.tex[2], signedErrorMap(*sel->image, *ref), side, ps);
    if (ps.pickX < 0 || ps.pickX >= ref->width || ps.pickY < 0 || ps.pickY >= ref->height) return;
    const size_t p = size_t(ps.pickY) * size_t(ref->width) + size_t(ps.pickX);
    if (!ref->covered[p]) {
        ImGui::Text("pixel %d, %d: not on the object", ps.pickX, ps.pickY);
        return;
    }
    const double m = sel->image->mean[p], r = ref->mean[p];
    wrappedText("pixel %d, %d: reference %.4g +- %.2g   model %.4g +- %.2g   (model - ref) / ref "
                "%s %%",
                ps.pickX, ps.pickY, r, std::sqrt(ref->variance[p]), m,
                std::sqrt(sel->image->variance[p]),
                r > 0 ? core::formatNumber(100 * (m - r) / r, 3).c_str() : "-");
}

} // namespace app
