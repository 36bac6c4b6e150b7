// Expected-value exits of the CPU walk (pathtrace.h, ExpectedExits): every flight upward from a
// collision is tallied with its probability of leaving instead of the exits that happen. It
// changes the variance, never the expectation. Checked against the histogram of the actual
// exits (Algorithm 1's estimator, independent seeds) bin by bin with z-tests and χ², for the
// implicit and the analog walk, with and without radial splitting, at oblique incidence per
// exit direction and per scattering order; its error bars against the spread of independent
// runs; and its purpose, a lower variance per path at every radius. Each for a forward medium
// (directions drawn from the phase function) and isotropic ones (directions drawn from the
// escape cone, with and without a critical angle).
#include "core/fields.h"
#include "core/statistics.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/pathtrace.h"
#include "spread_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace pathtrace;

namespace ev {

// σa 0.1, σs 0.9 (1/mm), g 0.5, η 1.3: l_d = 1/√(3·0.1·0.55) = 2.46 mm; directions from the
// phase function. Isotropic, η 1.3: directions from the escape cone (critical cosine 0.64).
// Isotropic, η 0.8: the cone is the whole upper hemisphere (no critical angle inside).
const Medium kMedium{0.1, 0.9, 0.5, 1.3};
const Medium kMedia[] = {kMedium, {0.1, 0.9, 0.0, 1.3}, {0.1, 0.9, 0.0, 0.8}};

std::string nameOf(const Medium& m) {
    return "g " + std::to_string(m.g) + ", eta " + std::to_string(m.eta);
}

SlabSettings settings(const Medium& m, Estimator e, int samples, uint64_t paths, uint64_t seed) {
    SlabSettings s;
    s.rMaxMm = 4 / std::sqrt(3 * m.sigmaA * (m.sigmaA + m.sigmaS * (1 - m.g))); // 4 l_d
    s.bins = 24;
    s.paths = paths;
    s.seed = seed;
    s.threads = 2;
    s.estimator = e;
    s.exits.samples = samples;
    return s;
}

double zOf(double a, double ea, double b, double eb) {
    const double e = std::hypot(ea, eb);
    return e > 0 ? (a - b) / e : 0.0;
}

// Every bin of `b` agrees with `a` (independent runs): |z| below the Bonferroni bound at
// P 1e-3 over the bins, and χ² below its 1e-3 quantile for 24 degrees of freedom (51.2).
void expectSameProfile(const SlabResult& a, const SlabResult& b) {
    const double zMax = core::bonferroniZ(1e-3, double(a.rd.size()));
    double chi2 = 0;
    for (size_t i = 0; i < a.rd.size(); ++i) {
        ASSERT_GT(a.rdStderr[i], 0.0) << "bin " << i;
        const double z = zOf(b.rd[i], b.rdStderr[i], a.rd[i], a.rdStderr[i]);
        EXPECT_LT(std::fabs(z), zMax) << "bin " << i << ": " << b.rd[i] << " vs " << a.rd[i];
        chi2 += z * z;
    }
    EXPECT_LT(chi2, 51.2);
}

// Variance per path of bin b relative to its mean squared.
double relVar(const SlabResult& x, size_t b) {
    const double rel = x.rdStderr[b] / x.rd[b];
    return rel * rel * double(x.paths);
}

} // namespace ev

// The same profile as the actual exits, for the implicit and the analog walk, with the default
// radial splitting and without; the energy balance (which counts the actual exits) stays exact.
TEST(ExpectedExits, LeaveTheExpectationOfEveryBinUnchanged) {
    for (const Medium& m : ev::kMedia)
        for (Estimator e : {Estimator::Implicit, Estimator::Analog})
            for (int levels : {0, Splitting{}.levels}) {
                SCOPED_TRACE(ev::nameOf(m) + ", " + core::nameOf(e) + ", splitting levels " +
                             std::to_string(levels));
                SlabSettings actual = ev::settings(m, e, 0, 100000, 1);
                SlabSettings expected = ev::settings(m, e, kExpectedExitSamples, 50000, 2);
                actual.splitting.levels = expected.splitting.levels = levels;
                const SlabResult a = runSlab(m, actual);
                const SlabResult x = runSlab(m, expected);
                ASSERT_TRUE(energyProblem(x).empty()) << energyProblem(x);
                ev::expectSameProfile(a, x);
                // The total reflectance counts the actual exits in both.
                EXPECT_LT(
                    std::fabs(ev::zOf(x.totalRd, x.totalRdStderr, a.totalRd, a.totalRdStderr)),
                    4.0);
            }
}

// One direction per collision (the walk's own, at every depth) is unbiased too, and so are
// many (16 within 5 mean free paths).
TEST(ExpectedExits, AnyNumberOfSamplesAndAnyDepthKeepTheExpectation) {
    for (const Medium& m : {ev::kMedia[0], ev::kMedia[1]}) {
        SCOPED_TRACE(ev::nameOf(m));
        const SlabResult a = runSlab(m, ev::settings(m, Estimator::Implicit, 0, 100000, 3));
        SlabSettings one = ev::settings(m, Estimator::Implicit, 1, 50000, 4);
        SlabSettings many = ev::settings(m, Estimator::Implicit, 16, 20000, 5);
        many.exits.depthMfp = 5;
        ev::expectSameProfile(a, runSlab(m, one));
        ev::expectSameProfile(a, runSlab(m, many));
    }
}

