// irradiance, image based lighting with occlusion (thesis 3.3.2: shared environment samples,
// one shadow map each, ping-pong accumulation), headless GL:
//   - a convex sphere under a constant environment L = 1 has no occlusion: every point's
//     estimate agrees with π(1 − F_dr) (1D quadrature) within its standard error, computed from
//     the per-sample values (z with a Bonferroni limit for a family-wise α = 1e-3; the iid
//     standard error is conservative for the stratified samples);
//   - a plate above a box: points under the plate are darker than the unoccluded value by more
//     than 5 standard errors, points on the plate's top agree with it;
//   - determinism (same seed: bitwise equal; another seed: different), the step size only
//     changes the summation order, progress and cancel;
//   - the unshadowed sum U (Stage::occludedUnshadowed, CPU in double) is the GPU pass with the
//     filter off within float summation, bounds every shadowed estimate, and is 0 for normals
//     that face away from every sample;
//   - the raster spread (Stage::occludedRasterSpread) bounds E_t from maps whose vertices each
//     moved on their own.
#include "core/statistics.h"
#include "gl_stage.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

namespace {
using namespace irradiance;

using core::normalUpperQuantile;

Settings occludedSettings() {
    Settings s;
    s.mode = LightMode::OccludedIbl;
    s.shadowMapSize = 256;
    s.occludedTotalSamples = 256;
    s.occludedSamplesPerStep = 16;
    s.seed = 7;
    return s;
}

TEST(IrradianceOccluded, ConvexSphereConvergesToTheUnoccludedValue) {
    Stage& st = irrtest::stage();
    const mesh::Mesh m = mesh::makeUvSphere(16, 32);
    const auto P = irrtest::vertexPositions(m), N = irrtest::vertexNormals(m);
    st.setScene(m, P, N);
    st.setEnvironment(irrtest::constantEnv(16, 8, glm::vec3(1.0f)));
    const Settings s = occludedSettings();
    const auto E = st.compute(s);
    const auto se = st.occludedStdError();
    ASSERT_EQ(E.size(), P.size());
    ASSERT_EQ(se.size(), P.size());
    const double ref = irrtest::hemisphericalFt(s.ior);
    const double zMax = normalUpperQuantile(1e-3 / (2.0 * P.size()));
    double sumZ = 0, worst = 0;
    for (size_t i = 0; i < P.size(); ++i) {
        ASSERT_GT(se[i].g, 0.0f);
        const double z = (E[i].g - ref) / se[i].g;
        sumZ += z;
        worst = std::max(worst, std::abs(z));
        EXPECT_LT(std::abs(z), zMax) << "point " << i << " E " << E[i].g << " ref " << ref;
        EXPECT_EQ(E[i].r, E[i].g); // grey environment
    }
    std::printf("occluded IBL on a sphere: %zu points, K = %d, mean z %.3f, max |z| %.2f (limit "
                "%.2f), relative standard error %.3f\n",
                P.size(), s.occludedTotalSamples, sumZ / P.size(), worst, zMax, se[0].g / ref);
}

TEST(IrradianceOccluded, PlateDarkensThePointsUnderIt) {
    Stage& st = irrtest::stage();
    mesh::Mesh m;
    irrtest::append(m, mesh::makeBox(1, 0.2, 1), glm::vec3(0, -0.3f, 0));
    irrtest::append(m, mesh::makeBox(0.4, 0.05, 0.4), glm::vec3(0, 0.1f, 0));
    std::vector<glm::vec3> P, N;
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) {
            P.emplace_back(-0.08f + 0.04f * i, -0.2f, -0.08f + 0.04f * j); // under the plate
            N.emplace_back(0, 1, 0);
            P.emplace_back(-0.16f + 0.08f * i, 0.125f, -0.16f + 0.08f * j); // the plate's top
            N.emplace_back(0, 1, 0);
        }
    st.setScene(m, P, N);
    st.setEnvironment(irrtest::constantEnv(16, 8, glm::vec3(1.0f)));
    Settings s = occludedSettings();
    s.occludedTotalSamples = 512;
    s.occludedSamplesPerStep = 32;
    const auto E = st.compute(s);
    const auto se = st.occludedStdError();
    const double ref = irrtest::hemisphericalFt(s.ior);
    const double zMax = normalUpperQuantile(1e-3 / (2.0 * P.size()));
    double under = 0;
    for (size_t i = 0; i < P.size(); i += 2) {
        EXPECT_LT(E[i].g + 5 * se[i].g, ref) << "under the plate, point " << i;
        EXPECT_LT(std::abs(E[i + 1].g - ref) / se[i + 1].g, zMax) << "plate top, point " << i;
        under += E[i].g / ref / (P.size() / 2);
    }
    std::printf("occluded IBL under the plate: %.3f of the unoccluded value\n", under);
}

