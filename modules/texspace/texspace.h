// texspace: the parameterisation of texture-space importance sampling (Chang 2007, seed 004,
// §3.1.1): every triangle gets texture coordinates in [0, 1]² without overlaps, and the area
// ratio A_S/A_T of eq. 3.2/3.3 (A_S its area on the surface, A_T its area in the texture), so
// that B(x_o) = ∫_T E′(x_i) R_d(x_i, x_o) dx_i with E′ = E · A_S/A_T integrates over the texture.
//   The mesh's own UVs are used when they qualify (uvProblem: every corner inside [0, 1]², every
//   triangle of positive area on the surface and in the texture, no two triangles overlapping in
//   the texture — touching along edges or at corners is allowed); otherwise a generated atlas
//   (packAtlas): the triangles two by two in the cells of a G × G grid, G = ⌈√⌈T/2⌉⌉, each the
//   lower-left or upper-right half of its cell, corners v0 → (0, 0), v1 → (1, 0), v2 → (0, 1) of
//   the half (mirrored for the upper one), shrunk towards its incentre by a gutter of
//   `gutterTexels` texels of a K × K texture so that bilinear lookups never mix two triangles.
//   Distortion per triangle: the affine map texture → surface has singular values σ1 ≥ σ2;
//   stretch = σ1/σ2 (1: similar shapes; the atlas maps every triangle onto a right isosceles
//   one, so an equilateral triangle has √3).
//   Overlap test: triangles binned by bounding box on a uniform grid, each candidate pair by the
//   separating-axis theorem on the six edge normals, an overlap only when the interiors overlap
//   by more than 1e-9 (relative to [0, 1]²).
#pragma once

#include "mesh/mesh.h"

#include <glm/vec2.hpp>

#include <array>
#include <string>
#include <vector>

namespace texspace {

struct Parameterization {
    std::vector<std::array<glm::dvec2, 3>> uv; // per triangle corner, in [0, 1]²
    std::vector<double> areaSurface;           // A_S per triangle (mesh units²)
    std::vector<double> areaTexture;           // A_T per triangle ([0, 1]² units)
    std::vector<double> stretch;               // σ1/σ2 of texture → surface, >= 1
    bool fromMesh = false;                     // the mesh's own UVs
    std::string note;                          // why the atlas was used
    int gridCells = 0;                         // atlas: G
    double areaRatio(size_t t) const { return areaSurface[t] / areaTexture[t]; }
};

// "" when the mesh's UVs qualify (see above), else the first problem, naming the triangle(s)
// (0-based indices) and, for an overlap, both.
std::string uvProblem(const mesh::Mesh& m);
// The same test on per-triangle texture coordinates (e.g. an atlas).
std::string uvProblem(const std::vector<std::array<glm::dvec2, 3>>& uv,
                      const std::vector<double>& areaSurface);

// The atlas of the mesh's triangles for a textureSize² texture (textureSize >= 2); throws
// core::Error("atlas", 0, …) when a triangle has no area or the cells would be smaller than
// the gutters.
Parameterization packAtlas(const mesh::Mesh& m, int textureSize, double gutterTexels = 1.0);

// The mesh's UVs when uvProblem() is empty, else the atlas with `note` saying why.
Parameterization parameterize(const mesh::Mesh& m, int textureSize);

} // namespace texspace