// The error bars are honest: a path's many tallies into one bin are summed before squaring,
// so over 16 independent runs each bin's spread matches the standard error the runs report
// (pooled Σ (x − x̄)²/se² over the bins ~ χ² with 15 · 24 degrees of freedom; the ratio to
// its mean within ±5 of its standard deviations). Counted per tally instead of per path, the
// reported errors would be too small.
TEST(ExpectedExits, StandardErrorsMatchTheSpreadOfIndependentRuns) {
    const int runs = 16;
    for (const Medium& m : {ev::kMedia[0], ev::kMedia[1]}) {
        SCOPED_TRACE(ev::nameOf(m));
        std::vector<SlabResult> r;
        for (int i = 0; i < runs; ++i)
            r.push_back(runSlab(m, ev::settings(m, Estimator::Implicit, kExpectedExitSamples, 4000,
                                                200 + uint64_t(i))));
        expectSpreadMatchesStandardErrors(r, 0);
    }
}

// The purpose: per path, the variance is lower at every radius, near the beam, at l_d and in
// the tail (here 2–4x; `bench pathtrace` weighs it against the time per path). For isotropic
// media with a critical angle, one direction from the escape cone does more than four from the
// phase function do for the forward medium: at least 3x.
TEST(ExpectedExits, LowerTheVariancePerPathAtEveryRadius) {
    const uint64_t n = 60000;
    for (const auto& [m, samples, factor] :
         {std::tuple{ev::kMedia[0], 4, 1.5}, std::tuple{ev::kMedia[1], 1, 3.0}}) {
        SCOPED_TRACE(ev::nameOf(m));
        const SlabResult a = runSlab(m, ev::settings(m, Estimator::Implicit, 0, n, 7));
        const SlabResult x = runSlab(m, ev::settings(m, Estimator::Implicit, samples, n, 8));
        for (auto [lo, hi] : {std::pair{1, 3}, std::pair{5, 7}, std::pair{18, 24}}) {
            double va = 0, vx = 0;
            for (int b = lo; b < hi; ++b)
                va += ev::relVar(a, size_t(b)), vx += ev::relVar(x, size_t(b));
            EXPECT_LT(vx, va / factor)
                << "bins [" << lo << ", " << hi << "): " << vx << " vs " << va;
        }
    }
}

// At oblique incidence, per spatial bin and exit-direction cell (the flight's refracted
// direction), and per scattering order, the whole-BSSRDF walk keeps the histogram's
// expectation: z-tests (Bonferroni) over every cell with enough actual exits.
TEST(ExpectedExits, ObliqueIncidencePerDirectionAndOrderKeepsTheExpectation) {
    for (const Medium& m : {Medium{0.05, 1.0, 0.5, 1.3}, Medium{0.05, 1.0, 0.0, 1.3}})
        for (ScatterOrders orders :
             {ScatterOrders::All, ScatterOrders::SingleOnly, ScatterOrders::MultipleOnly}) {
            SCOPED_TRACE(ev::nameOf(m) + ", " + core::nameOf(orders));
            EstimateSettings s;
            s.thetaIDeg = {60.0};
            s.bins.rBins = 5;
            s.bins.rMaxMm = orders == ScatterOrders::SingleOnly ? 1.5 : 5.0;
            s.bins.thetaSBins = 3;
            s.bins.dirCosBins = 2;
            s.bins.dirPhiBins = 3;
            s.orders = orders;
            s.estimator = BssrdfEstimator::Implicit;
            s.exits.samples = 0;
            s.paths = 300000;
            s.seed = 21;
            const BssrdfSlice a =
                finalize(estimateChunks(m, s, 0, 0, chunkCount(s)), s.bins, 60.0, m);
            s.exits.samples = kExpectedExitSamples;
            s.paths = 100000;
            s.seed = 22;
            const BssrdfSlice x =
                finalize(estimateChunks(m, s, 0, 0, chunkCount(s)), s.bins, 60.0, m);
            const double zMax = core::bonferroniZ(1e-3, double(a.S.size()));
            int tested = 0;
            for (size_t i = 0; i < a.S.size(); ++i) {
                if (!(a.SStderr[i] > 0) || a.S[i] / a.SStderr[i] < 10) continue;
                ++tested;
                EXPECT_LT(std::fabs(ev::zOf(x.S[i], x.SStderr[i], a.S[i], a.SStderr[i])), zMax)
                    << "cell " << i << ": " << x.S[i] << " +- " << x.SStderr[i] << " vs " << a.S[i]
                    << " +- " << a.SStderr[i];
            }
            EXPECT_GE(tested, 8) << "of " << a.S.size();
        }
}

// Bad settings name the field.
TEST(ExpectedExits, BadSettingsAreNamed) {
    SlabSettings s = ev::settings(ev::kMedium, Estimator::Implicit, 65, 10, 1);
    EXPECT_THROW(
        {
            try {
                validate(s);
            } catch (const core::Error& e) {
                EXPECT_NE(std::string(e.what()).find("exit samples must lie in [0, 64]"),
                          std::string::npos)
                    << e.what();
                throw;
            }
        },
        core::Error);
    s.exits.samples = 4;
    s.exits.depthMfp = -1;
    EXPECT_THROW(validate(s), core::Error);
    EstimateSettings e;
    e.exits.depthMfp = NAN;
    EXPECT_THROW(validate(e), core::Error);
}