TEST(IrradianceOccluded, DeterministicStepsProgressAndCancel) {
    Stage& st = irrtest::stage();
    const mesh::Mesh m = mesh::makeUvSphere(8, 16);
    st.setScene(m, irrtest::vertexPositions(m), irrtest::vertexNormals(m));
    EnvironmentMap env = makeDefaultSky(32, 16);
    st.setEnvironment(env);
    Settings s = occludedSettings();
    s.occludedTotalSamples = 40;
    s.occludedSamplesPerStep = 16;

    EXPECT_FALSE(st.occludedRunning());
    EXPECT_EQ(st.occludedProgress(), 0.0f);
    EXPECT_TRUE(st.occludedResult().empty());
    EXPECT_FALSE(st.stepOccluded()); // nothing running

    st.beginOccluded(s);
    EXPECT_TRUE(st.occludedRunning());
    EXPECT_EQ(st.occludedProgress(), 0.0f);
    EXPECT_FALSE(st.stepOccluded());
    EXPECT_FLOAT_EQ(st.occludedProgress(), 0.4f);
    EXPECT_EQ(st.occludedSamplesDone(), 16);
    EXPECT_EQ(st.occludedResult().size(), m.vertices.size()); // a partial estimate
    EXPECT_FALSE(st.stepOccluded());
    EXPECT_FLOAT_EQ(st.occludedProgress(), 0.8f);
    EXPECT_TRUE(st.stepOccluded());
    EXPECT_FLOAT_EQ(st.occludedProgress(), 1.0f);
    EXPECT_FALSE(st.occludedRunning());
    const auto a = st.occludedResult();

    const auto b = st.compute(s); // the same run in one call
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(glm::vec3)), 0);
    const auto again = st.compute(s);
    EXPECT_EQ(std::memcmp(a.data(), again.data(), a.size() * sizeof(glm::vec3)), 0);

    Settings other = s;
    other.seed = 8;
    const auto c = st.compute(other);
    EXPECT_NE(std::memcmp(a.data(), c.data(), a.size() * sizeof(glm::vec3)), 0);

    Settings steps = s;
    steps.occludedSamplesPerStep = 5; // only the summation order changes
    const auto d = st.compute(steps);
    for (size_t i = 0; i < a.size(); ++i)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(d[i][k], a[i][k], 1e-5f * (1 + a[i][k]));

    st.beginOccluded(s);
    EXPECT_FALSE(st.stepOccluded());
    st.cancelOccluded();
    EXPECT_FALSE(st.occludedRunning());
    EXPECT_EQ(st.occludedProgress(), 0.0f);
    EXPECT_TRUE(st.occludedResult().empty());
    EXPECT_FALSE(st.stepOccluded());
    // setScene cancels as well
    st.beginOccluded(s);
    st.setScene(m, irrtest::vertexPositions(m), irrtest::vertexNormals(m));
    EXPECT_FALSE(st.occludedRunning());
}

