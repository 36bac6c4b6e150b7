// irradiance/env_sampling: stratified, luminance-weighted environment samples (see
// env_sampling.h).
#include "irradiance/env_sampling.h"

#include "core/color.h"
#include "core/core.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace irradiance {
namespace {

uint64_t splitMix64(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
// Uniform double in [0, 1) from 53 bits of the stream (seed, index, lane).
double uniform(uint64_t seed, uint64_t index, uint64_t lane) {
    const uint64_t h = splitMix64(splitMix64(seed ^ splitMix64(index)) + lane);
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}
} // namespace

std::vector<EnvSample> sampleEnvironment(const EnvironmentMap& env, int count, uint64_t seed) {
    validateEnvironment(env, "environment");
    if (count < 1) throw core::Error("environment sample count must be >= 1");
    const int W = env.width, H = env.height;
    const size_t n = static_cast<size_t>(W) * H;
    std::vector<double> lum(n), omega(H);
    double total = 0;
    for (int y = 0; y < H; ++y) {
        omega[y] = texelSolidAngle(y, W, H);
        for (int x = 0; x < W; ++x) {
            const glm::vec3 L = env.texel(x, y);
            const size_t i = static_cast<size_t>(y) * W + x;
            lum[i] = core::luminance(glm::dvec3(L));
            total += omega[y] * lum[i];
        }
    }
    const double delta = total > 0 ? 0.05 * total / (4.0 * std::numbers::pi) : 1.0;
    std::vector<double> cdf(n + 1, 0.0);
    for (size_t i = 0; i < n; ++i)
        cdf[i + 1] = cdf[i] + omega[i / W] * (lum[i] + delta);
    const double sum = cdf[n];

    std::vector<EnvSample> samples(static_cast<size_t>(count));
    for (int k = 0; k < count; ++k) {
        const double u = (k + uniform(seed, k, 0)) / count * sum;
        // first texel whose upper CDF bound exceeds u
        size_t i = static_cast<size_t>(std::upper_bound(cdf.begin() + 1, cdf.end(), u) -
                                       (cdf.begin() + 1));
        i = std::min(i, n - 1);
        while (cdf[i + 1] == cdf[i] && i + 1 < n) // zero-probability texel (cannot happen, δ > 0)
            ++i;
        const int x = static_cast<int>(i % W), y = static_cast<int>(i / W);
        const double mu0 = std::cos(std::numbers::pi * y / H),
                     mu1 = std::cos(std::numbers::pi * (y + 1) / H);
        const double mu = mu0 + (mu1 - mu0) * uniform(seed, k, 1);
        const double phi = 2.0 * std::numbers::pi * (x + uniform(seed, k, 2)) / W;
        const double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        const double p = (cdf[i + 1] - cdf[i]) / sum; // P_i
        const double pdf = p / omega[y];
        EnvSample& e = samples[static_cast<size_t>(k)];
        e.direction = glm::vec3(static_cast<float>(s * std::cos(phi)), static_cast<float>(mu),
                                static_cast<float>(s * std::sin(phi)));
        e.pdf = static_cast<float>(pdf);
        e.weight = env.texel(x, y) * static_cast<float>(1.0 / pdf);
    }
    // Fisher–Yates with its own stream (lane 3), so prefixes are random subsets of strata.
    for (int k = count - 1; k > 0; --k) {
        const int j = static_cast<int>(uniform(seed, k, 3) * (k + 1));
        std::swap(samples[static_cast<size_t>(k)], samples[static_cast<size_t>(std::min(j, k))]);
    }
    return samples;
}

} // namespace irradiance
