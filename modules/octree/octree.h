// octree: the point-cloud octree of the hierarchical (Jensen–Buhler) evaluation, thesis 2.6.4,
// 3.3.1 and 3.3.3 (Figs. 3.4, 3.5, Algorithm 2), and a CPU replica of its GLSL traversal.
//
// Build (thesis 3.3.1). Start with every point in one array. A node's centre is the mean of its
// points' positions (float sums accumulated in double); each point gets the octant index
//   o = (x >= cx ? 1 : 0) | (y >= cy ? 2 : 0) | (z >= cz ? 4 : 0)
// and the node's slice is reordered by a stable counting sort on o. Every non-empty octant
// becomes a child, in increasing o. A set of at most kMaxLeafPoints points is a leaf. Nodes are
// numbered breadth first, so all children of a node are contiguous (Fig. 3.4) and node 0 is
// the root. Coincident points (a zero-size box with more than kMaxLeafPoints points) become one
// leaf when there are at most 15 (the 4-bit point count); more are refused.
//
// Child descriptor (Fig. 3.5), one uint32 per node:
//   bits 0–3  child count (0 for a leaf)
//   bits 4–7  point count (0 for an interior node)
//   bits 8–31 index: first child (interior) or first point in Octree::points (leaf)
// Limits: more than 2^24 nodes or points, or a depth that needs more than kStackSize stack
// entries (a leaf at depth d needs d − 1: the root is never pushed) is refused with a
// core::Error naming the limit — never silently wrong.
//
// Node attributes (thesis 3.3.3), one NodeRecord per node:
//   irradianceArea = (Σ E_i·A_i (RGB), Σ A_i) over the node's points
//   meanPosition   = Σ w_i·p_i / Σ w_i with w_i = (E_r + E_g + E_b)·A_i (irradiance weighted);
//                    the area-weighted mean when Σ w_i = 0 (an unlit node)
//   boxMin, boxMax = bounding box of the node's points
//   covarianceDiagonal, covarianceOffDiagonal = the weighted covariance of the points about
//                    the mean, Σ = Σ_i w_i (p_i − P)(p_i − P)ᵀ / Σ_i w_i (mesh units², same
//                    weights as meanPosition), computed as Σ w p pᵀ / Σ w − P Pᵀ with the
//                    double mean P and clamped to >= 0 on the diagonal:
//                    diagonal (Σxx, Σyy, Σzz, 0), off-diagonal (Σxy, Σxz, Σyz, 0)
// All sums are accumulated in double and stored as float.
//
// Traversal (thesis Algorithm 2; the GLSL in shaders/octree_render.comp does exactly this).
// The stack holds uint32 entries  node << 8 | childnum  (node index in the upper 24 bits, the
// number of siblings still to visit in the lower 8), at most kStackSize of them.
//   node = 0, childnum = 0
//   loop:
//     if subdivide(node):                         // interior node whose criterion fails
//       if node != 0: push(node << 8 | childnum)  //   overflow -> flag kFlagStackOverflow, stop
//       childnum = childCount(node) − 1; node = index(node) + childnum   // last child first
//     else:
//       if leaf(node): radiance += Σ point contributions (points index … index+count−1, in order)
//       else:          radiance += node contribution
//       next: while childnum == 0: if stack empty: done; else (node, childnum) = pop()
//             node −= 1; childnum −= 1
//   subdivide(node) = !leaf(node) && !accept(node)
//   accept(node): solid-angle criterion, eq. 2.40, with the float arithmetic below:
//     default:       d = xo − meanPosition;   d2 = d.x*d.x + d.y*d.y + d.z*d.z
//     bounding box:  d = max(boxMin − xo, 0) + max(xo − boxMax, 0) (per axis); d2 as above
//                    (conservative: never farther than the nearest point; thesis end of 2.6.4)
//     accept = irradianceArea.w < eps * d2     (Δω = A_v / d2 < ε; d2 = 0 never accepts)
//   Every visit of a node (each loop iteration) is one step; a pixel stops and is flagged
//   kFlagIterationCap after maxSteps steps (checked before a step: exactly maxSteps steps run).
//   A push onto a full stack sets kFlagStackOverflow and stops (that step is still recorded,
//   with the unchanged stack); whatever was added before stays in the sum.
// Contributions (units: positions in mesh units, `scale` mm per unit, Bssrdf() in 1/mm²):
//   point i:  E_i·A_i·scale² · Bssrdf(scale·p_i, n_i, scale·xo, no)
//   node v:   irradianceArea.rgb·scale² · Bssrdf(scale·meanPosition, no, scale·xo, no)
//   (a cluster has no single normal, so the receiver's normal stands in for Wi)
// Second-order cluster rule (Criterion::secondOrder). Treating a cluster as one point at P
// takes f(E[p]) for E[f(p)]; the diffusion kernels are convex in r (≈ r⁻³ at mid range), so
// that underestimates by ½·tr(H Σ) + O(size⁴/r⁴), the same sign everywhere. With the
// covariance Σ the node is instead evaluated at three points whose distances to xo match the
// second-order Taylor expansion of E[f(|xo − p|)]: with d = xo − P, r = |d|, the variance
// along d, q = dᵀΣd / r², and across it, t² = tr Σ − q, a point at offset x along d̂ and
// offset t across lies at distance √((r + x)² + |t|²); three offsets x ∈ {0, −s, +s},
// s = √(2q), with weights ½, ¼, ¼ (mean 0, variance q, third moment 0: exact to second order
// in the cluster size for any smooth radial f; the fourth moment 2q² is that of a uniform disk
// seen edge-on) and |t|² at its mean t²:
//   E[f] ≈ ½·f(ρ0) + ¼·f(ρ−) + ¼·f(ρ+),  ρ0 = √(r² + t²),  ρ∓ = √((r ∓ s)² + t²)
// Positive weights: never negative, no derivative, no clamp; it reduces to f(r) when Σ = 0.
// The node's evaluations are at xi_k = xo − (ρ_k / r)·d (on the ray from xo through P, at
// distance ρ_k; for radial models only the distance matters), wi = no, weights
// irradianceArea.rgb·(½, ¼, ¼), in the order ρ0, ρ−, ρ+ (clusterPoints()). Float arithmetic
// (CPU clusterPoints and GLSL octreeCluster/octreeClusterPoint in common/octree_layout.glsl):
//   d = xo − meanPosition;  r2 = (d.x*d.x + d.y*d.y) + d.z*d.z
//   a = d.x*d.x*Σxx + d.y*d.y*Σyy + d.z*d.z*Σzz                   (left to right)
//   b = d.x*d.y*Σxy + d.x*d.z*Σxz + d.y*d.z*Σyz                   (left to right, each
//                                                                   product ((d.x*d.y)*Σxy))
//   q = max((a + 2*b) / r2, 0);  T = (Σxx + Σyy) + Σzz;  t2 = max(T − q, 0)
//   r = sqrt(r2);  s = sqrt(2*q);  m = r − s;  p = r + s
//   ρ0 = sqrt(r2 + t2),  ρ− = sqrt(m*m + t2),  ρ+ = sqrt(p*p + t2)
//   xi_k = xo − d * (ρ_k / r)                                      (vec3 * float)
//   r2 = 0 (never for an accepted node: d2 = 0 never accepts, and a box that the bounding-box
//   criterion accepts does not contain xo, but it contains P): xi_k = meanPosition.
// The contributions then follow the common formula below (weight·scale²·value, each added to
// the sum on its own, so the three terms of a node are three additions). The renderer's
// profile-table path looks the table up at scale·ρ_k directly (same values up to rounding).
// Accuracy (bench hierarchy, bunny 100k points, dipole Marble, H100): relative RMSE against
// brute force at equal ε falls 7–70× with the bounding-box criterion (ε 3.2: 4.5 % → 0.40 %)
// and 2–35× with the solid-angle one (ε 0.4: 2.7 % → 0.72 %); where accepted clusters are
// wider than the kernel's decay length (solid angle ε >= 0.8) no low-order rule converges.
// Float expressions (CPU and GLSL alike; bw_octree is compiled with -ffp-contract=off):
//   point weight   w = irradiance.rgb * positionArea.w            (vec3 * float)
//   node weight    w = irradianceArea.rgb; second-order: irradianceArea.rgb * k_j, k = ½, ¼, ¼
//                  (exact: powers of two)
//   contribution   vec3 c = w * (scale * scale) * value;          ((w * s²) * value, per channel)
//   radiance      += c   for each evaluation, in trace order (a leaf's points in slot order)
// M(xo) = Σ contributions is the radiant exitance; the renderer turns it into radiance.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace octree {

