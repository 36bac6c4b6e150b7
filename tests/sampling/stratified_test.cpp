// sampling/stratified: the Latin-hypercube blocks and their variance. Each block's strata are
// permutations; every u is marginally uniform (chi-square); a block of a smooth integrand has far
// less variance than independent samples; means over whole blocks and over a cut-short block
// are unbiased (z-test against the closed-form integral); and blockVarianceOfMean is calibrated:
// the z-scores of many independent runs have the variance of Student's t (not the much smaller
// one the independent-sample formula would give), against ∫∫ (u0² + u0·u1) = 1/3 + 1/4.
#include "sampling_support.h"

#include "pathtrace/rng.h"
#include "sampling/stratified.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace sampling;

namespace {
constexpr int kK = kBlockSamples;
constexpr double kStrataExact = 1.0 / 3 + 1.0 / 4;
double strataIntegrand(double u0, double u1) {
    return u0 * u0 + u0 * u1;
}

struct StrataTally {
    uint64_t n = 0;
    double sum = 0, sumSq = 0, blockSum = 0, blockSumSq = 0, partial = 0;
    void add(double v) {
        sum += v;
        sumSq += v * v;
        partial += v;
        if (++n % kK == 0) {
            blockSum += partial;
            blockSumSq += partial * partial;
            partial = 0;
        }
    }
    double mean() const { return sum / double(n); }
    double variance() const { return blockVarianceOfMean(n, sum, sumSq, blockSum, blockSumSq); }
};

// n samples of the integrand, blocks drawn as the integrator draws them.
StrataTally strataRun(uint64_t seed, int n) {
    StrataTally r;
    BlockStrata<2> strata;
    for (int s = 0; s < n; ++s) {
        if (s % kK == 0) {
            pathtrace::Pcg32 prng = pathtrace::Pcg32::forPath(seed, uint64_t(s / kK));
            strata = BlockStrata<2>::draw(prng);
        }
        pathtrace::Pcg32 rng = pathtrace::Pcg32::forPath(seed ^ 0xabcdefull, uint64_t(s));
        const double u0 = strata.u(0, s % kK, rng.uniform());
        const double u1 = strata.u(1, s % kK, rng.uniform());
        r.add(strataIntegrand(u0, u1));
    }
    return r;
}
} // namespace

TEST(Stratified, BlocksArePermutationsAndEachUIsUniform) {
    constexpr int kBins = 32;
    std::vector<double> obs(kBins, 0), exp(kBins, 0);
    int samples = 0;
    for (uint64_t b = 0; b < 4000; ++b) {
        pathtrace::Pcg32 rng = pathtrace::Pcg32::forPath(7, b);
        const BlockStrata<2> s = BlockStrata<2>::draw(rng);
        for (int d = 0; d < 2; ++d) {
            std::array<uint8_t, kK> sorted = s.perm[size_t(d)];
            std::sort(sorted.begin(), sorted.end());
            for (int i = 0; i < kK; ++i)
                ASSERT_EQ(sorted[size_t(i)], i);
        }
        // sample 3's u in dimension 1 only: marginally uniform over [0, 1)
        const double u = s.u(1, 3, rng.uniform());
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        obs[size_t(u * kBins)] += 1;
        ++samples;
        EXPECT_LT(s.u(0, 0, 1.0), 1.0); // never 1, even from a ξ rounded up to 1
    }
    for (double& e : exp)
        e = samples / double(kBins);
    EXPECT_GT(pttest::chiSquare(obs, exp).pValue, 1e-3);
}

TEST(Stratified, WholeBlocksAndACutShortBlockAreUnbiased) {
    // 2000 runs each of 4 whole blocks, and of one block and 5 samples: the mean of the runs'
    // means against the exact integral, with the runs' spread as the error (independent runs)
    for (int n : {4 * kK, kK + 5}) {
        double s = 0, s2 = 0;
        constexpr int kRuns = 2000;
        for (int i = 0; i < kRuns; ++i) {
            const double m = strataRun(uint64_t(1000 + i) * 7919u + uint64_t(n), n).mean();
            s += m;
            s2 += m * m;
        }
        const double mean = s / kRuns, var = (s2 / kRuns - mean * mean) / (kRuns - 1);
        EXPECT_LT(std::fabs(mean - kStrataExact) / std::sqrt(var), core::bonferroniZ(1e-3, 2)) << n;
    }
}

TEST(Stratified, BlocksHaveFarLessVarianceThanIndependentSamples) {
    // the same integrand, 64 blocks: block variance against the per-sample one
    const StrataTally r = strataRun(3, 64 * kK);
    const double n = double(r.n), mean = r.mean();
    const double iid = (r.sumSq / n - mean * mean) / (n - 1);
    EXPECT_LT(r.variance(), iid / 10) << "block " << r.variance() << " independent " << iid;
    EXPECT_GT(r.variance(), 0.0);
}

TEST(Stratified, TheBlockVarianceIsCalibrated) {
    // z = (mean − exact)/√var over 400 independent runs of 64 blocks: t with 63 degrees of
    // freedom, E[z²] = 63/61, sd of the average of 400 z² about 0.074 (t²'s variance ≈ 2.2).
    constexpr int kRuns = 400;
    double z2 = 0;
    for (int i = 0; i < kRuns; ++i) {
        const StrataTally r = strataRun(uint64_t(50000 + i), 64 * kK);
        const double z = (r.mean() - kStrataExact) / std::sqrt(r.variance());
        z2 += z * z;
    }
    const double avg = z2 / kRuns;
    EXPECT_GT(avg, 63.0 / 61 - 5 * 0.074) << avg;
    EXPECT_LT(avg, 63.0 / 61 + 5 * 0.074) << avg;
}

TEST(Stratified, VarianceFormula) {
    // fewer than two whole blocks: the independent-sample formula
    StrataTally a;
    for (int i = 0; i < kK + 3; ++i)
        a.add(double(i % 4));
    const double n = double(a.n), m = a.mean();
    EXPECT_DOUBLE_EQ(a.variance(), (a.sumSq / n - m * m) * n / (n - 1) / n);
    // two whole blocks with equal sums and 3 more samples: s_B² = 0, only r·s²/n² remains
    StrataTally b;
    for (int i = 0; i < 2 * kK + 3; ++i)
        b.add(double(i % kK)); // each whole block sums to kK(kK−1)/2
    const double nb = double(b.n), mb = b.mean();
    const double s2 = (b.sumSq - nb * mb * mb) / (nb - 1);
    EXPECT_NEAR(b.variance(), 3 * s2 / (nb * nb), 1e-12 * s2);
    // nothing but zeros: 0; one non-zero sample: unknown
    EXPECT_EQ(blockVarianceOfMean(1, 0, 0, 0, 0), 0.0);
    EXPECT_TRUE(std::isinf(blockVarianceOfMean(1, 2, 4, 0, 0)));
}
