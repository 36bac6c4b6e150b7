// Tests of the oblique-incidence BSSRDF estimate (pathtrace/bssrdf_estimate.h): the exact sums,
// the bin geometry, bad settings, determinism for any thread and shard count, and the connection
// estimator against the analog histogram (an estimator that shares none of its connection
// code), bin by bin with Bonferroni-corrected z-tests, at θi 0°, 45°, 75° and g 0, 0.8, plus its
// energy (per path, connections minus exits has mean 0) and normal incidence against the slab
// tracer.
#include "core/core.h"
#include "core/statistics.h"
#include "pathtrace/bssrdf_estimate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

using namespace pathtrace;

namespace {

BssrdfTally runAll(const Medium& m, const EstimateSettings& s, size_t angle = 0) {
    return estimateChunks(m, s, angle, 0, chunkCount(s));
}

// z of the difference of two independent estimates.
double zOf(double a, double ea, double b, double eb) {
    const double e = std::sqrt(ea * ea + eb * eb);
    return e > 0 ? (a - b) / e : 0.0;
}

} // namespace

TEST(ExactSum, SameBitsInAnyOrder) {
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<double> xs;
    for (int i = 0; i < 5000; ++i)
        xs.push_back(std::ldexp(u(gen), int(gen() % 200) - 150));
    detail::ExactSum a, b;
    long double ref = 0;
    for (double x : xs) {
        a.add(x);
        ref += x;
    }
    std::shuffle(xs.begin(), xs.end(), gen);
    // b: the same values in another order, in two partial sums added at the end.
    detail::ExactSum b1, b2;
    for (size_t i = 0; i < xs.size(); ++i)
        (i % 3 ? b1 : b2).add(xs[i]);
    b.add(b2);
    b.add(b1);
    EXPECT_TRUE(a == b);
    EXPECT_NEAR(a.value(), double(ref), 1e-15 * std::fabs(double(ref)) + 1e-30);
    detail::ExactSum c;
    c.add(-2.5);
    c.add(0.75);
    EXPECT_EQ(c.value(), -1.75);
    c.add(std::nan(""));
    EXPECT_TRUE(c.overflow);
}

TEST(BssrdfBins, AreasAndSolidAnglesTile) {
    for (auto spacing : {RadialSpacing::Uniform, RadialSpacing::Log}) {
        BssrdfBins b;
        b.rBins = 7;
        b.rMaxMm = 3;
        b.spacing = spacing;
        b.thetaSBins = 5;
        b.dirCosBins = 4;
        b.dirPhiBins = 6;
        double area = 0;
        for (int ir = 0; ir < b.rBins; ++ir)
            area += binArea(b, ir) * b.thetaSBins;
        EXPECT_NEAR(area, std::numbers::pi * 9, 1e-12);
        double proj = 0;
        for (int c = 0; c < b.dirBins(); ++c)
            proj += cellProjectedSolidAngle(b, c);
        EXPECT_NEAR(proj, std::numbers::pi, 1e-12);
        const auto e = b.rEdges();
        EXPECT_EQ(e.front(), 0.0);
        EXPECT_EQ(e.back(), 3.0);
        if (spacing == RadialSpacing::Log) {
            EXPECT_NEAR(e[1], 0.003, 1e-15);
        }
    }
    BssrdfBins b;
    b.dirCosBins = 2;
    b.dirPhiBins = 4;
    EXPECT_EQ(cellOf(b, 0.99, 0.1), 4);
    EXPECT_EQ(cellOf(b, 0.2, -0.1), 3); // φ = −0.1 is in the last sector
    EXPECT_EQ(cellOf(b, 1.0, std::numbers::pi), 6);
}