inline constexpr int kMaxLeafPoints = 8;         // leaf threshold of the build (thesis: 8)
inline constexpr int kMaxCoincidentPoints = 15;  // what the 4-bit point count can hold
inline constexpr int kStackSize = 16;            // traversal stack entries (GLSL too)
inline constexpr uint32_t kMaxIndex = 0xffffffu; // 24-bit index field
inline constexpr uint32_t kDefaultMaxSteps = 1u << 20;

inline constexpr uint32_t packDescriptor(uint32_t childCount, uint32_t pointCount, uint32_t index) {
    return (childCount & 0xfu) | ((pointCount & 0xfu) << 4) | (index << 8);
}
inline constexpr uint32_t childCount(uint32_t d) {
    return d & 0xfu;
}
inline constexpr uint32_t pointCount(uint32_t d) {
    return (d >> 4) & 0xfu;
}
inline constexpr uint32_t descriptorIndex(uint32_t d) {
    return d >> 8;
}
inline constexpr bool isLeaf(uint32_t d) {
    return childCount(d) == 0;
}

inline constexpr uint32_t packStackEntry(uint32_t node, uint32_t childnum) {
    return (node << 8) | (childnum & 0xffu);
}
inline constexpr uint32_t stackNode(uint32_t e) {
    return e >> 8;
}
inline constexpr uint32_t stackChildnum(uint32_t e) {
    return e & 0xffu;
}

