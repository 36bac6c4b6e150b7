// Polar heatmap of a slice's spatial bins (polar_heatmap.h).
#include "gui/polar_heatmap.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace app {

namespace {} // namespace

// The outline of the annular sector [r0, r1] × [a, e] around c (arcs drawn as polylines).
void sectorOutline(ImDrawList* dl, ImVec2 c, float r0, float r1, float a, float e) {
    const int segs = std::max(2, int(std::ceil((e - a) / (std::numbers::pi_v<float> / 48))));
    dl->PathClear();
    for (int k = 0; k <= segs; ++k) {
        const float t = a + (e - a) * float(k) / float(segs);
        dl->PathLineTo(ImVec2(c.x + r1 * std::cos(t), c.y - r1 * std::sin(t)));
    }
    for (int k = segs; k >= 0; --k) {
        const float t = a + (e - a) * float(k) / float(segs);
        dl->PathLineTo(ImVec2(c.x + r0 * std::cos(t), c.y - r0 * std::sin(t)));
    }
    dl->PathStroke(IM_COL32(255, 255, 0, 255), ImDrawFlags_Closed, 2.0f);
}

// A disc of polar bins (both mirror halves) in a square of `side` pixels; returns the bin under
// the mouse (-1: none) and selects it on a click.
int polarHeatmap(const char* id, float side, const pathtrace::BssrdfBins& b,
                 const BinValues& values, int& selected) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton(id, ImVec2(side, side));
    const ImVec2 c(p0.x + side * 0.5f, p0.y + side * 0.5f);
    const std::vector<double> edges = b.rEdges();
    const float scale = (side * 0.5f - 2.0f) / float(b.rMaxMm);
    dl->AddRectFilled(p0, ImVec2(p0.x + side, p0.y + side), IM_COL32(20, 20, 24, 255));
    const float dth = std::numbers::pi_v<float> / float(b.thetaSBins);
    const ImDrawListFlags flags = dl->Flags;
    dl->Flags &= ~ImDrawListFlags_AntiAliasedFill; // neighbouring bins meet without seams
    for (int ir = 0; ir < b.rBins; ++ir) {
        const float r0 = float(edges[size_t(ir)]) * scale,
                    r1 = float(edges[size_t(ir) + 1]) * scale;
        for (int it = 0; it < b.thetaSBins; ++it) {
            const size_t bin = size_t(ir * b.thetaSBins + it);
            const ImU32 col = values.colour(bin);
            const int segs = std::max(1, int(std::ceil(dth / (std::numbers::pi_v<float> / 48))));
            for (int k = 0; k < segs; ++k) {
                const float a = (float(it) + float(k) / float(segs)) * dth;
                const float e = (float(it) + float(k + 1) / float(segs)) * dth;
                for (float sy : {1.0f, -1.0f}) { // screen y points down: +y is up
                    auto at = [&](float r, float t) {
                        return ImVec2(c.x + r * std::cos(t), c.y - sy * r * std::sin(t));
                    };
                    dl->AddQuadFilled(at(r0, a), at(r1, a), at(r1, e), at(r0, e), col);
                }
            }
        }
    }
    dl->Flags = flags;
    dl->AddCircle(c, float(b.rMaxMm) * scale, IM_COL32(150, 150, 150, 255), 64);
    // the beam: from the left, toward +x
    dl->AddLine(ImVec2(p0.x + 4, c.y), ImVec2(c.x - 4, c.y), IM_COL32(255, 255, 255, 160), 1.5f);
    dl->AddTriangleFilled(ImVec2(c.x - 3, c.y), ImVec2(c.x - 10, c.y - 4),
                          ImVec2(c.x - 10, c.y + 4), IM_COL32(255, 255, 255, 200));
    int hovered = -1;
    if (ImGui::IsItemHovered() || ImGui::IsItemClicked()) {
        const ImVec2 m = ImGui::GetMousePos();
        const double x = (m.x - c.x) / scale, y = (c.y - m.y) / scale;
        const double r = std::hypot(x, y);
        if (r < b.rMaxMm && r >= edges.front()) {
            const int ir = int(std::upper_bound(edges.begin(), edges.end(), r) - edges.begin()) - 1;
            const double th = std::atan2(std::abs(y), x);
            const int it = std::clamp(int(th / dth), 0, b.thetaSBins - 1);
            if (ir >= 0 && ir < b.rBins) hovered = ir * b.thetaSBins + it;
        }
        if (ImGui::IsItemClicked() && hovered >= 0) selected = hovered;
    }
    if (selected >= 0 && selected < b.spatialBins()) { // outline the selected bin (upper half)
        const int ir = selected / b.thetaSBins, it = selected % b.thetaSBins;
        const float r0 = float(edges[size_t(ir)]) * scale,
                    r1 = float(edges[size_t(ir) + 1]) * scale;
        sectorOutline(dl, c, r0, r1, float(it) * dth, float(it + 1) * dth);
    }
    return hovered;
}

} // namespace app
