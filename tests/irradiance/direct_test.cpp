// irradiance, directional and filtered lights (thesis 3.3.2, Fig. 3.3), headless GL:
//   - unoccluded convex sphere: E_t = E0·Ft(n·L)·max(0, n·L) per point for the three offset
//     filters; the naive filter gives either that or 0 (acne); back-facing points exactly 0.
//     Points whose projection lies within 4 shadow-map texels of the silhouette are only checked
//     to lie in [0, closed form]: there the filters' footprints (up to 1.234·1.5 + √2 ≈ 3.3
//     texels for the jittered PCF) reach the silhouette and the slope-scaled offset is capped
//     (tan θ <= 10), so partial shadowing is expected.
//   - a plate above a box: points in the plate's shadow get 0 and lit points the closed form
//     with the offset filters; the naive filter wrongly shadows a measurable fraction of the lit
//     points (acne, Fig. 3.3 a) and the offset filters none. Points whose light ray passes
//     within 5 texels of the plate's outline are skipped (the shadow edge is blurred by design).
//   - the visibility spread (Stage::visibilitySpread) bounds V from maps moved rigidly and from
//     maps whose vertices each moved on their own.
//   - filtered light: the projected texture value at the documented light-space uv
//     (light_frame.h), bilinear, clamped; the default checker.
#include "gl_stage.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace {
using namespace irradiance;

const glm::vec3 kE0(1.0f, 0.5f, 0.25f);

glm::vec3 closedForm(const glm::vec3& n, const glm::vec3& L, double eta) {
    const double c = glm::dot(n, L);
    return kE0 * static_cast<float>(irrtest::ft(c, eta) * std::max(c, 0.0));
}

bool matches(const glm::vec3& got, const glm::vec3& want) {
    for (int c = 0; c < 3; ++c)
        if (std::abs(got[c] - want[c]) > 1e-5f * want[c] + 1e-7f) return false;
    return true;
}

// The documented light basis (light_frame.h), recomputed here.
struct Basis {
    glm::vec3 u, v, w;
};
Basis basis(glm::vec3 L) {
    Basis b;
    b.w = glm::normalize(L);
    const glm::vec3 a = std::abs(b.w.y) > 0.999f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
    b.u = glm::normalize(glm::cross(a, b.w));
    b.v = glm::cross(b.w, b.u);
    return b;
}

TEST(IrradianceDirectional, ConvexSphereMatchesClosedFormForAllFilters) {
    Stage& st = irrtest::stage();
    const mesh::Mesh m = mesh::makeUvSphere(48, 96);
    const auto P = irrtest::vertexPositions(m), N = irrtest::vertexNormals(m);
    st.setScene(m, P, N);
    Settings s;
    s.mode = LightMode::Directional;
    s.direction = glm::vec3(0.3f, 0.8f, 0.5f) * 3.0f; // any length
    s.irradiance = kE0;
    s.shadowMapSize = 512;
    s.ior = 1.4f;
    const glm::vec3 L = glm::normalize(s.direction);
    const double texel = 2.0 * 1.02 * 0.5 / 512; // bounding radius 0.5
    for (ShadowFilter f : {ShadowFilter::Naive, ShadowFilter::Offset, ShadowFilter::OffsetPcf,
                           ShadowFilter::OffsetPcfJitter}) {
        s.filter = f;
        const auto E = st.compute(s);
        ASSERT_EQ(E.size(), P.size());
        int checked = 0, acne = 0, lit = 0;
        for (size_t i = 0; i < P.size(); ++i) {
            const double c = glm::dot(N[i], L);
            const glm::vec3 want = closedForm(N[i], L, s.ior);
            if (c <= 0) {
                EXPECT_EQ(E[i], glm::vec3(0.0f)) << i;
                continue;
            }
            const double toSilhouette = 0.5 * (1.0 - std::sqrt(1.0 - c * c));
            if (toSilhouette < 4 * texel) { // near the terminator: a partial visibility
                for (int k = 0; k < 3; ++k)
                    EXPECT_TRUE(E[i][k] >= 0 && E[i][k] <= want[k] * (1 + 1e-5f) + 1e-7f) << i;
                continue;
            }
            ++checked;
            if (f == ShadowFilter::Naive && E[i] == glm::vec3(0.0f)) {
                ++acne;
                continue;
            }
            ++lit;
            EXPECT_TRUE(matches(E[i], want))
                << "filter " << int(f) << " point " << i << " got " << E[i].r << " want " << want.r;
        }
        EXPECT_GT(checked, 1500);
        if (f == ShadowFilter::Naive) {
            std::printf("naive filter on the sphere: %d of %d lit points in acne\n", acne, checked);
            EXPECT_GT(lit, 0);
        }
    }
    EXPECT_EQ(st.lastLightFrame().w, L);
}