// GPU layouts (std430; uploaded as-is by the renderer).
struct NodeRecord {
    float irradianceArea[4];        // Σ E·A (RGB), Σ A
    float meanPosition[4];          // xyz, w = 0
    float boxMin[4];                // xyz, w = 0
    float boxMax[4];                // xyz, w = 0
    float covarianceDiagonal[4];    // Σxx, Σyy, Σzz, 0 (mesh units², about meanPosition)
    float covarianceOffDiagonal[4]; // Σxy, Σxz, Σyz, 0
};
struct PointRecord {
    float positionArea[4]; // xyz (mesh units), area (units²)
    float normal[4];       // xyz unit, w = 0
    float irradiance[4];   // E (RGB), w = 0
};
static_assert(sizeof(NodeRecord) == 96 && sizeof(PointRecord) == 48);

struct BuildStats {
    size_t nodes = 0, leaves = 0, points = 0;
    int maxDepth = 0;                  // root = depth 0
    std::vector<size_t> nodesPerDepth; // [depth]
    std::vector<size_t> leafOccupancy; // [k] = leaves holding k points, k = 0..15
    size_t bytes = 0;                  // descriptors + node records + point records
    double buildMs = 0;
};

struct Octree {
    std::vector<uint32_t> descriptors; // per node
    std::vector<uint32_t> depth;       // per node (root 0), for the panel and the stats
    std::vector<uint32_t> parent;      // per node (root: itself)
    std::vector<uint32_t> order;       // order[k] = input index of the point stored at slot k
    std::vector<PointRecord> points;   // per slot, in octree order
    std::vector<NodeRecord> nodes;     // per node; after build: Σ E·A = 0, Σ A, area-weighted
                                       // mean, box (what setIrradiance gives for E = 0)
    BuildStats stats;
};

// Builds the octree of the positions/normals/areas (same length, mesh units). Irradiance is zero
// until setIrradiance. Throws core::Error("octree", 0, message) for: no points, a non-finite
// position, more than kMaxIndex+1 nodes or points, more than kMaxCoincidentPoints coincident
// points, a depth beyond kStackSize + 1 (also: lengths that differ, an area that is negative or
// not finite). Should the rounded centroid fail to separate distinct points (only conceivable
// for points a few ulps apart), that node is split at its box midpoint instead.
Octree build(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
             const std::vector<float>& areas);

