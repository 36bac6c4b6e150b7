// render/frame_analysis (no GL): heatmap quantities, the radiance the camera sees at points,
// and the brute-force exitance sum, on small hand-made frames and clouds.
#include "render/frame_analysis.h"

#include <gtest/gtest.h>

#include <glm/mat4x4.hpp>

#include <cmath>

namespace {

// A 4×2 frame: pixel (x, y) shows surface iff x != 3; stats (steps, depth, flags).
render::Readback frame() {
    render::Readback rb;
    rb.width = 4;
    rb.height = 2;
    const size_t n = 8;
    rb.hdr.assign(n, glm::vec4(0));
    rb.exitance.assign(n, glm::vec4(0));
    rb.stats.assign(n, glm::uvec4(0));
    rb.position.assign(n, glm::vec4(0));
    rb.normal.assign(n, glm::vec4(0));
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) {
            const size_t p = rb.index(x, y);
            rb.position[p].w = x != 3 ? 1.0f : 0.0f;
            rb.stats[p] = glm::uvec4(10 * x + y, x + 2 * y, 0, 0);
            rb.exitance[p] = glm::vec4(float(x + 1), float(x + 1), float(x + 1), 1);
        }
    return rb;
}

} // namespace

TEST(FrameAnalysis, HeatValuesPerQuantity) {
    const render::Readback rb = frame();
    float mx = -1;
    auto steps = render::heatValues(rb, render::HeatQuantity::Steps, {}, mx);
    EXPECT_EQ(steps[rb.index(2, 1)], 21.0f);
    EXPECT_EQ(steps[rb.index(3, 0)], -1.0f); // background
    EXPECT_EQ(mx, 21.0f);
    auto depth = render::heatValues(rb, render::HeatQuantity::StackDepth, {}, mx);
    EXPECT_EQ(depth[rb.index(1, 1)], 3.0f);
    EXPECT_EQ(mx, 4.0f);
    // relative error against a brute-force image twice as bright on the left half
    std::vector<glm::vec4> brute(rb.exitance);
    for (int y = 0; y < 2; ++y)
        brute[rb.index(0, y)] *= 2.0f;
    auto err = render::heatValues(rb, render::HeatQuantity::RelativeError, brute, mx);
    EXPECT_FLOAT_EQ(err[rb.index(0, 0)], 0.5f);
    EXPECT_FLOAT_EQ(err[rb.index(1, 0)], 0.0f);
    EXPECT_EQ(err[rb.index(3, 0)], -1.0f);
    EXPECT_FLOAT_EQ(mx, 0.5f);
    // no brute-force image: no value anywhere
    err = render::heatValues(rb, render::HeatQuantity::RelativeError, {}, mx);
    for (float v : err)
        EXPECT_EQ(v, -1.0f);
    EXPECT_EQ(mx, 0.0f);
}

// A frame rendered from a camera: each pixel's surface point is the unprojected pixel centre
// at depth 1 in front of the camera, L_o = pixel index. Points on those surfaces read their
// pixel's luminance; points off the surface, behind the camera or outside read −1.
TEST(FrameAnalysis, RadianceAtPointsSeesOnlyTheVisibleSurface) {
    render::Camera cam;
    cam.distance = 3.0f;
    render::Readback rb;
    rb.width = 8;
    rb.height = 6;
    cam.aspect = float(rb.width) / float(rb.height);
    const glm::mat4 inv = glm::inverse(cam.projection() * cam.view());
    const size_t n = size_t(rb.width * rb.height);
    rb.hdr.resize(n);
    rb.position.resize(n);
    std::vector<glm::vec3> centres(n);
    for (int y = 0; y < rb.height; ++y)
        for (int x = 0; x < rb.width; ++x) {
            const float ndcX = (float(x) + 0.5f) / float(rb.width) * 2.0f - 1.0f;
            const float ndcY = 1.0f - (float(y) + 0.5f) / float(rb.height) * 2.0f;
            glm::vec4 w = inv * glm::vec4(ndcX, ndcY, 0.5f, 1.0f);
            const size_t p = rb.index(x, y);
            centres[p] = glm::vec3(w) / w.w;
            rb.position[p] = glm::vec4(centres[p], 1.0f);
            rb.hdr[p] = glm::vec4(float(p), float(p), float(p), 1.0f);
        }
    rb.position[rb.index(2, 2)].w = 0; // background there
    std::vector<glm::vec3> pts = {
        centres[rb.index(5, 1)], centres[rb.index(0, 4)], centres[rb.index(2, 2)],
        0.5f * (centres[rb.index(5, 1)] + cam.position()), cam.position() * 2.0f - cam.target};
    const std::vector<float> L = render::radianceAtPoints(rb, cam, pts, 1e-3f);
    EXPECT_FLOAT_EQ(L[0], float(rb.index(5, 1)));
    EXPECT_FLOAT_EQ(L[1], float(rb.index(0, 4)));
    EXPECT_EQ(L[2], -1.0f); // background pixel
    EXPECT_EQ(L[3], -1.0f); // in front of the visible surface: hidden from it by tolerance
    EXPECT_EQ(L[4], -1.0f); // behind the camera
}

TEST(FrameAnalysis, BruteForceExitanceSumsEveryPoint) {
    octree::Octree t;
    t.points.resize(3);
    for (int i = 0; i < 3; ++i) {
        octree::PointRecord& r = t.points[size_t(i)];
        r.positionArea[0] = float(i);
        r.positionArea[1] = r.positionArea[2] = 0;
        r.positionArea[3] = 0.5f * float(i + 1); // area
        r.normal[0] = r.normal[1] = 0;
        r.normal[2] = 1;
        r.irradiance[0] = 1;
        r.irradiance[1] = 2;
        r.irradiance[2] = 3;
    }
    const float scale = 2.0f;
    const auto pairs = render::allPointPairs(t, glm::vec3(0.5f, 0, 0), glm::vec3(0, 0, 1), scale);
    ASSERT_EQ(pairs.size(), 3u);
    EXPECT_EQ(pairs[2].xi, glm::vec3(4, 0, 0)); // scaled to mm
    EXPECT_EQ(pairs[2].xo, glm::vec3(1, 0, 0));
    EXPECT_EQ(pairs[1].wi, glm::vec3(0, 0, 1));
    const std::vector<glm::vec3> S = {{1, 1, 1}, {2, 2, 2}, {0, 0, 4}};
    // Σ E A scale² S: areas 0.5, 1, 1.5; scale² = 4
    const glm::vec3 m = render::bruteForceExitance(t, S, scale);
    EXPECT_FLOAT_EQ(m.x, 4 * (1 * 0.5f * 1 + 1 * 1.0f * 2));
    EXPECT_FLOAT_EQ(m.y, 4 * (2 * 0.5f * 1 + 2 * 1.0f * 2));
    EXPECT_FLOAT_EQ(m.z, 4 * (3 * 0.5f * 1 + 3 * 1.0f * 2 + 3 * 1.5f * 4));
}