// Plate (0.4 × 0.05 × 0.4, y in [0.075, 0.125]) above a box (1 × 0.2 × 1, top at y = −0.2).
struct PlateScene {
    mesh::Mesh mesh;
    std::vector<glm::vec3> P, N;
    glm::vec3 plateLo{-0.2f, 0.075f, -0.2f}, plateHi{0.2f, 0.125f, 0.2f};
};
PlateScene plateScene() {
    PlateScene sc;
    sc.mesh = {};
    irrtest::append(sc.mesh, mesh::makeBox(1, 0.2, 1), glm::vec3(0, -0.3f, 0));
    irrtest::append(sc.mesh, mesh::makeBox(0.4, 0.05, 0.4), glm::vec3(0, 0.1f, 0));
    uint32_t r = 12345;
    auto jitter = [&] {
        r = r * 1664525u + 1013904223u;
        return static_cast<float>((r >> 8) * (1.0 / 16777216.0)) - 0.5f;
    };
    for (int i = 0; i < 40; ++i)
        for (int j = 0; j < 40; ++j) {
            const float x = -0.48f + 0.96f * (i + 0.5f + 0.8f * jitter()) / 40;
            const float z = -0.48f + 0.96f * (j + 0.5f + 0.8f * jitter()) / 40;
            sc.P.emplace_back(x, -0.2f, z);
            sc.N.emplace_back(0, 1, 0);
        }
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) {
            sc.P.emplace_back(-0.18f + 0.36f * (i + 0.5f) / 10, 0.125f,
                              -0.18f + 0.36f * (j + 0.5f) / 10);
            sc.N.emplace_back(0, 1, 0);
        }
    return sc;
}

// Does the ray q + tL, t > 0, hit the box [lo, hi]? (slab test)
bool hitsBox(glm::dvec3 q, glm::dvec3 L, glm::dvec3 lo, glm::dvec3 hi) {
    double t0 = 1e-9, t1 = 1e30;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(L[a]) < 1e-12) {
            if (q[a] < lo[a] || q[a] > hi[a]) return false;
            continue;
        }
        double ta = (lo[a] - q[a]) / L[a], tb = (hi[a] - q[a]) / L[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    return t0 <= t1;
}

double boundingRadius(const mesh::Mesh& m) {
    glm::dvec3 lo(1e30), hi(-1e30);
    for (const auto& v : m.vertices) {
        lo = glm::min(lo, glm::dvec3(v[0], v[1], v[2]));
        hi = glm::max(hi, glm::dvec3(v[0], v[1], v[2]));
    }
    const glm::dvec3 c = 0.5 * (lo + hi);
    double r = 0;
    for (const auto& v : m.vertices)
        r = std::max(r, glm::length(glm::dvec3(v[0], v[1], v[2]) - c));
    return r;
}

// The plate scene's light: directional, oblique, a 512² shadow map.
Settings plateLight() {
    Settings s;
    s.mode = LightMode::Directional;
    s.direction = glm::vec3(0.3f, 1.0f, 0.2f);
    s.irradiance = kE0;
    s.shadowMapSize = 512;
    return s;
}

