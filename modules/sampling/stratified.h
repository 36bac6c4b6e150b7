// sampling/stratified: Latin-hypercube blocks of samples (McKay, Beckman & Conover 1979), for
// the estimators of integrate/integrate.h.
//   A pixel's samples are taken in blocks of K = kBlockSamples. Block b draws one random
//   permutation π_d of the K strata per stratified dimension d; its sample k uses
//       u_d = (π_d(k) + ξ) / K,   ξ uniform on [0, 1),
//   so the block's K samples cover each dimension's K strata once (a Latin hypercube), and the
//   permutations pair the strata of different dimensions at random.
//   Why any prefix of a block is unbiased: sample k's stratum π_d(k) is uniform over the K strata
//   (a uniformly random permutation), so each u_d is marginally uniform on [0, 1) and every single
//   sample is an unbiased estimate; a mean over any number of samples is unbiased, a block cut
//   short by a cancel or an odd sample count included (the strata it got are a sample without
//   replacement).
//   Variance: the samples of a block are not independent (negatively correlated: that is the
//   gain), so the variance of a mean comes from whole blocks, each block's mean being an
//   independent draw (blockVarianceOfMean below).
//   The permutations come from the caller's generator (Fisher–Yates), so they are reproducible
//   from (seed, pixel, block) like the samples themselves.
//   Where it is used: the disk estimator (integrate/image_integrator.cpp) stratifies the
//   strategy-with-radius uniform of DiskSampler::probe and the angle. Its selection of an axis
//   and a channel at random (one-sample MIS) adds a per-sample variance of about (1/P_N − 1)
//   times the squared mean on a smooth surface (README, Importance sampling): stratified, each
//   block gets its strategies' counts in proportion, and each strategy its radii spread over
//   its distribution. Uniform area sampling keeps independent samples: its error comes from the
//   rare samples near the shading point, which stratifying two coordinates does not control
//   (bench sampling measured no gain), and its heavy tail makes a block-based variance from few
//   blocks less trustworthy than the independent-sample one.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <utility>

namespace sampling {

constexpr int kBlockSamples = 16;

// One random permutation of the strata 0 … K−1 per stratified dimension.
template <int Dims> struct BlockStrata {
    std::array<std::array<uint8_t, kBlockSamples>, Dims> perm{};

    template <class Rng> static BlockStrata draw(Rng& rng) {
        BlockStrata s;
        for (auto& p : s.perm) {
            for (int i = 0; i < kBlockSamples; ++i)
                p[size_t(i)] = uint8_t(i);
            for (int i = kBlockSamples - 1; i > 0; --i) { // Fisher–Yates
                const int j = int(rng.uniform() * (i + 1));
                std::swap(p[size_t(i)], p[size_t(j < i ? j : i)]);
            }
        }
        return s;
    }
    // u_d of the block's sample k from a uniform xi in [0, 1).
    double u(int d, int k, double xi) const {
        const double v = (double(perm[size_t(d)][size_t(k)]) + xi) / kBlockSamples;
        return v < 1.0 ? v : 0x1.fffffffffffffp-1; // never 1 (rounding of K−1 + ξ)
    }
};

// The variance of the mean of n independent samples, s²/n (s² with n − 1); infinite for n < 2
// unless every sample was 0.
inline double independentVarianceOfMean(uint64_t n, double sum, double sumSq) {
    if (n < 2) return sum == 0 && sumSq == 0 ? 0.0 : std::numeric_limits<double>::infinity();
    const double nd = double(n), mean = sum / nd;
    return (sumSq > nd * mean * mean ? (sumSq - nd * mean * mean) / (nd - 1) : 0.0) / nd;
}

// The variance of the mean of n samples taken in blocks of K (n = m·K + r): the m whole blocks'
// sums B_i give the block variance s_B² (m >= 2), the r samples of the last block count as
// independent ones with the per-sample variance s² (an upper bound: sampling strata without
// replacement only lowers it):
//     Var(mean) ≈ (m·s_B² + r·s²) / n²,   s_B² the sample variance of the B_i.
// With fewer than two whole blocks it is the independent-sample formula s²/n, again an upper
// bound. sum and sumSq run over all n samples; blockSum and blockSumSq over the whole blocks'
// sums B_i and their squares. Infinite for n < 2 unless every sample was 0.
inline double blockVarianceOfMean(uint64_t n, double sum, double sumSq, double blockSum,
                                  double blockSumSq) {
    const uint64_t m = n / uint64_t(kBlockSamples);
    if (m < 2) return independentVarianceOfMean(n, sum, sumSq);
    const double nd = double(n);
    const double s2 = independentVarianceOfMean(n, sum, sumSq) * nd;
    const double md = double(m), r = double(n - m * uint64_t(kBlockSamples));
    const double bMean = blockSum / md;
    const double sB2 =
        blockSumSq > md * bMean * bMean ? (blockSumSq - md * bMean * bMean) / (md - 1) : 0.0;
    return (md * sB2 + r * s2) / (nd * nd);
}

} // namespace sampling
