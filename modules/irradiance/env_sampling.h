// irradiance/env_sampling: the environment samples of occluded image based lighting (thesis
// 3.3.2: "we choose the same samples for all points ... pick a sample on the environment map
// and treat it as a directional light source").
//   Texel i is chosen with probability P_i ∝ Ω_i·(Y_i + δ), Y the luminance
//   0.2126 R + 0.7152 G + 0.0722 B, δ = 0.05 · (Σ Ω_i Y_i)/4π (5 % of the mean luminance, so
//   every direction keeps a positive density; uniform in solid angle when the map is black);
//   the direction is uniform in solid angle inside the texel (φ and cos θ uniform). The density
//   per solid angle is pdf(ω) = P_i/Ω_i and a sample's weight is L_i/pdf(ω) (RGB), so
//     E_t(p) ≈ (1/K) Σ_k weight_k · Ft(n·ω_k) · max(0, n·ω_k) · V(p, ω_k)
//   is unbiased. The texel choice is stratified (sample k inverts the CDF at (k + ξ_k)/K) and
//   the K samples are then shuffled (Fisher–Yates), so every prefix is a random subset of the
//   strata and partial sums are unbiased too. Random numbers: SplitMix64 of (seed, index).
#pragma once

#include "irradiance/environment.h"

#include <cstdint>
#include <vector>

namespace irradiance {

struct EnvSample {
    glm::vec3 direction; // unit, environment frame
    glm::vec3 weight;    // L(ω) / pdf(ω), RGB
    float pdf = 0;       // per steradian
};

// `count` samples (count >= 1) for `seed`; identical for identical inputs.
std::vector<EnvSample> sampleEnvironment(const EnvironmentMap& env, int count, uint64_t seed);

} // namespace irradiance
