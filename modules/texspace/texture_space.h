// texspace/texture_space: stages 1 and 2 of texture-space importance sampling (Chang 2007,
// seed 004, §3.2.2) on the CPU side.
//   Texels: the parameterisation rasterised into a K × K texture, a texel covered when its
//   centre lies inside a triangle's texture image (edge functions, top-left rule, so a centre
//   on a shared edge belongs to exactly one triangle); per covered texel the surface point and
//   the interpolated vertex normal at that centre, its triangle and the area ratio A_S/A_T of
//   eq. 3.2. Stage 1 fills E′ = E_t · A_S/A_T per texel (E_t from the irradiance of the point
//   cloud pipeline, evaluated at the texel points).
//   Mip-ordered CDF (Fig. 3.3b): level 0 the K × K texel weights w (E′ · A_texel, luminance for
//   the choice), each coarser level the sum of its 2 × 2 children, up to one value; Algorithm 3.1
//   draws a texel by descending from the top: at each level the child j is chosen whose running
//   sum first exceeds u · (sum of the four), u rescaled into that child, so that texel t is drawn
//   with probability w_t / Σ w (sampleMip). The seed paper's pseudo-code keeps averages and
//   multiplies by 4; sums are the same order without the factor. Within the texel the point is
//   the texel's surface point (the centre), so the estimator of eq. 3.5 is a sum over texels.
#pragma once

#include "mesh/mesh.h"
#include "texspace/texspace.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace texspace {

struct Texels {
    int size = 0;                     // K
    std::vector<int32_t> triangle;    // per texel (row-major, v up), −1: not covered
    std::vector<glm::dvec3> position; // surface point at the texel centre (mesh units)
    std::vector<glm::dvec3> normal;   // interpolated vertex normal, unit
    std::vector<double> areaRatio;    // A_S/A_T of its triangle (mesh units² per [0,1]² unit)
    size_t covered = 0;
};

// Rasterises `p` (from parameterize / packAtlas of `m`) into size × size texels (2 … 8192).
Texels rasterize(const mesh::Mesh& m, const Parameterization& p, int size);

// The mip pyramid of sums over a size × size (power of two) weight texture: levels[0] = the
// weights (row-major), levels.back() = one value.
struct MipCdf {
    int size = 0;
    std::vector<std::vector<double>> levels;
    double total() const { return levels.back()[0]; }
};
// Throws core::Error("texture space", 0, …) when size is not a power of two, a weight is
// negative or not finite, or all are 0.
MipCdf buildMipCdf(const std::vector<double>& weights, int size);
// Algorithm 3.1: the texel (row-major index) drawn with probability w_t / Σ w for u in [0, 1).
uint32_t sampleMip(const MipCdf& cdf, double u);

} // namespace texspace
