// irradiance, image based lighting without occlusion (thesis 3.3.2), headless GL:
//   - a constant environment L = c: E_t(n) = c·2π∫_0^1 Ft(μ) μ dμ = c·π(1 − F_dr) for every
//     normal (the integral by independent 1D quadrature, test_util.h); η = 1 gives c·π and the
//     cubemap is recomputed when η changes;
//   - an environment bright only in the upper hemisphere: normal up = the full value, down = 0,
//     horizontal = half (symmetry);
//   - an environment bright only where cos φ > 0 (the +x half): +x full, −x zero; rotated by
//     π/2 about y the bright half is −z (world = R_y·env);
//   - envIntensity scales linearly; the default sky gives positive, finite values, brighter on
//     top than below.
// Tolerance: the cubemap holds the quadrature of environment.h (2 × 2 equal-solid-angle
// cells per texel, midpoint in φ and cos θ). For a 64 × 32 map the cells are h = π/64 apart;
// the integrand Ft(n·ω)·max(0, n·ω) is smooth except for the kink at n·ω = 0 (it vanishes
// linearly in μ for η = 1, quadratically otherwise), so the midpoint error is O(h²) relative,
// h²/12 ≈ 2e-4; measured at most 2.2e-4 over 49 normals and three η. 5e-4 relative (of the
// full hemisphere value for expected zeros) is the bound used. Cubemap lookups interpolate
// texel centres; for the directions tested the texels are symmetric about the direction, so
// the interpolation error is second order in the texel spacing and far below that.
#include "gl_stage.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <numbers>

namespace {
using namespace irradiance;
constexpr double kPi = std::numbers::pi;
constexpr double kTol = 5e-4;

std::vector<glm::vec3> testNormals() {
    std::vector<glm::vec3> n = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},  {0, -1, 0},         {0, 0, 1},
                                {0, 0, -1}, {1, 1, 1},  {-1, 2, 3}, {0.3f, -0.2f, 0.9f}};
    uint32_t r = 99;
    for (int i = 0; i < 40; ++i) {
        glm::vec3 v;
        for (int k = 0; k < 3; ++k) {
            r = r * 1664525u + 1013904223u;
            v[k] = static_cast<float>((r >> 8) * (1.0 / 16777216.0)) * 2 - 1;
        }
        if (glm::length(v) > 0.1f) n.push_back(glm::normalize(v));
    }
    return n;
}

// The stage with a small sphere mesh (only for setScene) and points with the given normals.
void setNormals(Stage& st, const std::vector<glm::vec3>& normals) {
    std::vector<glm::vec3> p(normals.size(), glm::vec3(0.0f));
    st.setScene(mesh::makeUvSphere(4, 8), p, normals);
}

void expectNear(const glm::vec3& got, const glm::dvec3& want, double tol, const std::string& what) {
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(got[c], want[c], tol * std::max(want[c], 1e-3)) << what << " channel " << c;
}

void expectZero(const glm::vec3& got, double tol, const std::string& what) {
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(got[c], 0.0f) << what;
        EXPECT_LT(got[c], tol) << what << " channel " << c;
    }
}

TEST(IrradianceIbl, ConstantEnvironmentIsTheHemisphericalIntegral) {
    Stage& st = irrtest::stage();
    const glm::dvec3 c(0.5, 1.0, 2.0);
    st.setEnvironment(irrtest::constantEnv(64, 32, glm::vec3(c)));
    const auto normals = testNormals();
    setNormals(st, normals);
    Settings s;
    s.mode = LightMode::Ibl;
    for (double eta : {1.3, 1.0, 1.5}) {
        s.ior = static_cast<float>(eta);
        const auto E = st.compute(s);
        const double h = irrtest::hemisphericalFt(eta);
        if (eta == 1.0) {
            EXPECT_NEAR(h, kPi, 1e-9);
        }
        double worst = 0;
        for (size_t i = 0; i < normals.size(); ++i)
            for (int k = 0; k < 3; ++k)
                worst = std::max(worst, std::abs(E[i][k] / (c[k] * h) - 1));
        std::printf("constant environment, eta %.2f: largest relative error %.3g\n", eta, worst);
        for (size_t i = 0; i < normals.size(); ++i)
            expectNear(E[i], c * h, kTol,
                       "eta " + std::to_string(eta) + " normal " + std::to_string(i));
    }
    EXPECT_NE(st.irradianceCubemap(), 0u);
    EXPECT_NE(st.environmentTexture(), 0u);
}

