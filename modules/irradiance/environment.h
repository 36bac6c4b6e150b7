// irradiance/environment: lat-long (equirectangular) environment maps for image based lighting
// (thesis 3.3.2, "Image Based Lighting"), their EXR I/O, the quadrature weights used by the
// irradiance cubemap and the generator of the shipped default sky.
//   Convention. Texel (x, y) of a W × H map, row 0 at the top, covers
//     φ ∈ [2π·x/W, 2π·(x+1)/W),  θ ∈ [π·y/H, π·(y+1)/H)      (θ from +y, the zenith)
//   and the direction of (θ, φ) is  ω = (sin θ cos φ, cos θ, sin θ sin φ)  in the environment's
//   frame (y up). Radiance is piecewise constant over texels; a texel's solid angle is
//     Ω = (2π/W)·(cos θ_top − cos θ_bottom).
//   The world frame is the environment frame rotated by Settings::envRotation about +y.
//   Files: OpenEXR, channels R, G, B (HALF or FLOAT; others ignored), finite and >= 0.
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace irradiance {

struct EnvironmentMap {
    int width = 0, height = 0;
    std::vector<float> rgb; // 3 floats per texel, row 0 (θ = 0, the zenith) first
    glm::vec3 texel(int x, int y) const {
        const size_t i = 3 * (static_cast<size_t>(y) * static_cast<size_t>(width) + x);
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

// ω(θ, φ) of the convention above.
glm::vec3 latLongDirection(double theta, double phi);
// The world-from-environment rotation R_y(a) about +y: (1, 0, 0) -> (cos a, 0, −sin a),
// (0, 0, 1) -> (sin a, 0, cos a).
glm::mat3 worldFromEnvironment(float rotation);
// Solid angle of the texels of row y (all texels of a row have the same).
double texelSolidAngle(int y, int width, int height);

// Throws core::Error(name, 0, ...) unless 1 <= width, height <= 16384, rgb has 3·W·H values and
// every value is finite and >= 0 (the message names the first bad texel and channel).
void validateEnvironment(const EnvironmentMap& env, const std::string& name);

// Reads a lat-long EXR. Throws core::Error(path, 0, ...) when the file is missing, not an EXR or
// truncated, lacks an R, G or B channel, has more than 8192x4096 texels, or holds non-finite or
// negative values.
EnvironmentMap readEnvironment(const std::filesystem::path& path);
// Writes R, G, B as FLOAT, ZIP compressed (atomic; round trips bitwise).
void writeEnvironment(const std::filesystem::path& path, const EnvironmentMap& env);

// The default sky (materials/env/default_sky.exr was written by writeDefaultEnvironment):
// sky radiance blue at the zenith fading to a pale horizon, a warm Gaussian sun blob
// (σ = 4°) at elevation 35°, azimuth φ = 30°, and a dark brown ground, each texel evaluated at
// its centre direction.
EnvironmentMap makeDefaultSky(int width = 128, int height = 64);
void writeDefaultEnvironment(const std::filesystem::path& path);

// Quadrature nodes of the irradiance integral over a lat-long map: every texel split into
// sub × sub equal-solid-angle cells (φ uniform, cos θ uniform), each cell a node at its
// centre (φ mid, cos θ mid) with weight L·Ω_cell. Nodes with L = 0 are dropped (they add
// nothing). Maps wider than maxWidth are first box-filtered 2 × 2 (solid-angle weighted per
// row pair) until they fit, which keeps ∫L dω over every merged cell exact.
struct QuadratureNode {
    glm::vec3 direction; // environment frame
    glm::vec3 weight;    // L · Ω (RGB)
};
std::vector<QuadratureNode> quadratureNodes(const EnvironmentMap& env, int sub = 2,
                                            int maxWidth = 256);

} // namespace irradiance