TEST(IrradianceDirectional, PlateShadowsTheBoxAndOffsetRemovesAcne) {
    Stage& st = irrtest::stage();
    const PlateScene sc = plateScene();
    st.setScene(sc.mesh, sc.P, sc.N);
    Settings s = plateLight();
    const glm::dvec3 L = glm::normalize(glm::dvec3(s.direction));
    const Basis b = basis(glm::vec3(L));
    const double margin = 5 * 2.0 * 1.02 * boundingRadius(sc.mesh) / 512;
    std::vector<int> state(sc.P.size()); // 0 lit, 1 shadowed, -1 near the shadow edge
    int nLit = 0, nShadow = 0;
    for (size_t i = 0; i < sc.P.size(); ++i) {
        const glm::dvec3 q(sc.P[i]);
        const bool sh = hitsBox(q, L, sc.plateLo, sc.plateHi);
        bool edge = false;
        for (int k = 0; k < 16; ++k) {
            const double a = k * std::numbers::pi / 8;
            const glm::dvec3 d =
                margin * (std::cos(a) * glm::dvec3(b.u) + std::sin(a) * glm::dvec3(b.v));
            edge |= hitsBox(q + d, L, sc.plateLo, sc.plateHi) != sh;
        }
        state[i] = edge ? -1 : (sh ? 1 : 0);
        nLit += state[i] == 0;
        nShadow += state[i] == 1;
    }
    ASSERT_GT(nShadow, 100);
    ASSERT_GT(nLit, 500);
    int wrongNaive = -1;
    for (ShadowFilter f : {ShadowFilter::Naive, ShadowFilter::Offset, ShadowFilter::OffsetPcf,
                           ShadowFilter::OffsetPcfJitter}) {
        s.filter = f;
        const auto E = st.compute(s);
        int wrong = 0;
        for (size_t i = 0; i < sc.P.size(); ++i) {
            const glm::vec3 want = closedForm(sc.N[i], glm::vec3(L), s.ior);
            if (state[i] == 1) {
                EXPECT_EQ(E[i], glm::vec3(0.0f)) << "filter " << int(f) << " point " << i;
            } else if (state[i] == 0) {
                if (!matches(E[i], want)) {
                    ++wrong;
                    if (f == ShadowFilter::Naive) {
                        EXPECT_EQ(E[i], glm::vec3(0.0f)) << i;
                    }
                }
            }
        }
        if (f == ShadowFilter::Naive) {
            wrongNaive = wrong;
            std::printf("naive filter on the plate scene: %d of %d lit points in acne\n", wrong,
                        nLit);
            EXPECT_GT(wrong, nLit / 20); // acne: more than 5 % of the lit points
        } else {
            EXPECT_EQ(wrong, 0) << "filter " << int(f);
            EXPECT_LT(wrong, wrongNaive);
        }
    }

    // E_t as its two factors (what a capture records, each within its own precision): the
    // unshadowed E_u (filter none) is the closed form at every point, the plate's shadow
    // included; V is 0 in the shadow, 1 where lit and between at the blurred edge; E_u·V is E_t
    // to float rounding, and the result buffer holds E_t afterwards.
    s.filter = ShadowFilter::OffsetPcfJitter;
    const std::vector<glm::vec3> Et = st.compute(s);
    const Stage::Factors fs = st.factors(s);
    ASSERT_EQ(fs.unshadowed.size(), sc.P.size());
    ASSERT_EQ(fs.visibility.size(), sc.P.size());
    int partial = 0;
    for (size_t i = 0; i < sc.P.size(); ++i) {
        const float V = fs.visibility[i];
        EXPECT_TRUE(matches(fs.unshadowed[i], closedForm(sc.N[i], glm::vec3(L), s.ior))) << i;
        EXPECT_TRUE(V >= 0.0f && V <= 1.0f) << i << ": V " << V;
        if (state[i] == 1) {
            EXPECT_EQ(V, 0.0f) << i;
        } else if (state[i] == 0) {
            EXPECT_EQ(V, 1.0f) << i;
        }
        partial += state[i] == -1 && V > 0.0f && V < 1.0f;
        for (int c = 0; c < 3; ++c) // the shader's product last: a replay forms E_t so
            EXPECT_EQ(Et[i][c], fs.unshadowed[i][c] * V) << i;
    }
    EXPECT_GT(partial, 10);
    std::vector<glm::vec4> buffer(sc.P.size());
    glGetNamedBufferSubData(st.resultBuffer(), 0,
                            static_cast<GLsizeiptr>(buffer.size() * sizeof(glm::vec4)),
                            buffer.data());
    for (size_t i = 0; i < sc.P.size(); ++i)
        EXPECT_EQ(glm::vec3(buffer[i]), Et[i]) << i;
    s.mode = LightMode::Ibl; // no visibility factor
    EXPECT_THROW(st.factors(s), core::Error);
}