TEST(IrradianceIbl, UpperHemisphereEnvironment) {
    Stage& st = irrtest::stage();
    const float c = 3.0f;
    EnvironmentMap e = irrtest::constantEnv(64, 32, glm::vec3(c));
    for (size_t i = 3 * 64 * 16; i < e.rgb.size(); ++i)
        e.rgb[i] = 0.0f; // rows 16..31: θ > π/2
    st.setEnvironment(e);
    setNormals(st, {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {0, 0, -1}});
    Settings s;
    s.mode = LightMode::Ibl;
    s.ior = 1.33f;
    s.envRotation = 0.7f; // rotation about y leaves this map unchanged
    const auto E = st.compute(s);
    const double h = c * irrtest::hemisphericalFt(s.ior);
    expectNear(E[0], glm::dvec3(h), kTol, "up");
    // down: only nodes just above the horizon reach the texel centres next to (0, -1, 0)
    expectZero(E[1], kTol * h, "down");
    expectNear(E[2], glm::dvec3(h / 2), kTol, "+x");
    expectNear(E[3], glm::dvec3(h / 2), kTol, "-z");
}

TEST(IrradianceIbl, AzimuthConventionAndRotation) {
    Stage& st = irrtest::stage();
    const int W = 64, H = 32;
    EnvironmentMap e = irrtest::constantEnv(W, H, glm::vec3(1.0f));
    for (int y = 0; y < H; ++y)
        for (int x = W / 4; x < 3 * W / 4; ++x) // φ in [π/2, 3π/2): cos φ < 0
            for (int k = 0; k < 3; ++k)
                e.rgb[3 * (y * W + x) + k] = 0.0f;
    st.setEnvironment(e);
    setNormals(st, {{1, 0, 0}, {-1, 0, 0}, {0, 0, -1}, {0, 0, 1}, {0, 1, 0}});
    Settings s;
    s.mode = LightMode::Ibl;
    const double h = irrtest::hemisphericalFt(s.ior);
    auto E = st.compute(s);
    expectNear(E[0], glm::dvec3(h), kTol, "+x");
    expectZero(E[1], kTol * h, "-x");
    expectNear(E[4], glm::dvec3(h / 2), kTol, "up");
    s.envRotation = static_cast<float>(kPi / 2);
    E = st.compute(s);
    expectNear(E[2], glm::dvec3(h), kTol, "-z after rotation");
    expectZero(E[3], kTol * h, "+z after rotation");
    expectNear(E[0], glm::dvec3(h / 2), kTol, "+x after rotation");
    s.envIntensity = 2.5f;
    const auto F = st.compute(s);
    for (size_t i = 0; i < F.size(); ++i)
        EXPECT_NEAR(F[i].g, 2.5f * E[i].g, 1e-6f * (1 + F[i].g));
}

TEST(IrradianceIbl, DefaultSky) {
    Stage& st = irrtest::stage();
    st.loadEnvironment(std::filesystem::path(BW_SOURCE_ROOT) / "materials/env/default_sky.exr");
    setNormals(st, {{0, 1, 0}, {0, -1, 0}});
    Settings s;
    s.mode = LightMode::Ibl;
    const auto E = st.compute(s);
    for (int k = 0; k < 3; ++k) {
        EXPECT_TRUE(std::isfinite(E[0][k]) && E[0][k] > 0);
        EXPECT_GT(E[0][k], 2 * E[1][k]);
        EXPECT_GT(E[1][k], 0);
    }
}

} // namespace
