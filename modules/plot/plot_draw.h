// plot/plot_draw.h: drawPlot(), the ImGui widget of the pencil plot (thesis §3.6.3) — the only
// part of the plot module that sees ImGui, included by app/ only. It draws into the current
// window's ImDrawList inside an InvisibleButton, so it works in any ImGui window and also
// headless (no GL needed to build the draw lists). Axes, ticks, hover sampling and the
// clipped geometry come from the pure half (plot/plot.h, plot/detail/geometry.h).
#pragma once

#include "plot/plot.h"

#include <imgui.h>

#include <string>
#include <vector>

namespace plot {

// ---- drawing (plot_draw.cpp) --------------------------------------------------------------
struct PlotOptions {
    bool legend = true;       // legend box in the top-right corner of the plot area
    bool hoverTooltip = true; // crosshair + dots + tooltip table while hovered
};

struct PlotState {
    bool hovered = false;       // mouse over the plot area (inside the axes)
    double hoverX = 0;          // data x under the mouse (valid when hovered)
    std::vector<HoverRow> rows; // sampleAt(series, hoverX) (filled when hovered)
    ImVec2 min, max;            // screen rect of the whole widget incl. axes (PNG export)
    ImVec2 plotMin, plotMax;    // screen rect of the data area
};

// Draws title, subtitle (e.g. the normalisation convention), axes, grid, bands, curves,
// legend and hover readout into the current window and advances the layout by `size`.
// size.x <= 0 or size.y <= 0: use the available content region on that axis.
// The axes are used as given (after sanitized()); call autoRange() for automatic ranges.
PlotState drawPlot(const char* id, ImVec2 size, const std::vector<Series>& series,
                   const Axis& xAxis, const Axis& yAxis, const std::string& title,
                   const std::string& subtitle, const PlotOptions& options = {});

// `text` as it fits `width` in the current font: whole, or cut at a character (UTF-8) with
// "..." so that it says it was cut (a title over a narrow plot; the app's labels).
std::string elided(std::string text, float width);

} // namespace plot