// The rgb of the stage's result buffer (what the last compute left there).
std::vector<glm::vec3> readResultRgb(Stage& st, size_t n) {
    std::vector<glm::vec4> buffer(n);
    glGetNamedBufferSubData(st.resultBuffer(), 0,
                            static_cast<GLsizeiptr>(buffer.size() * sizeof(glm::vec4)),
                            buffer.data());
    return std::vector<glm::vec3>(buffer.begin(), buffer.end());
}

// What a capture allows V on another driver beyond the samplers' weights
// (Stage::visibilitySpread): the shadow map drawn to each of rasterShifts(), the corners and the
// edges' midpoints of the square of ±kRasterShiftTexels. For every filter with a shadow map: 0
// wherever V does not change near the point (lit points far from the plate's shadow, points deep in
// it), positive along the shadow's edge (and at the naive filter's acne, which depends on where the
// rasteriser put the depths), and every point's V from maps drawn 0.04 texel aside (the offset an
// NVIDIA H200's G-buffer had from llvmpipe's) in three directions lies within it; and the calls
// leave compute(s)'s result.
TEST(IrradianceDirectional, TheVisibilitySpreadBoundsAShadowMapDrawnElsewhere) {
    Stage& st = irrtest::stage();
    const PlateScene sc = plateScene();
    st.setScene(sc.mesh, sc.P, sc.N);
    Settings s = plateLight();
    for (ShadowFilter f : {ShadowFilter::Naive, ShadowFilter::Offset, ShadowFilter::OffsetPcf,
                           ShadowFilter::OffsetPcfJitter}) {
        s.filter = f;
        const std::vector<glm::vec3> e = st.compute(s);
        const std::vector<float> spread = st.visibilitySpread(s);
        ASSERT_EQ(spread.size(), sc.P.size());
        EXPECT_EQ(st.computeShifted(s, glm::vec2(0.0f)).size(), sc.P.size());
        const std::vector<glm::vec3> again = readResultRgb(st, sc.P.size());
        EXPECT_EQ(again, e) << "the spread leaves compute(s)'s result";
        const std::vector<glm::vec4> v = st.computeShifted(s, glm::vec2(0.0f));
        int edge = 0, beyond = 0, moved = 0;
        double worst = 0;
        for (const glm::vec2 shift :
             {glm::vec2(0.04f, 0.0f), glm::vec2(-0.03f, 0.03f), glm::vec2(0.028f, -0.028f)}) {
            const std::vector<glm::vec4> w = st.computeShifted(s, shift);
            for (size_t i = 0; i < v.size(); ++i) {
                const double d = std::abs(double(w[i].w) - v[i].w);
                moved += d > kVisibilityTolerance;
                worst = std::max(worst, d);
                EXPECT_LE(d, spread[i] + 1e-6) << "filter " << int(f) << " point " << i << " shift "
                                               << shift.x << "," << shift.y << " V " << v[i].w;
            }
        }
        for (size_t i = 0; i < v.size(); ++i) {
            edge += spread[i] > 0;
            beyond += spread[i] > kVisibilityTolerance;
        }
        if (f != ShadowFilter::Offset) { // its hard edge passes within 1/16 texel of no point
            EXPECT_GT(edge, 0) << "filter " << int(f);
        }
        EXPECT_LT(edge, int(v.size()) / 4) << "filter " << int(f); // the edge (and acne) only
        std::printf("filter %d: spread > 0 at %d of %zu points, > 2^-7 at %d; maps 0.04 texel "
                    "aside moved V past 2^-7 %d times, worst %.4f\n",
                    int(f), edge, v.size(), beyond, moved, worst);
    }
}

