// pointcloud: point clouds covering a triangle mesh surface, for the hierarchical (Jensen–Buhler)
// multiple-scattering evaluation (thesis 2.6.4, 3.3.1). Every point carries a position, a unit
// normal, its surface area p_a (Σ p_a = A, the mesh area; uniform clouds use p_a = A/N) and the
// index of the triangle it lies on.
//   sampleUniform: area-weighted uniform random sampling — the triangle is chosen by binary
//     search in the cumulative area table, the position by uniform barycentrics (the sqrt
//     trick: b0 = 1 − √u1, b1 = u2·√u1). Random numbers are counter based (SplitMix64 of the
//     seed and the sample index), so the result is identical for any thread count.
//   relaxRepulsion: Turk's point repulsion (1992; thesis 2.6.4): each iteration every point
//     moves by the sum of repulsive forces from the neighbours within r = 2·√(A/(N·π)), the
//     move projected into its tangent plane and clamped, then re-projected onto the mesh (the
//     closest point on the nearby triangles, found in a uniform grid of triangles, see
//     relaxation.cpp). Double buffered, so parallel and deterministic.
//   sampleElimination: weighted sample elimination (Yuksel 2015) from a uniform candidate set
//     (candidateFactor·N), survivors keep their exact surface positions.
//   sampleStratified / sampleStratifiedRepulsion: a stratified initial set (Morton-ordered
//     triangles, triangular van der Corput points) relaxed by a fast Turk repulsion (compact
//     cubic kernel, heavy-ball momentum, Verlet lists, local re-projection; fast_relaxation.cpp).
//   measureUniformity: nearest-neighbour distance statistics (hash grid).
//   writePly / readPly: binary little-endian PLY (x y z nx ny nz area float32, triangle
//     uint32), the cache format; cacheKey names a cache entry from the mesh bytes, the
//     parameters and the cache format.
// Errors are core::Error(file, 0, message).
#pragma once

#include "mesh/mesh.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace pointcloud {

struct Point {
    float p[3];
    float n[3];
    float area;
    uint32_t triangle; // index into mesh.triangles; kNoTriangle when unknown (loaded from PLY)
};
inline constexpr uint32_t kNoTriangle = 0xffffffffu;

struct PointCloud {
    std::vector<Point> points;
    double totalArea = 0; // A, the sampled mesh's surface area
};

// Total surface area of the mesh (sum of triangle areas, double precision).
double meshArea(const mesh::Mesh& m);

// N points uniformly distributed over the surface (see above), each with area A/N and the
// normal interpolated from the vertex normals (normalised; the face normal when the mesh has
// none). threads: 0 = all cores; the result does not depend on it. Throws core::Error when the
// mesh has no area or n == 0.
PointCloud sampleUniform(const mesh::Mesh& m, size_t n, uint64_t seed, int threads = 0);

// Called after every relaxation iteration with (iterations done, iterations in all).
using IterationProgress = std::function<void(int done, int total)>;

struct RepulsionOptions {
    int iterations = 30;
    double radiusScale = 1.0;   // r = radiusScale · 2·√(A/(N·π))
    double stepScale = 0.3;     // move = stepScale · r · Σ_j (1 − d_ij/r)·(p_i − p_j)/d_ij
    int threads = 0;            // 0 = all cores; the result does not depend on it
    IterationProgress progress; // may be empty
};
// Turk's point repulsion applied to `initial` (points of `m`); areas stay A/N.
PointCloud relaxRepulsion(const mesh::Mesh& m, const PointCloud& initial,
                          const RepulsionOptions& options = {});

struct EliminationOptions {
    double candidateFactor = 5.0; // candidates = ceil(candidateFactor · N), from sampleUniform
    int threads = 0;              // 0 = all cores; the result does not depend on it
};
// Weighted sample elimination (Yuksel 2015): exactly N points, areas A/N.
//   r_max = √(A / (2√3·N)) (Yuksel's bound for N points on a surface of area A, the radius of
//   the densest hexagonal packing); w_i = Σ_{j: d_ij < 2 r_max} (1 − d_ij/(2 r_max))^8; the
//   sample of highest weight (ties: lowest index) is removed and its neighbours' weights
//   reduced (indexed max-heap) until N remain. Yuksel's weight limiting (r_min) is not used.
PointCloud sampleElimination(const mesh::Mesh& m, size_t n, uint64_t seed,
                             const EliminationOptions& options = {});

