// Images of the texture-space stages (seed 004 Fig. 3.3 and 3.10) for the Render panel, the
// `render --stage-images` output and captures: RGBA8, row 0 at the top = v near 1 (the texture
// as it is usually drawn). Pure CPU, no algorithms beyond display mappings.
//   E′ (eq. 3.2): luminance-preserving exposure so the 99th percentile of the covered texels'
//     luminance maps to 1, then gamma 2.2; texels no triangle covers are dark blue-grey.
//   CDF level l (Fig. 3.3b): the mip level's sums, log10 over four decades below its maximum,
//     on the sequential colour map; zero sums black.
//   Atlas: per texel its triangle's stretch σ1/σ2 on the sequential map (1 dark … 4 and more
//     bright), a chequer of grey by triangle parity so the layout shows; uncovered black.
//   Samples: the E′ image darkened, each drawn texel in bright green.
#pragma once

#include "texspace/pipeline.h"

#include <cstdint>
#include <vector>

namespace app {

struct Rgba8Image {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;
};

Rgba8Image eprimeImage(const texspace::Pipeline& p);
Rgba8Image cdfLevelImage(const texspace::MipCdf& cdf, int level);
Rgba8Image atlasImage(const texspace::Pipeline& p);
Rgba8Image samplesImage(const texspace::Pipeline& p, const texspace::SampleSet& set);

} // namespace app