// rasterShifts() moves the whole map; a driver snaps each vertex on its own, which turns edges
// and tilts the depth planes no rigid move does. Emulated on the bunny (Stage::setVertexSnap:
// every vertex moved on its own by up to kRasterShiftTexels along both image axes and 8 ulps of
// depth, the interpolation's rounding): for every filter, two light directions and two map
// sizes, every point's V stays within visibilitySpread (the same sampler, so to 1e-6), though
// the moves change V at hundreds of points, most by more than the samplers' 2^-7. Moves four
// times larger fail.
TEST(IrradianceDirectional, TheVisibilitySpreadBoundsAMapWhoseVerticesSnapApart) {
    Stage& st = irrtest::stage();
    const irrtest::PointsOnMesh sc = irrtest::bunnyPoints();
    st.setScene(sc.mesh, sc.P, sc.N);
    int moved = 0, past = 0, beyond = 0;
    for (const int size : {256, 1024})
        for (const glm::vec3 dir : {glm::vec3(0.3f, 1.0f, 0.2f), glm::vec3(-0.6f, 0.5f, 0.7f)})
            for (const ShadowFilter f : {ShadowFilter::Naive, ShadowFilter::Offset,
                                         ShadowFilter::OffsetPcf, ShadowFilter::OffsetPcfJitter}) {
                Settings s = plateLight();
                s.direction = dir;
                s.shadowMapSize = size;
                s.filter = f;
                const std::vector<float> spread = st.visibilitySpread(s);
                const std::vector<glm::vec4> v = st.computeShifted(s, glm::vec2(0.0f));
                for (const uint32_t seed : {1u, 2u}) {
                    st.setVertexSnap({kRasterShiftTexels, 8.0f, seed});
                    const std::vector<glm::vec4> w = st.computeShifted(s, glm::vec2(0.0f));
                    st.setVertexSnap({4.0f * kRasterShiftTexels, 8.0f, seed});
                    const std::vector<glm::vec4> far = st.computeShifted(s, glm::vec2(0.0f));
                    st.setVertexSnap({});
                    for (size_t i = 0; i < v.size(); ++i) {
                        const double d = std::abs(double(w[i].w) - v[i].w);
                        moved += d > 0;
                        past += d > kVisibilityTolerance;
                        beyond += std::abs(double(far[i].w) - v[i].w) > spread[i] + 1e-6;
                        EXPECT_LE(d, spread[i] + 1e-6)
                            << "size " << size << " filter " << int(f) << " seed " << seed
                            << " point " << i << " V " << v[i].w << " moved " << w[i].w;
                    }
                }
            }
    EXPECT_GT(past, 100) << "the emulation moves too little to show anything";
    EXPECT_GT(beyond, 100) << "moves four times larger stay within the spread too";
    std::printf("vertices snapped apart by up to 1/16 texel: V changed %d times, past 2^-7 %d "
                "times, each within the rigid moves' spread; at 1/4 texel %d past it\n",
                moved, past, beyond);
}

// Bilinear lookup with clamp-to-edge of an RGB image (row 0 = top = v near 1).
glm::vec3 bilinear(const std::vector<float>& img, int W, int H, glm::vec2 uv) {
    auto texel = [&](int i, int j) { // GL texel (i, j), j = 0 the bottom row
        i = std::clamp(i, 0, W - 1);
        j = std::clamp(j, 0, H - 1);
        const size_t k = 3 * (static_cast<size_t>(H - 1 - j) * W + i);
        return glm::vec3(img[k], img[k + 1], img[k + 2]);
    };
    const float x = uv.x * W - 0.5f, y = uv.y * H - 0.5f;
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const float fx = x - x0, fy = y - y0;
    return (1 - fx) * (1 - fy) * texel(x0, y0) + fx * (1 - fy) * texel(x0 + 1, y0) +
           (1 - fx) * fy * texel(x0, y0 + 1) + fx * fy * texel(x0 + 1, y0 + 1);
}

