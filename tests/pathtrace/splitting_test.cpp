// Radial splitting of the slab walk (pathtrace.h, Splitting): it changes the variance, never the
// expectation. Checked against the same walk without splitting (z-tests per bin, the totals),
// its standard errors against the spread of independent runs (a path's copies are one history,
// so the per-path second moments must still give honest error bars), and its purpose: a lower
// variance per path in the tail, where the pencil profile is hardest to resolve.
#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/pathtrace.h"
#include "spread_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace pathtrace;

namespace {

// σa 0.1, σs 0.9 (1/mm), g 0.5, η 1.3: l_d = 1/√(3·0.1·0.55) = 2.46 mm.
const Medium kMedium{0.1, 0.9, 0.5, 1.3};
double diffusionLength(const Medium& m) {
    return 1.0 / std::sqrt(3 * m.sigmaA * (m.sigmaA + m.sigmaS * (1 - m.g)));
}

SlabSettings settings(int levels, uint64_t paths, uint64_t seed) {
    SlabSettings s;
    s.rMaxMm = 4 * diffusionLength(kMedium);
    s.bins = 24;
    s.paths = paths;
    s.seed = seed;
    s.threads = 2;
    s.splitting.levels = levels;
    // the χ² below takes the bins as independent: actual exits (expected-value exits correlate
    // neighbouring bins; expected_exits_test.cpp checks them split and unsplit)
    s.exits.samples = 0;
    return s;
}

// Every bin of `split` agrees with `plain` (independent runs): |z| < 4 per bin, and over the 24
// bins χ² < 51 (P < 1e-3 for 24 degrees of freedom).
void expectSameProfile(const SlabResult& plain, const SlabResult& split) {
    double chi2 = 0;
    for (size_t b = 0; b < plain.rd.size(); ++b) {
        const double se = std::hypot(plain.rdStderr[b], split.rdStderr[b]);
        ASSERT_GT(se, 0.0) << "bin " << b;
        const double z = (split.rd[b] - plain.rd[b]) / se;
        EXPECT_LT(std::fabs(z), 4.0) << "bin " << b << ": " << split.rd[b] << " vs " << plain.rd[b];
        chi2 += z * z;
    }
    EXPECT_LT(chi2, 51.0);
}

} // namespace

// The same expectation: every bin, the total diffuse reflectance and the absorbed fraction of a
// split run agree with a run without splitting (independent seeds) within |z| < 4.
TEST(Splitting, LeavesTheExpectationOfEveryBinUnchanged) {
    const SlabResult plain = runSlab(kMedium, settings(0, 200000, 1));
    const SlabResult split = runSlab(kMedium, settings(Splitting{}.levels, 100000, 2));
    ASSERT_TRUE(energyProblem(split).empty()) << energyProblem(split);
    expectSameProfile(plain, split);
    EXPECT_LT(std::fabs(split.totalRd - plain.totalRd) /
                  std::hypot(split.totalRdStderr, plain.totalRdStderr),
              4.0);
    EXPECT_LT(std::fabs(split.absorbed - plain.absorbed) /
                  std::hypot(split.absorbedStderr, plain.absorbedStderr),
              4.0);
    // It did split: more interactions per path than the walk without splitting.
    EXPECT_GT(double(split.events) / double(split.paths),
              1.1 * double(plain.events) / double(plain.paths));
}

// The error bars are honest: over 24 independent split runs, each bin's spread matches the
// standard error the runs report. Pooled over the outer bins, Σ (x − x̄)²/se² ~ χ² with
// 23 · bins degrees of freedom; the ratio to its mean lies within ±5 of its standard deviations.
// Copies counted as separate paths would make the reported errors too small (ratio well above 1).
TEST(Splitting, StandardErrorsMatchTheSpreadOfIndependentRuns) {
    const int runs = 24;
    std::vector<SlabResult> r;
    for (int i = 0; i < runs; ++i)
        r.push_back(runSlab(kMedium, settings(Splitting{}.levels, 8000, 100 + uint64_t(i))));
    // the split region
    expectSpreadMatchesStandardErrors(r, r[0].rd.size() / 2);
}

// The purpose: in the outer quarter (3–4 l_d) the variance per path is far lower with splitting
// (3.2x here, at the price of more interactions per path, which `bench pathtrace` weighs in its
// efficiency lines); near the beam, where nothing splits, it is unchanged.
TEST(Splitting, LowersTheVariancePerPathInTheTail) {
    const uint64_t n = 100000;
    const SlabResult plain = runSlab(kMedium, settings(0, n, 7));
    const SlabResult split = runSlab(kMedium, settings(Splitting{}.levels, n, 7));
    auto relVar = [&](const SlabResult& x, size_t b) {
        const double rel = x.rdStderr[b] / x.rd[b];
        return rel * rel * double(x.paths);
    };
    double tailPlain = 0, tailSplit = 0, nearPlain = 0, nearSplit = 0;
    for (size_t b = 18; b < 24; ++b)
        tailPlain += relVar(plain, b), tailSplit += relVar(split, b);
    for (size_t b = 1; b < 3; ++b)
        nearPlain += relVar(plain, b), nearSplit += relVar(split, b);
    EXPECT_LT(tailSplit, tailPlain / 2.5) << tailSplit << " vs " << tailPlain;
    EXPECT_NEAR(nearSplit / nearPlain, 1.0, 0.2);
}

// The analog walk splits too (its copies carry w/2^k; absorption stays a roulette): the same
// expectation as without splitting in every bin (z-tests, χ²) and a lower variance per path in
// the tail.
TEST(Splitting, AnalogWalksSplitWithTheSameExpectation) {
    SlabSettings a0 = settings(0, 200000, 3), a5 = settings(Splitting{}.levels, 100000, 4);
    a0.estimator = a5.estimator = Estimator::Analog;
    const SlabResult plain = runSlab(kMedium, a0);
    const SlabResult split = runSlab(kMedium, a5);
    ASSERT_TRUE(energyProblem(split).empty()) << energyProblem(split);
    expectSameProfile(plain, split);
    EXPECT_LT(std::fabs(split.absorbed - plain.absorbed) /
                  std::hypot(split.absorbedStderr, plain.absorbedStderr),
              4.0);
    double tailPlain = 0, tailSplit = 0;
    for (size_t b = 18; b < 24; ++b) {
        tailPlain += std::pow(plain.rdStderr[b] / plain.rd[b], 2) * double(plain.paths);
        tailSplit += std::pow(split.rdStderr[b] / split.rd[b], 2) * double(split.paths);
    }
    EXPECT_LT(tailSplit, tailPlain / 2) << tailSplit << " vs " << tailPlain;
}
