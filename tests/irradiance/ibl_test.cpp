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
#include "gl/gl.h"
#include "gl_stage.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

namespace {

// OpenGL 4.5 Table 8.19: the face (+X −X +Y −Y +Z −Z) and (s, t) of direction d, ties to x, y.
int faceOf(const glm::dvec3& d, double& s, double& t) {
    const glm::dvec3 a = glm::abs(d);
    double sc, tc, ma;
    int face;
    if (a.x >= a.y && a.x >= a.z) {
        face = d.x >= 0 ? 0 : 1, sc = d.x >= 0 ? -d.z : d.z, tc = -d.y, ma = a.x;
    } else if (a.y >= a.z) {
        face = d.y >= 0 ? 2 : 3, sc = d.x, tc = d.y >= 0 ? d.z : -d.z, ma = a.y;
    } else {
        face = d.z >= 0 ? 4 : 5, sc = d.z >= 0 ? d.x : -d.x, tc = -d.y, ma = a.z;
    }
    s = 0.5 * (sc / ma + 1), t = 0.5 * (tc / ma + 1);
    return face;
}

const char* kSamplerLookup = R"(#version 450
layout(local_size_x = 64) in;
layout(binding = 3) uniform samplerCube Cube;
layout(std430, binding = 0) readonly buffer In { vec4 dirs[]; };
layout(std430, binding = 1) writeonly buffer Out { vec4 values[]; };
uniform uint Count;
void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i < Count) values[i] = texture(Cube, dirs[i].xyz);
})";

} // namespace

// The IBL lookup is bilinear in float in the shader (irradiance_ibl.comp), so drivers agree
// where their samplers' weights would not. Against the driver's own sampler (seamless, linear)
// at 3000 random directions more than one texel inside a face: the same values within what a
// sampler's fixed-point weights may move them (2^-8 of the four texels' contrast, the bound of
// irradiance::kVisibilityTolerance) plus float rounding; this checks the face and orientation
// conventions against the driver's. At directions within a texel of an edge or a corner, where
// the shader takes the texel the tap's direction points into, the value lies within the range
// of the texels around.
TEST(IrradianceIbl, TheShaderFiltersTheCubemapAsASamplerDoes) {
    Stage& st = irrtest::stage();
    st.loadEnvironment(std::filesystem::path(BW_SOURCE_ROOT) / "materials/env/default_sky.exr");
    std::vector<glm::vec3> dirs;
    uint32_t r = 7;
    while (dirs.size() < 3000) {
        glm::vec3 v;
        for (int k = 0; k < 3; ++k) {
            r = r * 1664525u + 1013904223u;
            v[k] = static_cast<float>((r >> 8) * (1.0 / 16777216.0)) * 2 - 1;
        }
        if (glm::length(v) > 0.1f && glm::length(v) <= 1.0f) dirs.push_back(glm::normalize(v));
    }
    for (float e : {0.999f, 1.0f, 1.001f}) // along edges and at corners
        for (const glm::vec3& v : {glm::vec3(1, e, 0.3f), glm::vec3(-e, 1, -0.6f),
                                   glm::vec3(0.2f, -1, e), glm::vec3(1, 1, e)})
            dirs.push_back(glm::normalize(v));
    setNormals(st, dirs);
    Settings s;
    s.mode = LightMode::Ibl;
    const std::vector<glm::vec3> E = st.compute(s);
    ASSERT_EQ(E.size(), dirs.size());

    const int N = kCubeFaceSize;
    std::vector<glm::vec4> texels(size_t(6 * N * N));
    glGetTextureImage(st.irradianceCubemap(), 0, GL_RGBA, GL_FLOAT,
                      GLsizei(texels.size() * sizeof(glm::vec4)), texels.data());
    gl::Program lookup = gl::buildProgram({{GL_COMPUTE_SHADER, kSamplerLookup}});
    std::vector<glm::vec4> in(dirs.size());
    for (size_t i = 0; i < dirs.size(); ++i)
        in[i] = glm::vec4(dirs[i], 0.0f);
    gl::Buffer inBuf = gl::createBuffer(in.size() * sizeof(glm::vec4), in.data());
    gl::Buffer outBuf = gl::createBuffer(in.size() * sizeof(glm::vec4), nullptr);
    glUseProgram(lookup.id());
    glUniform1ui(glGetUniformLocation(lookup.id(), "Count"), GLuint(in.size()));
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
    glBindTextureUnit(3, st.irradianceCubemap());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, inBuf.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, outBuf.id());
    glDispatchCompute(GLuint((in.size() + 63) / 64), 1, 1);
    // barrier: the lookup's values → their readback
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> sampled(in.size());
    glGetNamedBufferSubData(outBuf.id(), 0, GLsizeiptr(sampled.size() * sizeof(glm::vec4)),
                            sampled.data());
    glUseProgram(0);
    glBindTextureUnit(3, 0);

    size_t interior = 0, edge = 0;
    double worstInterior = 0; // in units of the allowed difference
    for (size_t i = 0; i < dirs.size(); ++i) {
        double sCoord = 0, tCoord = 0;
        const int face = faceOf(glm::dvec3(dirs[i]), sCoord, tCoord);
        const double u = sCoord * N - 0.5, v = tCoord * N - 0.5;
        const int i0 = int(std::floor(u)), j0 = int(std::floor(v));
        glm::dvec3 lo(1e30), hi(-1e30); // over the texels within two of the lookup
        for (int dj = -1; dj <= 2; ++dj)
            for (int di = -1; di <= 2; ++di) {
                const int ii = std::clamp(i0 + di, 0, N - 1), jj = std::clamp(j0 + dj, 0, N - 1);
                const glm::dvec3 x(texels[size_t((face * N + jj) * N + ii)]);
                lo = glm::min(lo, x), hi = glm::max(hi, x);
            }
        const double inside = std::min({u + 0.5, N - 0.5 - u, v + 0.5, N - 0.5 - v});
        for (int c = 0; c < 3; ++c) {
            const double got = E[i][c], want = sampled[i][c];
            if (inside > 1.0) {
                const double allowed = (hi[c] - lo[c]) / 128.0 + 1e-6 * std::fabs(want);
                worstInterior = std::max(worstInterior, std::fabs(got - want) / allowed);
                EXPECT_LE(std::fabs(got - want), allowed)
                    << "direction " << i << " channel " << c << ": shader " << got << ", sampler "
                    << want;
            } else {
                // the neighbouring face's texels lie within the range of its edge's texels'
                // neighbours; allow the contrast of this face's edge region twice over
                const double slack = 2 * (hi[c] - lo[c]) + 1e-6 * std::fabs(want);
                EXPECT_NEAR(got, want, slack) << "edge direction " << i << " channel " << c;
            }
        }
        ++(inside > 1.0 ? interior : edge);
    }
    std::printf("%zu interior directions (worst difference %.3g of the allowed), %zu near an "
                "edge\n",
                interior, worstInterior, edge);
    EXPECT_GT(interior, 2000u);
    EXPECT_GT(edge, 10u);
}