// The limits build() enforces; lowered only by tests to see the refusals without 2^24 points.
struct BuildOptions {
    int stackSize = kStackSize;    // depth must stay <= stackSize + 1
    uint32_t maxIndex = kMaxIndex; // nodes and points must stay <= maxIndex + 1
};
Octree build(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
             const std::vector<float>& areas, const BuildOptions& options);

// Sets each point's irradiance (irradiance[i] for INPUT point i) and recomputes every node's
// attributes bottom-up (see above). Throws core::Error when the size differs.
void setIrradiance(Octree& t, const std::vector<glm::vec3>& irradiance);

// "fnv1a64:…" over descriptors, point records and node records (deterministic for a given input).
std::string hash(const Octree& t);

// ---- CPU replica of the traversal -------------------------------------------------------------
// The default ε of each criterion: 0.05 for the solid angle A/d², 4.0 for the bounding-box
// distance (whose values are of another scale; README "Defaults").
constexpr float defaultEps(bool boundingBox) {
    return boundingBox ? 4.0f : 0.05f;
}
struct Criterion {
    float eps = defaultEps(false);
    bool boundingBox = false;
    bool secondOrder = true; // nodes by the three-point second-order rule (see above)
    uint32_t maxSteps = kDefaultMaxSteps;
    int stackSize =
        kStackSize; // entries; a push beyond it flags kFlagStackOverflow (tests lower it)
};

enum class Decision : uint8_t { Recurse, EvaluateNode, EvaluatePoints };
const char* decisionName(Decision d); // "recurse", "node", "points"

inline constexpr uint32_t kFlagStackOverflow = 1u;
inline constexpr uint32_t kFlagIterationCap = 2u;

// One BSSRDF evaluation the traversal asks for, in the order it adds them.
struct Evaluation {
    glm::vec3 xi;     // mesh units (point position, node mean position or cluster point)
    glm::vec3 wi;     // point normal, or `no` for a node
    glm::vec3 weight; // E·A (point), Σ E·A (node) or Σ E·A·k_j (second-order node), units²
};

// The second-order rule's three evaluation points of node record `r` for receiver xo (mesh
// units), in order ρ0, ρ−, ρ+, with the float arithmetic above; kClusterWeights are the k_j.
inline constexpr float kClusterWeights[3] = {0.5f, 0.25f, 0.25f};
void clusterPoints(const NodeRecord& r, const glm::vec3& xo, glm::vec3 out[3]);

struct Step {
    uint32_t node = 0;
    Decision decision = Decision::Recurse;
    uint32_t depth = 0;
    float solidAngle = 0;         // A_v / d2 (inf when d2 = 0)
    std::vector<uint32_t> stack;  // packed entries after the step, bottom first
    uint32_t firstEvaluation = 0; // into Trace::evaluations
    uint32_t evaluationCount = 0; // 0 for Recurse
    glm::vec3 contribution{0.0f}; // filled by accumulate()
    glm::vec3 runningSum{0.0f};   // filled by accumulate()
};

struct Trace {
    glm::vec3 xo{0.0f}, no{0.0f, 0.0f, 1.0f};
    std::vector<Step> steps;
    std::vector<Evaluation> evaluations;
    uint32_t flags = 0;
    uint32_t maxStackDepth = 0;
    // Smallest |A_v − eps·d2| / max(A_v, eps·d2) over all criterion tests: a decision closer
    // than ~1e-6 to the threshold may legitimately differ between CPU and GPU float rounding.
    float closestMargin = 1e30f;
    glm::vec3 radiantExitance{0.0f}; // filled by accumulate()
};

// Runs the traversal for one receiver (xo in mesh units, no unit). Records every step.
Trace traverse(const Octree& t, const glm::vec3& xo, const glm::vec3& no, const Criterion& c);

// Given bssrdfValues[k] = Bssrdf(scale·xi_k, wi_k, scale·xo, no) (RGB, 1/mm²) for every
// evaluation, fills each step's contribution and running sum (float, adding in trace order,
// each contribution = weight·scale²·value) and the trace's radiant exitance. The running sum
// adds every evaluation's contribution one at a time (as the GPU does); a step's contribution
// is the float sum of its own evaluations from 0. Throws core::Error when the sizes differ.
void accumulate(Trace& trace, const std::vector<glm::vec3>& bssrdfValues, float scale);

} // namespace octree