TEST(BssrdfEstimate, RejectsBadSettings) {
    auto expectError = [](auto edit, const std::string& needle) {
        EstimateSettings s;
        edit(s);
        try {
            validate(s);
            ADD_FAILURE() << "accepted: " << needle;
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expectError([](EstimateSettings& s) { s.thetaIDeg = {90}; }, "theta_i must lie in [0, 90)");
    expectError([](EstimateSettings& s) { s.thetaIDeg = {-5}; }, "theta_i must lie in [0, 90)");
    expectError([](EstimateSettings& s) { s.thetaIDeg = {std::nan("")}; }, "theta_i");
    expectError([](EstimateSettings& s) { s.thetaIDeg.clear(); }, "at least one");
    expectError([](EstimateSettings& s) { s.bins.rBins = 0; }, "r_bins must be >= 1");
    expectError([](EstimateSettings& s) { s.bins.thetaSBins = 100000; }, "absurd bin count");
    expectError([](EstimateSettings& s) { s.bins.dirCosBins = -3; }, "dir_cos_bins");
    expectError(
        [](EstimateSettings& s) {
            s.bins.rBins = 1000;
            s.bins.thetaSBins = 100;
            s.bins.dirCosBins = 10;
            s.bins.dirPhiBins = 10;
        },
        "4e6");
    expectError(
        [](EstimateSettings& s) {
            s.bins.spacing = RadialSpacing::Log;
            s.bins.rMinMm = 20;
        },
        "r_min");
    expectError([](EstimateSettings& s) { s.bins.rStartMm = 10; },
                "r_start must lie in [0, r_max)");
    expectError([](EstimateSettings& s) { s.paths = 0; }, "paths");
}

TEST(BssrdfEstimate, SameBitsForAnyThreadAndShardCount) {
    const Medium m{0.5, 1.0, 0.5, 1.4}; // short paths: this test is about sums, not physics
    EstimateSettings s;
    s.thetaIDeg = {30};
    s.bins.rBins = 6;
    s.bins.rMaxMm = 4;
    s.bins.thetaSBins = 3;
    s.bins.dirCosBins = 2;
    s.bins.dirPhiBins = 3;
    s.paths = 4 * kChunkPaths + 77;
    s.threads = 1;
    const BssrdfTally one = runAll(m, s);
    s.threads = 2;
    EXPECT_TRUE(runAll(m, s) == one);
    for (uint64_t n : {2u, 3u, 6u}) {
        BssrdfTally merged = makeTally(s.bins);
        for (uint64_t k = n; k-- > 0;) { // merged in reverse order on purpose
            const auto [a, b] = shardChunks(s, k, n);
            merged.merge(estimateChunks(m, s, 0, a, b));
        }
        EXPECT_TRUE(merged == one) << n << " shards";
    }
    EXPECT_EQ(one.paths, s.paths);
}

namespace {

struct Case {
    double g, thetaI;
    ScatterOrders orders = ScatterOrders::All;
    double rMax = 5; // mm: the bins must be where the tallied orders leave
};

// Connections against the analog histogram, every spatial bin (and, with directions, every
// cell with enough analog hits), Bonferroni over all tests of one case.
void compareWithAnalog(const Case& c, bool directions) {
    const Medium m{0.05, 1.0, c.g, 1.3};
    EstimateSettings s;
    s.thetaIDeg = {c.thetaI};
    s.bins.rBins = 5;
    s.bins.rMaxMm = c.rMax;
    s.bins.thetaSBins = 3;
    if (directions) {
        s.bins.dirCosBins = 2;
        s.bins.dirPhiBins = 3;
    }
    s.threads = 0;
    s.orders = c.orders;
    s.estimator = BssrdfEstimator::Connections;
    const uint64_t nConn = 40000, nAnalog = 800000;
    s.paths = nConn;
    s.seed = 11;
    const BssrdfSlice conn = finalize(runAll(m, s), s.bins, c.thetaI, m);
    s.estimator = BssrdfEstimator::Analog;
    s.exits.samples = 0; // Algorithm 1's histogram of the actual exits
    s.paths = nAnalog;
    s.seed = 12;
    const BssrdfSlice ana = finalize(runAll(m, s), s.bins, c.thetaI, m);
    const auto& a = directions ? ana.S : ana.R;
    const auto& ae = directions ? ana.SStderr : ana.RStderr;
    const auto& b = directions ? conn.S : conn.R;
    const auto& be = directions ? conn.SStderr : conn.RStderr;
    const double zMax = core::bonferroniZ(1e-3, double(a.size()) + 1);
    int tested = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        // The analog bin must hold enough hits for its mean to be near normal (≥ ~100).
        if (!(ae[i] > 0) || a[i] / ae[i] < 10) continue;
        ++tested;
        const double z = zOf(b[i], be[i], a[i], ae[i]);
        EXPECT_LT(std::fabs(z), zMax)
            << "g " << c.g << " theta_i " << c.thetaI << " bin " << i << ": connections " << b[i]
            << " +- " << be[i] << ", analog " << a[i] << " +- " << ae[i];
        // Connections must be the better estimator per path traced (variance × paths).
        if (!directions) {
            EXPECT_LT(be[i] * std::sqrt(double(nConn)), ae[i] * std::sqrt(double(nAnalog)))
                << "bin " << i;
        }
    }
    EXPECT_GE(tested, int(a.size()) * 2 / 3) << "g " << c.g << " theta_i " << c.thetaI;
    if (c.orders == ScatterOrders::SingleOnly) return; // the walk stops at its first collision
    // Energy: connections and exits estimate the same flux, path by path.
    EXPECT_LT(std::fabs(conn.energyDiff / conn.energyDiffStderr), zMax)
        << conn.energyDiff << " +- " << conn.energyDiffStderr;
    // Both walks see the same total reflectance.
    EXPECT_LT(std::fabs(zOf(conn.totalRd, conn.totalRdStderr, ana.totalRd, ana.totalRdStderr)),
              zMax);
}

} // namespace

TEST(BssrdfEstimate, ConnectionsAgreeWithAnalogHistogram) {
    for (const Case c :
         {Case{0.0, 0}, Case{0.0, 45}, Case{0.0, 75}, Case{0.8, 0}, Case{0.8, 45}, Case{0.8, 75}})
        compareWithAnalog(c, false);
}

// Single scattering only and multiple scattering only, each against the histogram of the exits
// after exactly one / at least two collisions.
TEST(BssrdfEstimate, ScatteringOrdersAgreeWithAnalogHistogram) {
    // single scattering leaves within a few mean free paths of the entry
    for (const Case c : {Case{0.0, 45, ScatterOrders::SingleOnly, 1.5},
                         Case{0.8, 75, ScatterOrders::MultipleOnly}})
        compareWithAnalog(c, false);
}

TEST(BssrdfEstimate, ConnectionsAgreeWithAnalogPerDirection) {
    for (const Case c : {Case{0.0, 45}, Case{0.8, 75}})
        compareWithAnalog(c, true);
}

TEST(BssrdfEstimate, NormalIncidenceMatchesTheSlabTracer) {
    const Medium m{0.01, 1.0, 0.0, 1.3};
    SlabSettings slab;
    slab.rMaxMm = 6;
    slab.bins = 12;
    slab.paths = 300000;
    slab.seed = 5;
    const SlabResult ref = runSlab(m, slab);
    EstimateSettings s;
    s.bins.rBins = slab.bins;
    s.bins.rMaxMm = slab.rMaxMm;
    s.bins.thetaSBins = 1;
    s.paths = 20000;
    s.seed = 6;
    const BssrdfSlice c = finalize(runAll(m, s), s.bins, 0, m);
    const double zMax = core::bonferroniZ(1e-3, slab.bins);
    for (int i = 0; i < slab.bins; ++i)
        EXPECT_LT(std::fabs(zOf(c.R[size_t(i)], c.RStderr[size_t(i)], ref.rd[size_t(i)],
                                ref.rdStderr[size_t(i)])),
                  zMax)
            << "bin " << i << ": " << c.R[size_t(i)] << " vs " << ref.rd[size_t(i)];
    EXPECT_NEAR(c.specular, ref.specular, 1e-15);
}
