// Point-cloud relaxation and metrics:
//  * Turk's point repulsion (Turk 1992; thesis 2.6.4, 3.3.1). Each iteration, point i moves by
//      m_i = stepScale · r · Σ_{j: d_ij < r} (1 − d_ij/r) · (p_i − p_j)/d_ij
//    projected into its tangent plane (m_i −= n_i (n_i·m_i)) and clamped to the triangle-grid
//    cell size h, then re-projected onto the surface: the closest point on the triangles of the
//    3×3×3 cells of a uniform grid of triangles around the moved position (every triangle is
//    stored in the cells its bounding box overlaps; since the moved point is at most h from the
//    surface, its closest surface point lies in those cells). Triangles facing away from the
//    point's normal (face normal · n_i < −0.5, e.g. the far side of a thin plate) are skipped,
//    so points never jump through thin geometry; when none is found the point stays. This
//    replaces the thesis' walk to the neighbouring polygon / clamp to the edge with an
//    equivalent closest-point query that also handles non-manifold neighbourhoods. Positions
//    are double buffered (read iteration k, write k+1), so the parallel loop is deterministic.
//  * Weighted sample elimination (Yuksel 2015) with an indexed max-heap.
//  * Nearest-neighbour uniformity metrics: each point's nearest neighbour from a k-d tree
//    (nanoflann), O(n log n) whatever the spread of the points. (A ring search on the hash grid
//    was O(R^4) in the ring count R: a mesh with one far vertex, whose points sit on a long
//    needle triangle, ran for minutes.)
#include "pointcloud/internal.h"
#include "pointcloud/pointcloud.h"

#include "core/core.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <nanoflann.hpp>

namespace pointcloud {

namespace detail {

// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5);
// returns the barycentrics (u, v, w) of the closest point, u·a + v·b + w·c.
V3 closestBarycentric(const V3& p, const V3& a, const V3& b, const V3& c) {
    V3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
    V3 bp = sub(p, b);
    double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        return {1 - v, v, 0};
    }
    V3 cp = sub(p, c);
    double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        return {1 - w, 0, w};
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0, 1 - w, w};
    }
    double denom = 1 / (va + vb + vc);
    double v = vb * denom, w = vc * denom;
    return {1 - v - w, v, w};
}

} // namespace detail

using namespace detail;

namespace {

// Uniform grid of triangles (dense, over the mesh bounding box, padded by one cell).
class TriangleGrid {
  public:
    TriangleGrid(const mesh::Mesh& m, double cell) : m_mesh(m) {
        V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
        for (const auto& v : m.vertices)
            for (int k = 0; k < 3; ++k)
                lo[k] = std::min(lo[k], double(v[k])), hi[k] = std::max(hi[k], double(v[k]));
        double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
        m_cell = std::max(cell, extent / 96); // at most ~100 cells per axis
        for (int k = 0; k < 3; ++k) {
            m_lo[k] = lo[k] - m_cell;
            m_dim[k] = int64_t((hi[k] - m_lo[k]) / m_cell) + 2;
        }
        std::vector<std::vector<uint32_t>> cells(size_t(m_dim[0] * m_dim[1] * m_dim[2]));
        for (size_t t = 0; t < m.triangles.size(); ++t) {
            V3 a{1e300, 1e300, 1e300}, b{-1e300, -1e300, -1e300};
            for (uint32_t vi : m.triangles[t])
                for (int k = 0; k < 3; ++k)
                    a[k] = std::min(a[k], double(m.vertices[vi][k])),
                    b[k] = std::max(b[k], double(m.vertices[vi][k]));
            auto ca = cellOf(a), cb = cellOf(b);
            for (int64_t z = ca[2]; z <= cb[2]; ++z)
                for (int64_t y = ca[1]; y <= cb[1]; ++y)
                    for (int64_t x = ca[0]; x <= cb[0]; ++x)
                        cells[size_t((z * m_dim[1] + y) * m_dim[0] + x)].push_back(uint32_t(t));
        }
        m_start.assign(cells.size() + 1, 0);
        for (size_t c = 0; c < cells.size(); ++c)
            m_start[c + 1] = m_start[c] + cells[c].size();
        m_tris.reserve(m_start.back());
        for (auto& c : cells)
            m_tris.insert(m_tris.end(), c.begin(), c.end());
    }
    double cellSize() const { return m_cell; }

