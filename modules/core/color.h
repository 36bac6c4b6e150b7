// core/color.h: the luminance of linear RGB with the Rec. 709 (sRGB) primaries,
// Y = 0.2126 R + 0.7152 G + 0.0722 B (ITU-R BT.709-6, item 3.2). The one scalar the
// swatches (thesis 3.6.1), heatmaps, environment sampling and the reference plot show.
// Shaders keep their own GLSL copy. Also the sequential colour ramp of the scalar views
// (point attributes, octree levels, replay differences).
#pragma once

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include <algorithm>

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

// t in [0, 1] (clamped) → RGB in [0, 1]: dark blue → teal → green → yellow.
inline glm::vec3 colorRamp(float t) {
    static constexpr glm::vec3 stops[5] = {{0.15f, 0.10f, 0.45f},
                                           {0.15f, 0.35f, 0.60f},
                                           {0.12f, 0.60f, 0.55f},
                                           {0.45f, 0.80f, 0.30f},
                                           {0.99f, 0.90f, 0.15f}};
    if (!(t > 0)) return stops[0];
    if (t >= 1) return stops[4];
    const float x = t * 4.0f;
    const int k = std::min(int(x), 3);
    return glm::mix(stops[k], stops[k + 1], x - float(k));
}

} // namespace core