// What a capture allows E_u of filtered light on another driver beyond float arithmetic
// (Stage::unshadowedSpread): T's bilinear weights for a uv a few ulp (δ = 8·2^-24) apart move by
// N·δ each, N the texture's larger side: |ΔE_u| <= max E0 · 2·N·δ·(max T − min T). The default
// checker is 64 texels of 1 and 0.25; other lights have no such term.
TEST(IrradianceFiltered, TheSpreadBetweenDriversIsTheWeightsOfAUvAFewUlpApart) {
    Stage& st = irrtest::stage();
    st.useCheckerTexture();
    Settings s;
    s.mode = LightMode::Filtered;
    s.irradiance = glm::vec3(1.0f, 3.0f, 2.0f);
    EXPECT_DOUBLE_EQ(st.unshadowedSpread(s), 3.0 * 2 * 64 * (8.0 / 16777216.0) * 0.75);
    st.setProjectedTexture(2, 5, std::vector<float>(30, 0.5f));
    EXPECT_EQ(st.unshadowedSpread(s), 0.0) << "a constant texture has no contrast to move";
    for (LightMode m : {LightMode::Directional, LightMode::Ibl, LightMode::OccludedIbl}) {
        s.mode = m;
        EXPECT_EQ(st.unshadowedSpread(s), 0.0);
    }
    st.useCheckerTexture();
}

TEST(IrradianceFiltered, ProjectedTextureInLightSpace) {
    Stage& st = irrtest::stage();
    const mesh::Mesh m = mesh::makeUvSphere(32, 64);
    const auto P = irrtest::vertexPositions(m), N = irrtest::vertexNormals(m);
    st.setScene(m, P, N);
    const int W = 4, H = 2;
    const std::vector<float> img = {1.0f, 0.1f, 0.2f, 0.3f, 0.9f, 0.4f, 0.5f, 0.6f,
                                    1.0f, 0.7f, 0.8f, 0.2f, 0.2f, 0.3f, 0.9f, 0.6f,
                                    0.6f, 0.1f, 0.1f, 1.0f, 0.5f, 0.4f, 0.2f, 0.8f};
    st.setProjectedTexture(W, H, img);
    Settings s;
    s.mode = LightMode::Filtered;
    s.direction = glm::vec3(-0.4f, 0.5f, 0.7f);
    s.irradiance = kE0;
    s.shadowMapSize = 512;
    s.filter = ShadowFilter::OffsetPcf;
    const Basis b = basis(s.direction);
    const float extent = 1.02f * 0.5f;
    const double texel = 2.0 * extent / 512;
    const auto E = st.compute(s);
    double maxErr = 0;
    int checked = 0;
    for (size_t i = 0; i < P.size(); ++i) {
        const double c = glm::dot(N[i], b.w);
        if (c <= 0 || 0.5 * (1.0 - std::sqrt(1.0 - c * c)) < 4 * texel) continue;
        const glm::vec2 uv =
            glm::vec2(0.5f) + 0.5f * glm::vec2(glm::dot(P[i], b.u), glm::dot(P[i], b.v)) / extent;
        const glm::vec3 want = closedForm(N[i], b.w, s.ior) * bilinear(img, W, H, uv);
        const glm::vec3 base = closedForm(N[i], b.w, s.ior);
        for (int k = 0; k < 3; ++k) {
            // the shader filters T in float (irradiance_direct.comp, projectedBilinear), not
            // the sampler, whose weights may have as few as 8 fractional bits (Direct3D 11's
            // rule, which NVIDIA's follow: an H200 came to 0.00381 here when the sampler
            // filtered): on every driver the lookup is this bilinear up to float rounding, a uv a
            // few ulp apart moving a weight by W·ulp, far below 1e-5
            const double err = std::abs(E[i][k] - want[k]) / base[k];
            maxErr = std::max(maxErr, err);
            EXPECT_LT(err, 1e-5) << i << " channel " << k;
        }
        ++checked;
    }
    std::printf("filtered light: %d points, largest error %.3g of the texel range\n", checked,
                maxErr);
    EXPECT_GT(checked, 500);

    // the default checker: only 1 and 0.25 inside squares, both present
    st.useCheckerTexture();
    const auto C = st.compute(s);
    int ones = 0, quarters = 0;
    for (size_t i = 0; i < P.size(); ++i) {
        const glm::vec3 base = closedForm(N[i], b.w, s.ior);
        if (base.r < 1e-3f) continue;
        const float ratio = C[i].r / base.r;
        EXPECT_TRUE(ratio >= 0.25f - 1e-4f && ratio <= 1.0f + 1e-4f) << ratio;
        ones += ratio > 1.0f - 1e-4f;
        quarters += ratio < 0.25f + 1e-4f;
    }
    EXPECT_GT(ones, 100);
    EXPECT_GT(quarters, 100);
}

} // namespace
