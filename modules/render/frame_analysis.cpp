// render/frame_analysis: heatmap quantities, radiance at points, brute-force exitance (see
// frame_analysis.h).
#include "render/frame_analysis.h"

#include <glm/mat4x4.hpp>

#include <algorithm>
#include <cmath>

namespace render {

std::vector<float> heatValues(const Readback& rb, HeatQuantity q,
                              const std::vector<glm::vec4>& brute, float& maxValue) {
    std::vector<float> v(rb.stats.size(), -1.0f);
    maxValue = 0;
    for (size_t p = 0; p < v.size(); ++p) {
        if (rb.position[p].w < 0.5f) continue;
        if (q == HeatQuantity::Steps) v[p] = float(rb.stats[p].x);
        if (q == HeatQuantity::StackDepth) v[p] = float(rb.stats[p].y);
        if (q == HeatQuantity::RelativeError && p < brute.size()) {
            const float b = core::luminance(glm::vec3(brute[p]));
            const float h = core::luminance(glm::vec3(rb.exitance[p]));
            v[p] = b > 0 ? std::abs(h - b) / b : 0.0f;
        }
        maxValue = std::max(maxValue, v[p]);
    }
    return v;
}

std::vector<float> radianceAtPoints(const Readback& rb, Camera cam,
                                    const std::vector<glm::vec3>& points, float tol) {
    std::vector<float> out(points.size(), -1.0f);
    if (rb.width <= 0 || rb.height <= 0) return out;
    cam.aspect = float(rb.width) / float(rb.height);
    const glm::mat4 vp = cam.projection() * cam.view();
    for (size_t i = 0; i < points.size(); ++i) {
        const glm::vec4 c = vp * glm::vec4(points[i], 1.0f);
        if (!(c.w > 0)) continue;
        const float fx = (c.x / c.w * 0.5f + 0.5f) * float(rb.width);
        const float fy = (0.5f - c.y / c.w * 0.5f) * float(rb.height);
        if (!(fx >= 0) || !(fy >= 0)) continue;
        const int x = int(fx), y = int(fy);
        if (x >= rb.width || y >= rb.height) continue;
        const size_t p = rb.index(x, y);
        if (rb.position[p].w < 0.5f) continue;
        if (glm::length(glm::vec3(rb.position[p]) - points[i]) > tol) continue;
        out[i] = core::luminance(glm::vec3(rb.hdr[p]));
    }
    return out;
}

std::vector<BssrdfPair> allPointPairs(const octree::Octree& tree, glm::vec3 xo, glm::vec3 no,
                                      float scale) {
    std::vector<BssrdfPair> pairs;
    pairs.reserve(tree.points.size());
    for (const octree::PointRecord& r : tree.points)
        pairs.push_back({scale * glm::vec3(r.positionArea[0], r.positionArea[1], r.positionArea[2]),
                         glm::vec3(r.normal[0], r.normal[1], r.normal[2]), scale * xo, no});
    return pairs;
}

glm::vec3 bruteForceExitance(const octree::Octree& tree, const std::vector<glm::vec3>& values,
                             float scale) {
    glm::vec3 sum(0.0f);
    const size_t n = std::min(values.size(), tree.points.size());
    for (size_t i = 0; i < n; ++i) {
        const octree::PointRecord& r = tree.points[i];
        const glm::vec3 w =
            glm::vec3(r.irradiance[0], r.irradiance[1], r.irradiance[2]) * r.positionArea[3];
        sum += w * (scale * scale) * values[i];
    }
    return sum;
}

std::string invalidPixelsProblem(const InvalidPixels& n) {
    if (!n.any()) return "";
    std::string out;
    auto add = [&](uint32_t count, const char* what, const char* shown) {
        if (count == 0) return;
        out += out.empty() ? "L_o is " : ", ";
        out += what;
        out += " at " + std::to_string(count);
        if (out.find(" of ") == std::string::npos)
            out += " of " + std::to_string(n.surface) + " surface pixels";
        out += shown;
    };
    add(n.nan, "NaN", " (magenta)");
    add(n.inf, "infinite", " (magenta)");
    add(n.negative, "negative", " (black)");
    return out + ": the model returned such values";
}

} // namespace render
