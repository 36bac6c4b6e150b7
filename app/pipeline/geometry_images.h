// Pictures of the geometry scores (geometry_scoring.h) for the reports and the Scoreboard's
// geometry tab: a channel image tone-mapped to grey (linear up to `white`, then the sRGB-like
// power 1/2.2), and the signed relative error (M − R)/R of a model image as a diverging map,
// blue where the model is too dark, red where too bright, white at 0, saturated at ±range;
// pixels that do not show the object are dark slate.
#pragma once

#include "pipeline/geometry_scoring.h"

#include <cstdint>
#include <vector>

namespace app {

inline constexpr double kGeometryErrorRange = 0.5; // ±50 % saturates the signed error map

struct RgbaImage {
    int width = 0, height = 0;
    std::vector<uint8_t> rgba;
};

// The 99th percentile of the covered pixels' means (the white point shared by a case's images).
double whitePoint(const ChannelImage& ref);
RgbaImage toneMapped(const ChannelImage& img, double white);
RgbaImage signedErrorMap(const ChannelImage& model, const ChannelImage& ref,
                         double range = kGeometryErrorRange);
// One picture of a case: the reference and each model's image in the top row, each model's
// signed error below it (the bottom-left tile is the error map's colour scale), 2 px gaps.
RgbaImage caseStrip(const ChannelImage& ref, const std::vector<const ChannelImage*>& models);

} // namespace app
