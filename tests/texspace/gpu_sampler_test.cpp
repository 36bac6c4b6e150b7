// Stage 2 of texture-space sampling on the GPU (texspace/gpu_sampler.h, Algorithm 3.1 in
// shaders/texspace_sample.comp) against the CPU descent (sampleMip) with the same u: the same
// texel except where float and double sums put u on different sides of a child boundary (at most
// 1e-3 of the draws); no texel without weight is ever drawn; the draws pass a chi-square test
// against w_t / Σ w; samples do not depend on how they are split into dispatches.
#include "../support/gl_fixture.h"
#include "texspace/gpu_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

TEST(TextureSpaceGpu, DescentMatchesTheCpuReplicaAndItsDistribution) {
    testsupport::context();
    const int size = 64;
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u01(0, 1);
    std::vector<double> w(size * size);
    for (double& x : w)
        x = u01(rng) < 0.3 ? 0.0 : std::exp(4 * u01(rng)); // zeros and three decades
    const texspace::MipCdf cdf = texspace::buildMipCdf(w, size);
    texspace::GpuSampler gpu(shader::Sources{testsupport::sourceRoot()});
    gpu.setCdf(cdf);
    const uint64_t n = 400000;
    const std::vector<texspace::GpuSample> s = gpu.draw(n, 5);
    ASSERT_EQ(s.size(), n);
    size_t mismatches = 0;
    std::vector<double> count(w.size(), 0);
    for (const auto& x : s) {
        ASSERT_LT(x.texel, w.size());
        ASSERT_GE(x.u, 0.0);
        ASSERT_LT(x.u, 1.0);
        mismatches += texspace::sampleMip(cdf, x.u) != x.texel;
        count[x.texel] += 1;
    }
    EXPECT_LE(mismatches, n / 1000) << mismatches << " of " << n;
    double chi2 = 0;
    int dof = -1;
    for (size_t k = 0; k < w.size(); ++k) {
        if (w[k] == 0) {
            EXPECT_EQ(count[k], 0) << "texel " << k << " has no weight";
            continue;
        }
        const double expected = double(n) * w[k] / cdf.total();
        chi2 += (count[k] - expected) * (count[k] - expected) / expected;
        ++dof;
    }
    // normal approximation of χ² with ν dof, one-sided p = 1e-3
    EXPECT_LT((chi2 - dof) / std::sqrt(2.0 * dof), 3.09) << "chi2 " << chi2 << " dof " << dof;
    // samples 1000 … 1999 drawn on their own are the same as within the big dispatch
    const std::vector<texspace::GpuSample> part = gpu.draw(1000, 5, 1000);
    for (size_t i = 0; i < part.size(); ++i) {
        EXPECT_EQ(part[i].texel, s[1000 + i].texel) << i;
        EXPECT_EQ(part[i].u, s[1000 + i].u) << i;
    }
}
