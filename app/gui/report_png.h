// Pictures for reports written headless (the scoreboard, `compare`): ImGui drawing calls
// rendered into an offscreen framebuffer by Dear ImGui's OpenGL3 backend and encoded as PNG, so
// the report shows the same plots and heatmaps as the panels (plot/plot_draw.h,
// gui/polar_heatmap.h), drawn by the same code.
#pragma once

#include "plot/plot.h"

#include <functional>
#include <string>
#include <vector>

namespace app {

// Renders `draw` (ImGui calls into one borderless window covering the image) at width × height
// pixels and returns the PNG bytes. Needs a current OpenGL 4.5 context; uses an ImGui context
// of its own and restores the caller's. Throws core::Error when the image cannot be made.
std::string renderImGuiPng(int width, int height, const std::function<void()>& draw);

// A plot (plot::drawPlot, no hover readout) as PNG bytes.
std::string plotPng(int width, int height, const std::vector<plot::Series>& series,
                    const plot::Axis& x, const plot::Axis& y, const std::string& title,
                    const std::string& subtitle);

// Standard base64 (RFC 4648) of `bytes`, for images embedded in a self-contained HTML page;
// written here because no packaged library of the project offers it.
std::string base64(const std::string& bytes);

} // namespace app