    // Closest surface point to p among triangles not facing away from `normal`.
    bool closest(const V3& p, const V3& normal, V3& outP, V3& outBary, uint32_t& outTri) const {
        auto c = cellOf(p);
        double best = std::numeric_limits<double>::infinity();
        uint32_t lastTri = kNoTriangle;
        for (int64_t z = std::max<int64_t>(c[2] - 1, 0); z <= std::min(c[2] + 1, m_dim[2] - 1); ++z)
            for (int64_t y = std::max<int64_t>(c[1] - 1, 0); y <= std::min(c[1] + 1, m_dim[1] - 1);
                 ++y)
                for (int64_t x = std::max<int64_t>(c[0] - 1, 0);
                     x <= std::min(c[0] + 1, m_dim[0] - 1); ++x) {
                    size_t cell = size_t((z * m_dim[1] + y) * m_dim[0] + x);
                    for (size_t k = m_start[cell]; k < m_start[cell + 1]; ++k) {
                        uint32_t t = m_tris[k];
                        if (t == lastTri) continue;
                        lastTri = t;
                        const auto& tri = m_mesh.triangles[t];
                        V3 a = toV3(m_mesh.vertices[tri[0]]), b = toV3(m_mesh.vertices[tri[1]]);
                        V3 cc = toV3(m_mesh.vertices[tri[2]]);
                        V3 fn = cross(sub(b, a), sub(cc, a));
                        double fl = length(fn);
                        if (!(fl > 0) || dot(fn, normal) < -0.5 * fl) continue;
                        V3 bc = closestBarycentric(p, a, b, cc);
                        V3 q = add(add(mul(a, bc[0]), mul(b, bc[1])), mul(cc, bc[2]));
                        V3 dq = sub(q, p);
                        double d2 = dot(dq, dq);
                        if (d2 < best || (d2 == best && t < outTri)) {
                            best = d2, outP = q, outBary = bc, outTri = t;
                        }
                    }
                }
        return best < std::numeric_limits<double>::infinity();
    }

  private:
    std::array<int64_t, 3> cellOf(const V3& p) const {
        std::array<int64_t, 3> c;
        for (int k = 0; k < 3; ++k)
            c[k] = std::clamp<int64_t>(int64_t(std::floor((p[k] - m_lo[k]) / m_cell)), 0,
                                       m_dim[k] - 1);
        return c;
    }
    const mesh::Mesh& m_mesh;
    double m_cell = 1;
    V3 m_lo{};
    std::array<int64_t, 3> m_dim{};
    std::vector<size_t> m_start;
    std::vector<uint32_t> m_tris;
};

std::vector<V3> positionsOf(const PointCloud& c) {
    std::vector<V3> p(c.points.size());
    for (size_t i = 0; i < p.size(); ++i)
        p[i] = toV3(c.points[i].p);
    return p;
}

} // namespace

PointCloud relaxRepulsion(const mesh::Mesh& m, const PointCloud& initial,
                          const RepulsionOptions& options) {
    const size_t n = initial.points.size();
    if (n < 2 || options.iterations <= 0) return initial;
    const double area = initial.totalArea > 0 ? initial.totalArea : meshArea(m);
    const double r = options.radiusScale * 2 * std::sqrt(area / (double(n) * std::numbers::pi));
    if (!(r > 0) || !std::isfinite(r)) throw core::Error("relaxRepulsion: bad radius");
    const bool vertexNormals = m.normals.size() == m.vertices.size();
    TriangleGrid triGrid(m, r);
    const double maxStep = triGrid.cellSize();
    PointCloud cur = initial, next = initial;
    std::vector<V3> pos = positionsOf(cur);
    for (int it = 0; it < options.iterations; ++it) {
        if (it > 0 && options.progress) options.progress(it, options.iterations);
        PointGrid grid(pos, r);
        parallelFor(n, options.threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                const Point& src = cur.points[i];
                V3 force{0, 0, 0};
                grid.forNeighbours(pos[i], i, r, [&](size_t j, double d) {
                    if (d <= 1e-12 * r) return;
                    force = add(force, mul(sub(pos[i], pos[j]), (1 - d / r) / d));
                });
                V3 nrm = toV3(src.n);
                V3 move = mul(force, options.stepScale * r);
                move = sub(move, mul(nrm, dot(nrm, move)));
                double len = length(move);
                Point& dst = next.points[i];
                dst = src;
                if (!(len > 0)) continue;
                if (len > maxStep) move = mul(move, maxStep / len);
                V3 q{}, bc{};
                uint32_t t = kNoTriangle;
                if (!triGrid.closest(add(pos[i], move), nrm, q, bc, t)) continue;
                const auto& tri = m.triangles[t];
                V3 nn;
                if (vertexNormals) {
                    nn = add(add(mul(toV3(m.normals[tri[0]]), bc[0]),
                                 mul(toV3(m.normals[tri[1]]), bc[1])),
                             mul(toV3(m.normals[tri[2]]), bc[2]));
                } else {
                    V3 a = toV3(m.vertices[tri[0]]);
                    nn = cross(sub(toV3(m.vertices[tri[1]]), a), sub(toV3(m.vertices[tri[2]]), a));
                }
                double nl = length(nn);
                for (int k = 0; k < 3; ++k) {
                    dst.p[k] = float(q[k]);
                    if (nl > 0) dst.n[k] = float(nn[k] / nl);
                }
                dst.triangle = t;
            }
        });
        std::swap(cur, next);
        pos = positionsOf(cur);
    }
    return cur;
}

