// core/color.h: the luminance of linear RGB with the Rec. 709 (sRGB) primaries,
// Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6, item 3.2). The one scalar the
// swatches (thesis 3.6.1), heatmaps, environment sampling and the reference plot show.
// Shaders keep their own GLSL copy.
#pragma once

#include <glm/vec3.hpp>

#include <array>

namespace core {

inline constexpr std::array<double, 3> kRec709Luminance = {0.2126, 0.7152, 0.0722};

inline double luminance(const glm::dvec3& rgb) {
    return kRec709Luminance[0] * rgb.r + kRec709Luminance[1] * rgb.g + kRec709Luminance[2] * rgb.b;
}
// Float arithmetic for float images (the same weights, rounded to float).
inline float luminance(const glm::vec3& rgb) {
    return float(kRec709Luminance[0]) * rgb.r + float(kRec709Luminance[1]) * rgb.g +
           float(kRec709Luminance[2]) * rgb.b;
}

} // namespace core
