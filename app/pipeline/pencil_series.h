// What the pencil plot (thesis 3.6.3) draws, made from the workbench's state and no ImGui: one
// series per visible model (or R, G, B of the soloed one) with its colour and line style, the
// path-traced reference as a series with a ±2σ band, the error figures of a model curve against
// it (shown per model in the legend, the Scoreboard's rel_err), and the hybrid's R_p markers.
#pragma once

#include "pipeline/reference_stage.h"
#include "pipeline/workbench.h"
#include "plot/plot.h"

#include <cstdint>
#include <string>
#include <vector>

namespace app {

// R_d(r)/(1 − R_sp): MCML's R_d renormalised to unit power entering the medium, the
// convention of the models' Bssrdf(). channel 0..2, or 3 for Rec.709 luminance (channels are
// independent runs, so variances add with the squared weights).
plot::Series referenceSeries(const ReferenceSnapshot& snap, int channel, bool rTimesR);

// The error figures of a model on a channel (0..2) are the Scoreboard stage's row: the same
// rel_err as the Scoreboard panel and `compare` (pipeline/scoring.h); nullptr while not scored.
const ScoreboardRow* scoreOf(const Workbench& wb, const std::string& displayPath, int channel);
// "rel_err 3.1 % ± 0.2 %  ratio@1ld 1.02  @4ld 0.98" of a row, and the tooltip that says what
// rel_err is, over which radii and of which channel.
std::string errorFigures(const capture::ScoreRow& r);
std::string errorTooltip(const ScoreboardRow& r);

// The plot's series for the current settings (one per visible model, or R/G/B when soloed),
// then the path-traced reference when enabled; model labels carry their rel_err against it per
// channel (on the luminance plot, each of R, G, B), their tooltips its definition. Each series
// is compared with (plot::Series::compareTo) the path-traced reference, or with the model
// plot.compare_with names where comparesWithModel.
std::vector<plot::Series> plotSeries(const Workbench& wb);
// plot.compare_with names a model the plot shows (not soloed, visible, evaluated).
bool comparesWithModel(const Workbench& wb);

// R_p of the hybrid (texspace/hybrid.h) for the pencil plot's marker: the soloed model's three
// channels, else the Render panel's model on the plot's channel (not luminance), from the
// plotted profile and texture_space.local.lower_bound.
struct RpMarker {
    double rMm;
    uint32_t color;
    std::string label;
};
std::vector<RpMarker> hybridRpMarkers(const Workbench& wb);

// The units of the plotted profile (the plot's axis note, the `profile` CSV's header).
std::string normalisationNote();

} // namespace app