// Stage::occludedRasterSpread moves each sample's whole map to rasterShifts(); a driver snaps each
// vertex on its own. Emulated on the bunny under the default sky (Stage::setVertexSnap: in every
// sample's map each vertex moved on its own by up to kRasterShiftTexels along both image axes
// and 8 ulps of depth): every point's E_t, per channel, stays within the spread (the same samples
// and sampler, so to float summation: 1e-5 of U), though the moves change thousands of values.
// Moves four times larger fail.
TEST(IrradianceOccluded, TheRasterSpreadBoundsMapsWhoseVerticesSnapApart) {
    Stage& st = irrtest::stage();
    const irrtest::PointsOnMesh sc = irrtest::bunnyPoints();
    st.setScene(sc.mesh, sc.P, sc.N);
    st.setEnvironment(makeDefaultSky(32, 16));
    Settings s = occludedSettings();
    s.occludedTotalSamples = 32;
    s.occludedSamplesPerStep = 8;
    const std::vector<glm::vec3> spread = st.occludedRasterSpread(s);
    const std::vector<glm::vec3> e = st.occludedResult();
    const std::vector<glm::vec3> U = st.occludedUnshadowed(s, sc.N);
    int moved = 0, beyond = 0;
    for (const uint32_t seed : {1u, 2u}) {
        st.setVertexSnap({kRasterShiftTexels, 8.0f, seed});
        const std::vector<glm::vec3> w = st.compute(s);
        st.setVertexSnap({4.0f * kRasterShiftTexels, 8.0f, seed});
        const std::vector<glm::vec3> far = st.compute(s);
        st.setVertexSnap({});
        for (size_t i = 0; i < e.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const double d = std::abs(double(w[i][c]) - e[i][c]);
                const double rounding = 1e-5 * U[i][c];
                moved += d > rounding;
                beyond += std::abs(double(far[i][c]) - e[i][c]) > spread[i][c] + rounding;
                EXPECT_LE(d, spread[i][c] + rounding)
                    << "seed " << seed << " point " << i << " channel " << c << " E_t " << e[i][c]
                    << " moved " << w[i][c] << " spread " << spread[i][c];
            }
    }
    EXPECT_GT(moved, 1000) << "the emulation moves too little to show anything";
    EXPECT_GT(beyond, 100) << "moves four times larger stay within the spread too";
    std::printf("occluded IBL, vertices snapped apart by up to 1/16 texel: %d values changed, each "
                "within the rigid moves' spread; at 1/4 texel %d past it\n",
                moved, beyond);
}

} // namespace

// The allowance a replay on another driver gives the occluded E_t, kVisibilityTolerance · U, rests
// on U being the same estimate with every V = 1: the CPU sum in double agrees with the GPU pass
// run with ShadowFilter::None over the same samples (float sums of 256 terms in steps of 16,
// 3e-7 relative measured), and every shadowed point's E_t lies at or under it.
TEST(IrradianceOccluded, TheUnshadowedSumIsThePassWithoutShadows) {
    Stage& st = irrtest::stage();
    mesh::Mesh m;
    irrtest::append(m, mesh::makeBox(1, 0.2, 1), glm::vec3(0, -0.3f, 0));
    irrtest::append(m, mesh::makeBox(0.4, 0.05, 0.4), glm::vec3(0, 0.1f, 0));
    const mesh::Mesh sphere = mesh::makeUvSphere(12, 24);
    irrtest::append(m, sphere, glm::vec3(0.3f, 0.2f, 0.3f));
    const auto P = irrtest::vertexPositions(m), N = irrtest::vertexNormals(m);
    st.setScene(m, P, N);
    st.setEnvironment(makeDefaultSky(32, 16));
    Settings s = occludedSettings();
    s.envRotation = 0.7f;
    s.envIntensity = 1.5f;
    s.ior = 1.4f;
    const auto E = st.compute(s);
    Settings none = s;
    none.filter = ShadowFilter::None;
    const auto gpu = st.compute(none);
    const auto U = st.occludedUnshadowed(s, N);
    ASSERT_EQ(U.size(), N.size());
    double worstRel = 0, shadowed = 0;
    for (size_t i = 0; i < N.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            ASSERT_GT(U[i][c], 0.0f) << "point " << i; // the sky lights every direction
            const double rel = std::abs(double(gpu[i][c]) - U[i][c]) / U[i][c];
            worstRel = std::max(worstRel, rel);
            EXPECT_LT(rel, 1e-5) << "point " << i << " channel " << c;
            EXPECT_LE(E[i][c], U[i][c] * (1 + 1e-5)) << "point " << i << " channel " << c;
            if (E[i][c] < 0.9 * U[i][c]) ++shadowed;
        }
    EXPECT_GT(shadowed, 30); // the plate and the sphere shade some points
    // an environment lit in one green texel above the horizon (θ in [π/4, 3π/8)): nothing in
    // red, nothing for a normal facing down
    EnvironmentMap one = irrtest::constantEnv(16, 8, glm::vec3(0.0f));
    one.rgb[3 * (2 * one.width + 5) + 1] = 10.0f;
    st.setEnvironment(one);
    const std::vector<glm::vec3> both = {glm::vec3(0, 1, 0), glm::vec3(0, -1, 0)};
    const auto u1 = st.occludedUnshadowed(s, both);
    EXPECT_EQ(u1[0].r, 0.0f);
    EXPECT_GT(u1[0].g, 0.0f);
    EXPECT_EQ(u1[1].g, 0.0f);
    std::printf(
        "occluded IBL: the CPU's unshadowed sum against the GPU pass without shadows: worst "
        "%.2e relative over %zu points; %.0f shadowed values\n",
        worstRel, N.size(), shadowed);
}
