// The polar heatmap of a BSSRDF slice's spatial bins (pathtrace/bssrdf_estimate.h): a disc of
// polar bins r × θs over the surface plane, both mirror halves, the beam arriving from the left
// and travelling toward +x. Drawn into the current ImGui window, so the slice panel and the
// headless scoreboard report (gui/report_png.h) show the same picture.
#pragma once

#include "pathtrace/bssrdf_estimate.h"

#include <imgui.h>

#include <functional>
#include <vector>

namespace app {

// What one heatmap shows: a value per spatial bin (NaN: none) and its colour.
struct BinValues {
    std::vector<double> v;
    std::function<ImU32(size_t)> colour;
};

// The outline of the annular sector [r0, r1] × [a, e] around c (arcs drawn as polylines).
void sectorOutline(ImDrawList* dl, ImVec2 c, float r0, float r1, float a, float e);

// A disc of polar bins (both mirror halves) in a square of `side` pixels; returns the bin under
// the mouse (-1: none) and selects it on a click.
int polarHeatmap(const char* id, float side, const pathtrace::BssrdfBins& b,
                 const BinValues& values, int& selected);

} // namespace app