// Stratified sampling (no randomness beyond one offset per triangle): the triangles are put in
// Morton order of their centroids, triangle t of that order gets
//   k_t = round(N·C_t/A) − round(N·C_{t−1}/A) points (C_t the cumulative area, Σ k_t = N),
// placed at consecutive points of the triangular van der Corput sequence (Basu & Owen 2015,
// "Low discrepancy constructions in the triangle") starting at a random index drawn from
// (seed, t). Areas A/N, normals interpolated as in sampleUniform; thread independent.
PointCloud sampleStratified(const mesh::Mesh& m, size_t n, uint64_t seed, int threads = 0);

struct StratifiedRepulsionOptions {
    int iterations = 40;
    double radiusScale = 2.0;   // kernel radius R = radiusScale · d_hex, d_hex = √(2A/(√3·N))
    double stepScale = 0.5;     // gradient step = stepScale · d_hex
    double momentum = 0.7;      // heavy-ball coefficient β, in [0, 1)
    int threads = 0;            // 0 = all cores; the result does not depend on it
    IterationProgress progress; // may be empty
};
// Fast even point cloud: sampleStratified, then Turk-style repulsion (Turk 1992) with a compact
// cubic kernel and heavy-ball momentum (Polyak 1964):
//   v_i ← T_i [ β·v_i + stepScale·d_hex · Σ_{j: d_ij < R} (1 − d_ij/R)³ (p_i − p_j)/d_ij ]
//   p_i ← closest surface point to p_i + clamp(v_i, d_hex/2),  v_i ← the actual move,
// T_i the projection into the tangent plane of p_i's normal. Neighbours come from Verlet lists
// (Verlet 1967) of radius R + d_hex/2, rebuilt on a fixed schedule; the re-projection searches
// only the triangles within d_hex of the point's current triangle (precomputed), with the same
// closest-point rule and facing test as relaxRepulsion. Double buffered: deterministic for any
// thread count. Exactly N points on triangles of m, areas A/N, in Morton order.
PointCloud sampleStratifiedRepulsion(const mesh::Mesh& m, size_t n, uint64_t seed,
                                     const StratifiedRepulsionOptions& options = {});

struct Uniformity {
    double meanNN = 0; // mean nearest-neighbour distance
    double minNN = 0;  // smallest nearest-neighbour distance
    double maxNN = 0;  // largest nearest-neighbour distance
    double cvNN = 0;   // coefficient of variation (standard deviation / mean)
};
// Euclidean nearest-neighbour distances (hash grid); all zero for fewer than two points.
Uniformity measureUniformity(const PointCloud& cloud, int threads = 0);

// Binary little-endian PLY: "element vertex N" with float properties x y z nx ny nz area, the
// uint property triangle, and a "comment total_area <%.17g>" line, so a cloud read back is
// bitwise the cloud written (a capture hashes the points; the cache must not change them).
// Atomic write (core::writeFile). readPly also accepts the layout without triangle (files of
// other programs: kNoTriangle), sets totalArea to the comment's value (the sum of the areas when
// it is missing), and throws core::Error(path, 0, ...) for anything else (bad magic, format,
// element, property list, missing end_header, truncated or oversized data).
void writePly(const std::filesystem::path& path, const PointCloud& cloud);
PointCloud readPly(const std::filesystem::path& path);

// Cache key: the 16 hex digits of core::hashHex over the mesh's vertex and triangle bytes
// followed by "|n|method|seed|kCacheFormat" (the "fnv1a64:" prefix dropped so the key is a safe
// file name). kCacheFormat changes whenever a cache file written before could differ from what
// this build generates (layout or generation), so no earlier version's cache file is read.
inline constexpr const char* kCacheFormat = "cache2"; // 2: triangles stored
std::string cacheKey(const mesh::Mesh& m, size_t n, const std::string& method, uint64_t seed);

} // namespace pointcloud
