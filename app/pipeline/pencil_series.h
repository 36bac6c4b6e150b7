// The path-traced reference as a plot series (with a ±2σ band) and the error figures of a
// model curve against it (shown per model in the pencil plot legend).
#pragma once

#include "plot/plot.h"
#include "pipeline/reference_stage.h"

namespace app {

// R_d(r)/(1 − R_sp): MCML's R_d renormalised to unit power entering the medium, the
// convention of the models' Bssrdf(). channel 0..2, or 3 for Rec.709 luminance (channels are
// independent runs, so variances add with the squared weights).
plot::Series referenceSeries(const ReferenceSnapshot& snap, int channel, bool rTimesR);

struct ModelError {
    bool valid = false;
    double relL2 = 0;    // sqrt(Σ(model − ref)²) / sqrt(Σ ref²) over the reference bins
    double ratioAt1 = 0; // model / reference at r = 1 l_d (nearest bin)
    double ratioAt4 = 0; // ... at r = 4 l_d
};
ModelError modelError(const plot::Series& model, const plot::Series& reference, double ld);

} // namespace app