PointCloud sampleElimination(const mesh::Mesh& m, size_t n, uint64_t seed,
                             const EliminationOptions& options) {
    if (n == 0) throw core::Error("sampleElimination: the point count must be > 0");
    const size_t candidates =
        std::max(n, size_t(std::ceil(std::max(1.0, options.candidateFactor) * double(n))));
    PointCloud cand = sampleUniform(m, candidates, seed, options.threads);
    const double A = cand.totalArea;
    const double rmax = std::sqrt(A / (2 * std::sqrt(3.0) * double(n)));
    const double r2 = 2 * rmax;
    std::vector<V3> pos = positionsOf(cand);
    PointGrid grid(pos, r2);
    // Neighbour lists and weights (parallel, each i independent: deterministic).
    std::vector<std::vector<std::pair<uint32_t, double>>> nbr(candidates);
    std::vector<double> w(candidates, 0);
    parallelFor(candidates, options.threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            grid.forNeighbours(pos[i], i, r2, [&](size_t j, double d) {
                double wij = std::pow(1 - d / r2, 8);
                nbr[i].push_back({uint32_t(j), wij});
            });
            std::sort(nbr[i].begin(), nbr[i].end());
            for (const auto& [j, wij] : nbr[i])
                w[i] += wij;
        }
    });
    // Indexed binary max-heap on (weight, then lower index first).
    std::vector<uint32_t> heap(candidates), where(candidates);
    for (size_t i = 0; i < candidates; ++i)
        heap[i] = uint32_t(i), where[i] = uint32_t(i);
    auto above = [&](uint32_t a, uint32_t b) { return w[a] > w[b] || (w[a] == w[b] && a < b); };
    auto place = [&](size_t k, uint32_t v) { heap[k] = v, where[v] = uint32_t(k); };
    size_t size = candidates;
    auto siftDown = [&](size_t k) {
        uint32_t v = heap[k];
        for (;;) {
            size_t c = 2 * k + 1;
            if (c >= size) break;
            if (c + 1 < size && above(heap[c + 1], heap[c])) ++c;
            if (!above(heap[c], v)) break;
            place(k, heap[c]);
            k = c;
        }
        place(k, v);
    };
    for (size_t k = size / 2; k-- > 0;)
        siftDown(k);
    std::vector<char> alive(candidates, 1);
    while (size > n) {
        uint32_t top = heap[0];
        alive[top] = 0;
        --size;
        if (size > 0) {
            place(0, heap[size]);
            siftDown(0);
        }
        for (const auto& [j, wij] : nbr[top]) {
            if (!alive[j]) continue;
            w[j] -= wij; // weight decreases: the entry can only move down
            siftDown(where[j]);
        }
    }
    PointCloud out;
    out.totalArea = A;
    out.points.reserve(n);
    const float area = float(A / double(n));
    for (size_t i = 0; i < candidates; ++i)
        if (alive[i]) {
            out.points.push_back(cand.points[i]);
            out.points.back().area = area;
        }
    return out;
}

namespace {
// The positions as nanoflann's dataset interface.
struct PositionsAdaptor {
    const std::vector<V3>& pos;
    size_t kdtree_get_point_count() const { return pos.size(); }
    double kdtree_get_pt(size_t i, size_t dim) const { return pos[i][dim]; }
    template <class Box> bool kdtree_get_bbox(Box&) const { return false; }
};
} // namespace

Uniformity measureUniformity(const PointCloud& cloud, int threads) {
    Uniformity u;
    const size_t n = cloud.points.size();
    if (n < 2) return u;
    std::vector<V3> pos = positionsOf(cloud);
    const PositionsAdaptor data{pos};
    using Tree =
        nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PositionsAdaptor>,
                                            PositionsAdaptor, 3, size_t>;
    Tree tree(3, data, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree.buildIndex();
    std::vector<double> nn(n);
    parallelFor(n, threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            // the two nearest: the point itself (distance 0) and its nearest neighbour, or
            // a coincident point (then both are at distance 0)
            size_t index[2];
            double d2[2];
            const size_t found = tree.knnSearch(pos[i].data(), 2, index, d2);
            nn[i] = found == 2 ? std::sqrt(d2[1]) : std::numeric_limits<double>::infinity();
        }
    });
    double sum = 0, sum2 = 0;
    u.minNN = std::numeric_limits<double>::infinity();
    for (double d : nn) {
        sum += d, sum2 += d * d;
        u.minNN = std::min(u.minNN, d), u.maxNN = std::max(u.maxNN, d);
    }
    u.meanNN = sum / double(n);
    double var = std::max(0.0, sum2 / double(n) - u.meanNN * u.meanNN);
    u.cvNN = u.meanNN > 0 ? std::sqrt(var) / u.meanNN : 0;
    return u;
}

} // namespace pointcloud
