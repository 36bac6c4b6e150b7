// Fast even point clouds (pointcloud.h: sampleStratified, sampleStratifiedRepulsion).
//  * Stratified initial set: triangles in Morton order of their centroids, counts by rounding
//    the cumulative area (so the density is right at every scale above a triangle), positions
//    from the triangular van der Corput sequence (Basu & Owen 2015). Starting from this instead
//    of white noise removes the large-scale density fluctuations that plain repulsion needs
//    hundreds of iterations to diffuse away (thesis 2.6.4 uses Turk 1992 from random points).
//  * Repulsion: Turk's point repulsion with the compact kernel (1 − d/R)³, R = 2·d_hex, and
//    heavy-ball momentum (Polyak 1964); forces in float over Verlet neighbour lists (Verlet 1967;
//    skin d_hex/2, rebuilt every iteration for the first two, then every eighth — a pair that
//    crosses the skin between rebuilds is missed until the next one), moves in the tangent plane
//    clamped to d_hex/2, then the exact closest point on the mesh among the triangles within
//    d_hex of the point's triangle (the moved point is within d_hex/2 of its old position, so
//    its closest surface point is within d_hex of the old triangle: the same result as the
//    closest point on the whole mesh, with relaxRepulsion's facing test). Candidates are
//    culled by a lower bound of their distance (plane and edge half-spaces). Double buffered.
#include "pointcloud/internal.h"
#include "pointcloud/pointcloud.h"

#include "core/core.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace pointcloud {

using namespace detail;

namespace {

// Spreads the low 10 bits of x to every third bit (Morton code helper).
uint32_t spread3(uint32_t x) {
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

// Triangular van der Corput point i (Basu & Owen 2015): base-4 digits of i, least significant
// first, pick one of the four congruent sub-triangles (0 = the inverted middle one, 1..3 the
// corners) of the reference triangle (0,0), (1,0), (0,1); the result is the centroid of the
// final sub-triangle, returned as the weights (x, y) of vertices 1 and 2.
std::array<double, 2> triangularVdc(uint32_t i) {
    double ax = 0, ay = 0, bx = 1, by = 0, cx = 0, cy = 1;
    for (int k = 0; k < 16; ++k, i >>= 2) {
        double abx = 0.5 * (ax + bx), aby = 0.5 * (ay + by);
        double acx = 0.5 * (ax + cx), acy = 0.5 * (ay + cy);
        double bcx = 0.5 * (bx + cx), bcy = 0.5 * (by + cy);
        switch (i & 3u) {
        case 0:
            ax = bcx, ay = bcy, bx = acx, by = acy, cx = abx, cy = aby;
            break;
        case 1:
            bx = abx, by = aby, cx = acx, cy = acy;
            break;
        case 2:
            ax = abx, ay = aby, cx = bcx, cy = bcy;
            break;
        default:
            ax = acx, ay = acy, bx = bcx, by = bcy;
            break;
        }
    }
    return {(ax + bx + cx) / 3, (ay + by + cy) / 3};
}

struct Tri {
    V3 a, b, c;
    V3 unitNormal;
    std::array<V3, 3> edgeNormal;     // in-plane unit normals of the edges ab, bc, ca, outward
    std::array<double, 3> edgeOffset; // edgeNormal[k] · (a vertex of edge k)
    double planeOffset = 0;           // unitNormal · a
    bool valid = false;               // non-degenerate
};

// The triangles and their projection candidates. Triangle t's candidates are the triangles whose
// bounding boxes, each grown by reach/2, overlap t's (every triangle within distance `reach` of
// t). They are looked up per query point: a uniform grid lists in each cell the triangles whose
// grown box overlaps it, and a query q near triangle t reads q's cell, keeping the entries whose
// box overlaps t's. Lists kept per triangle instead made a long sliver (a stray far vertex: the
// rest of the mesh is a speck at one of its ends, inside its box) test every triangle of the
// mesh for every point on it, n · T per iteration.
class Surface {
  public:
    Surface(const mesh::Mesh& m, double reach) : m_mesh(m) {
        const size_t nt = m.triangles.size();
        m_tris.resize(nt);
        m_box.resize(nt);
        V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
        double sumDiag = 0;
        for (size_t t = 0; t < nt; ++t) {
            Tri& T = m_tris[t];
            T.a = toV3(m.vertices[m.triangles[t][0]]);
            T.b = toV3(m.vertices[m.triangles[t][1]]);
            T.c = toV3(m.vertices[m.triangles[t][2]]);
            V3 fn = cross(sub(T.b, T.a), sub(T.c, T.a));
            double fl = length(fn);
            T.valid = fl > 0 && std::isfinite(fl);
            T.unitNormal = T.valid ? mul(fn, 1 / fl) : V3{0, 0, 0};
            T.planeOffset = dot(T.unitNormal, T.a);
            const V3 v[3] = {T.a, T.b, T.c};
            for (int k = 0; k < 3; ++k) {
                V3 e = cross(sub(v[(k + 1) % 3], v[k]), T.unitNormal);
                double el = length(e);
                T.edgeNormal[k] = el > 0 ? mul(e, 1 / el) : V3{0, 0, 0};
                T.edgeOffset[k] = dot(T.edgeNormal[k], v[k]);
            }
            for (int k = 0; k < 3; ++k) {
                m_box[t][0][k] = std::min({T.a[k], T.b[k], T.c[k]}) - 0.5 * reach;
                m_box[t][1][k] = std::max({T.a[k], T.b[k], T.c[k]}) + 0.5 * reach;
                lo[k] = std::min(lo[k], m_box[t][0][k]);
                hi[k] = std::max(hi[k], m_box[t][1][k]);
            }
            sumDiag += length(sub(m_box[t][1], m_box[t][0]));
        }
        // Uniform grid of the grown boxes, cell ~ the mean grown-box diagonal.
        double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-30});
        m_cell = std::max(sumDiag / double(std::max<size_t>(nt, 1)), extent / 128);
        m_lo = lo;
        for (int k = 0; k < 3; ++k)
            m_dim[k] = int64_t((hi[k] - lo[k]) / m_cell) + 1;
        m_start.assign(size_t(m_dim[0] * m_dim[1] * m_dim[2]) + 1, 0);
        auto forCells = [&](size_t t, auto&& f) {
            const std::array<int64_t, 3> c0 = cellOf(m_box[t][0]), c1 = cellOf(m_box[t][1]);
            for (int64_t z = c0[2]; z <= c1[2]; ++z)
                for (int64_t y = c0[1]; y <= c1[1]; ++y)
                    for (int64_t x = c0[0]; x <= c1[0]; ++x)
                        f(size_t((z * m_dim[1] + y) * m_dim[0] + x));
        };
        for (size_t t = 0; t < nt; ++t)
            if (m_tris[t].valid) forCells(t, [&](size_t c) { ++m_start[c + 1]; });
        for (size_t c = 0; c + 1 < m_start.size(); ++c)
            m_start[c + 1] += m_start[c];
        m_items.resize(m_start.back());
        std::vector<uint32_t> fill(m_start.begin(), m_start.end() - 1);
        for (size_t t = 0; t < nt; ++t) // each cell's list in ascending triangle order
            if (m_tris[t].valid) forCells(t, [&](size_t c) { m_items[fill[c]++] = uint32_t(t); });
    }

    // Closest point to q on the candidates of triangle `from` (itself first, then ascending)
    // that do not face away from `normal` (face normal · normal >= −0.5); false when there is
    // none. q is within reach/2 of `from`, so every candidate closer to q than `from` has a
    // grown box holding q and is listed in q's cell. A candidate is skipped when a lower bound
    // of its distance — the largest distance of q outside its plane or its three edge planes
    // (the triangle lies inside all four half-spaces) — is no better than the best so far.
    bool closest(const V3& q, const V3& normal, uint32_t from, V3& outP, V3& outBary,
                 uint32_t& outTri) const {
        double best = std::numeric_limits<double>::infinity();
        auto consider = [&](uint32_t t) {
            const Tri& T = m_tris[t];
            const double h = dot(T.unitNormal, q) - T.planeOffset;
            const double s0 = dot(T.edgeNormal[0], q) - T.edgeOffset[0];
            const double s1 = dot(T.edgeNormal[1], q) - T.edgeOffset[1];
            const double s2 = dot(T.edgeNormal[2], q) - T.edgeOffset[2];
            const double lb = std::max({std::abs(h), s0, s1, s2});
            if (lb * lb >= best && !(lb * lb == best && t < outTri)) return;
            if (dot(T.unitNormal, normal) < -0.5) return;
            V3 bc = closestBarycentric(q, T.a, T.b, T.c);
            V3 p = add(add(mul(T.a, bc[0]), mul(T.b, bc[1])), mul(T.c, bc[2]));
            V3 d = sub(p, q);
            double d2 = dot(d, d);
            if (d2 < best || (d2 == best && t < outTri))
                best = d2, outP = p, outBary = bc, outTri = t;
        };
        if (!m_tris[from].valid) return false; // (no point lies on a degenerate triangle)
        consider(from);
        const std::array<int64_t, 3> c = cellOf(q);
        const size_t cell = size_t((c[2] * m_dim[1] + c[1]) * m_dim[0] + c[0]);
        const std::array<V3, 2>& bf = m_box[from];
        for (uint32_t k = m_start[cell]; k < m_start[cell + 1]; ++k) {
            const uint32_t t = m_items[k];
            const std::array<V3, 2>& bt = m_box[t];
            if (t == from || bt[0][0] > bf[1][0] || bf[0][0] > bt[1][0] || bt[0][1] > bf[1][1] ||
                bf[0][1] > bt[1][1] || bt[0][2] > bf[1][2] || bf[0][2] > bt[1][2])
                continue;
            consider(t);
        }
        return best < std::numeric_limits<double>::infinity();
    }

    V3 normalAt(uint32_t t, const V3& bc) const {
        const auto& tri = m_mesh.triangles[t];
        if (m_mesh.normals.size() == m_mesh.vertices.size()) {
            V3 nn = add(add(mul(toV3(m_mesh.normals[tri[0]]), bc[0]),
                            mul(toV3(m_mesh.normals[tri[1]]), bc[1])),
                        mul(toV3(m_mesh.normals[tri[2]]), bc[2]));
            double l = length(nn);
            if (l > 0) return mul(nn, 1 / l);
        }
        return m_tris[t].unitNormal;
    }
    const Tri& tri(size_t t) const { return m_tris[t]; }

  private:
    // The grid cell of p, clamped to the grid (NaN: cell 0).
    std::array<int64_t, 3> cellOf(const V3& p) const {
        std::array<int64_t, 3> c{};
        for (int k = 0; k < 3; ++k) {
            const double x = (p[k] - m_lo[k]) / m_cell;
            c[k] = x >= 0 ? std::min<int64_t>(int64_t(std::min(x, 1e18)), m_dim[k] - 1) : 0;
        }
        return c;
    }

    const mesh::Mesh& m_mesh;
    std::vector<Tri> m_tris;
    std::vector<std::array<V3, 2>> m_box; // bounding boxes grown by reach/2
    V3 m_lo{};
    double m_cell = 1;
    std::array<int64_t, 3> m_dim{};
    std::vector<uint32_t> m_start, m_items; // triangles per grid cell (CSR)
};

using F4 = std::array<float, 4>; // x, y, z, unused

// Neighbour lists (CSR) of all j with |p_j − p_i| < radius. Points are hashed by their cell
// (size `radius`) into a power-of-two table with a linear hash (x + y·P1 + z·P2, so cells adjacent
// in x share cache lines), counting-sorted by bucket into contiguous copies of cell and position;
// entries are filtered by their exact cell, so collisions never duplicate a neighbour. Lists are
// gathered per fixed block of points and in a fixed order (cells dz, dy, dx, then bucket order),
// so they do not depend on the thread count.
struct NeighbourLists {
    std::vector<uint32_t> start, items;
    void build(const std::vector<F4>& pos, float radius, int threads) {
        const size_t n = pos.size();
        size_t buckets = 64;
        while (buckets < 2 * n)
            buckets *= 2;
        const uint64_t mask = buckets - 1;
        const float inv = 1 / radius;
        // Cells beyond ±2^15 (points spread over 10^4 neighbour radii or more: a stray far
        // vertex) add their high bits, multiplied, to the low ones: a cell index that came from
        // a large float is a multiple of a power of two, which the mask alone maps to one bucket.
        // Within ±2^15, as every cloud of up to ~10^9 points on a normalised mesh, the hash is
        // the linear one.
        auto high = [](int64_t v) { return v >= 32768 || v < -32768 ? uint64_t(v >> 15) : 0; };
        auto bucketOf = [&](int64_t x, int64_t y, int64_t z) {
            constexpr uint64_t P1 = 0x9E3779B97F4A7C15ull, P2 = 0xC2B2AE3D27D4EB4Full,
                               P3 = 0xD6E8FEB86659FD93ull;
            return size_t((uint64_t(x) + uint64_t(y) * P1 + uint64_t(z) * P2 +
                           (high(x) + high(y) * P1 + high(z) * P2) * P3) &
                          mask);
        };
        struct Entry {
            float p[3];
            uint32_t index;
            int64_t c[3];
        };
        std::vector<Entry> own(n);
        std::vector<uint32_t> bucket(n), bstart(buckets + 1, 0);
        // 64-bit cells, clamped to ±2^62 so that a cell ± 1 (the loops below) never overflows:
        // the clamp is monotone, so two points within `radius` still have cells at most 1 apart
        // and the exact cell filter still holds. A mesh with a stray vertex far out (at 1e20) is
        // normalised to a speck beside one long sliver, whose points are ~1e12 cells apart:
        // 32-bit cells clamped at 2^30 put them all into one cell, n² pairs per rebuild.
        constexpr double kCellLimit = 4611686018427387904.0; // 2^62
        for (size_t i = 0; i < n; ++i) {
            Entry& e = own[i];
            for (int a = 0; a < 3; ++a) {
                e.p[a] = pos[i][a];
                e.c[a] = int64_t(
                    std::clamp(double(std::floor(pos[i][a] * inv)), -kCellLimit, kCellLimit));
            }
            e.index = uint32_t(i);
            bucket[i] = uint32_t(bucketOf(e.c[0], e.c[1], e.c[2]));
            ++bstart[bucket[i] + 1];
        }
        for (size_t b = 0; b < buckets; ++b)
            bstart[b + 1] += bstart[b];
        std::vector<Entry> sorted(n);
        {
            std::vector<uint32_t> fill(bstart.begin(), bstart.end() - 1);
            for (size_t i = 0; i < n; ++i)
                sorted[fill[bucket[i]]++] = own[i];
        }
        const float r2 = radius * radius;
        constexpr size_t kBlock = 512;
        const size_t blocks = (n + kBlock - 1) / kBlock;
        std::vector<std::vector<uint32_t>> blockItems(blocks);
        start.assign(n + 1, 0);
        parallelFor(blocks, threads, [&](size_t b0, size_t b1) {
            for (size_t blk = b0; blk < b1; ++blk) {
                auto& out = blockItems[blk];
                for (size_t i = blk * kBlock; i < std::min(n, (blk + 1) * kBlock); ++i) {
                    const Entry& q = own[i];
                    const size_t before = out.size();
                    for (int dz = -1; dz <= 1; ++dz)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                const int64_t x = q.c[0] + dx, y = q.c[1] + dy, z = q.c[2] + dz;
                                const size_t b = bucketOf(x, y, z);
                                for (uint32_t e = bstart[b]; e < bstart[b + 1]; ++e) {
                                    const Entry& en = sorted[e];
                                    const float ex = en.p[0] - q.p[0], ey = en.p[1] - q.p[1],
                                                ez = en.p[2] - q.p[2];
                                    if (ex * ex + ey * ey + ez * ez < r2 && en.c[0] == x &&
                                        en.c[1] == y && en.c[2] == z && en.index != i)
                                        out.push_back(en.index);
                                }
                            }
                    start[i + 1] = uint32_t(out.size() - before);
                }
            }
        });
        for (size_t i = 0; i < n; ++i)
            start[i + 1] += start[i];
        items.resize(start[n]);
        parallelFor(blocks, threads, [&](size_t b0, size_t b1) {
            for (size_t blk = b0; blk < b1; ++blk)
                std::copy(blockItems[blk].begin(), blockItems[blk].end(),
                          items.begin() + start[blk * kBlock]);
        });
    }
};

// The points in Morton order of their positions (2^20 cells per axis over their bounding box;
// ties: index), so that neighbours are close in memory.
std::vector<Point> mortonOrder(std::vector<Point> pts) {
    const size_t n = pts.size();
    V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& p : pts)
        for (int k = 0; k < 3; ++k)
            lo[k] = std::min(lo[k], double(p.p[k])), hi[k] = std::max(hi[k], double(p.p[k]));
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-30});
    std::vector<std::pair<uint64_t, uint32_t>> key(n);
    for (size_t i = 0; i < n; ++i) {
        uint64_t code = 0;
        for (int k = 0; k < 3; ++k) {
            uint32_t q = uint32_t(
                std::clamp((double(pts[i].p[k]) - lo[k]) / extent * 1048576.0, 0.0, 1048575.0));
            code |= (uint64_t(spread3(q >> 10)) << (30 + k)) | (uint64_t(spread3(q)) << k);
        }
        key[i] = {code, uint32_t(i)};
    }
    std::sort(key.begin(), key.end());
    std::vector<Point> out(n);
    for (size_t i = 0; i < n; ++i)
        out[i] = pts[key[i].second];
    return out;
}

// Fixed parameters (in units of the hexagonal spacing d_hex): the neighbour-list skin, the
// largest move per iteration, and the list rebuild schedule (every iteration for the first
// kRebuildFirst iterations, where the stratified seams move most, then every kRebuildEvery).
constexpr double kSkin = 0.5;
constexpr double kMaxStep = 0.5;
constexpr int kRebuildFirst = 2;
constexpr int kRebuildEvery = 8;

} // namespace

PointCloud sampleStratified(const mesh::Mesh& m, size_t n, uint64_t seed, int threads) {
    if (n == 0) throw core::Error("sampleStratified: the point count must be > 0");
    if (n >= kNoTriangle) throw core::Error("sampleStratified: too many points");
    const size_t nt = m.triangles.size();
    // Triangles in Morton order of their centroids (ties: index).
    V3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& v : m.vertices)
        for (int k = 0; k < 3; ++k)
            lo[k] = std::min(lo[k], double(v[k])), hi[k] = std::max(hi[k], double(v[k]));
    double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-30});
    std::vector<std::pair<uint32_t, uint32_t>> order(nt);
    std::vector<double> area(nt);
    for (size_t t = 0; t < nt; ++t) {
        const auto& tri = m.triangles[t];
        V3 a = toV3(m.vertices[tri[0]]), b = toV3(m.vertices[tri[1]]), c = toV3(m.vertices[tri[2]]);
        area[t] = 0.5 * length(cross(sub(b, a), sub(c, a)));
        V3 g = mul(add(add(a, b), c), 1.0 / 3);
        uint32_t code = 0;
        for (int k = 0; k < 3; ++k)
            code |= spread3(uint32_t(std::clamp((g[k] - lo[k]) / extent * 1024, 0.0, 1023.0))) << k;
        order[t] = {code, uint32_t(t)};
    }
    std::sort(order.begin(), order.end());
    double total = 0;
    for (size_t t = 0; t < nt; ++t)
        total += area[order[t].second];
    if (!(total > 0) || !std::isfinite(total))
        throw core::Error("sampleStratified: the mesh has no surface area");
    // Counts by rounding the cumulative area along the curve: Σ k_t = n exactly.
    std::vector<uint32_t> first(nt + 1, 0);
    double cum = 0;
    for (size_t t = 0; t < nt; ++t) {
        cum += area[order[t].second];
        double f = t + 1 == nt ? double(n) : std::floor(double(n) * cum / total + 0.5);
        first[t + 1] = uint32_t(std::clamp(f, double(first[t]), double(n)));
    }
    const bool vertexNormals = m.normals.size() == m.vertices.size();
    PointCloud cloud;
    cloud.totalArea = total;
    cloud.points.resize(n);
    const float pa = float(total / double(n));
    parallelFor(nt, threads, [&](size_t begin, size_t end) {
        for (size_t s = begin; s < end; ++s) {
            const uint32_t t = order[s].second;
            const auto& tri = m.triangles[t];
            V3 v0 = toV3(m.vertices[tri[0]]), v1 = toV3(m.vertices[tri[1]]);
            V3 v2 = toV3(m.vertices[tri[2]]);
            V3 fn = cross(sub(v1, v0), sub(v2, v0));
            const uint32_t offset = uint32_t(CounterRng(seed, t).next() >> 32);
            for (uint32_t i = first[s]; i < first[s + 1]; ++i) {
                auto [x, y] = triangularVdc(offset + (i - first[s]));
                double b0 = 1 - x - y;
                V3 p = add(add(mul(v0, b0), mul(v1, x)), mul(v2, y));
                V3 nrm = vertexNormals ? add(add(mul(toV3(m.normals[tri[0]]), b0),
                                                 mul(toV3(m.normals[tri[1]]), x)),
                                             mul(toV3(m.normals[tri[2]]), y))
                                       : fn;
                double len = length(nrm);
                if (!(len > 0)) nrm = fn, len = length(nrm);
                Point& out = cloud.points[i];
                for (int k = 0; k < 3; ++k) {
                    out.p[k] = float(p[k]);
                    out.n[k] = float(nrm[k] / len);
                }
                out.area = pa;
                out.triangle = t;
            }
        }
    });
    return cloud;
}

PointCloud sampleStratifiedRepulsion(const mesh::Mesh& m, size_t n, uint64_t seed,
                                     const StratifiedRepulsionOptions& o) {
    PointCloud cloud = sampleStratified(m, n, seed, o.threads);
    if (n < 2 || o.iterations <= 0) return cloud;
    if (!(o.radiusScale > 0) || !(o.stepScale >= 0) || !(o.momentum >= 0 && o.momentum < 1))
        throw core::Error("sampleStratifiedRepulsion: bad options");
    const double A = cloud.totalArea;
    const double dHex = std::sqrt(2 * A / (std::sqrt(3.0) * double(n)));
    const double R = o.radiusScale * dHex;
    const double skin = kSkin * dHex;
    const double maxStep = kMaxStep * dHex;
    // Every closest point a move can reach lies within 2·maxStep of the point's triangle.
    Surface surface(m, 2 * maxStep);
    cloud.points = mortonOrder(std::move(cloud.points));
    std::vector<V3> pos(n), nrm(n), vel(n, V3{0, 0, 0}), nextPos(n), nextNrm(n), nextVel(n);
    std::vector<uint32_t> tri(n), nextTri(n);
    std::vector<F4> posf(n);
    for (size_t i = 0; i < n; ++i)
        pos[i] = toV3(cloud.points[i].p), nrm[i] = toV3(cloud.points[i].n),
        tri[i] = cloud.points[i].triangle;
    auto toFloat = [&] {
        for (size_t i = 0; i < n; ++i)
            posf[i] = {float(pos[i][0]), float(pos[i][1]), float(pos[i][2]), 0.f};
    };
    toFloat();
    NeighbourLists lists;
    const float Rf = float(R), invR = float(1 / R);
    const double step = o.stepScale * dHex;
    for (int it = 0; it < o.iterations; ++it) {
        if (it > 0 && o.progress) o.progress(it, o.iterations);
        if (it < kRebuildFirst || it % kRebuildEvery == 0)
            lists.build(posf, float(R + skin), o.threads);
        parallelFor(n, o.threads, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                // Σ_j (1 − d_ij/R)³ (p_i − p_j)/d_ij over the list of i.
                float fx = 0, fy = 0, fz = 0;
                const F4 pi = posf[i];
                for (uint32_t e = lists.start[i]; e < lists.start[i + 1]; ++e) {
                    const F4& pj = posf[lists.items[e]];
                    const float dx = pi[0] - pj[0], dy = pi[1] - pj[1], dz = pi[2] - pj[2];
                    const float d2 = dx * dx + dy * dy + dz * dz;
                    if (!(d2 < Rf * Rf) || !(d2 > 0)) continue;
                    const float l = std::sqrt(d2);
                    float w = 1 - l * invR;
                    w = w * w * w / l;
                    fx += dx * w, fy += dy * w, fz += dz * w;
                }
                const V3 p = pos[i], ni = nrm[i];
                V3 mv = add(mul(V3{fx, fy, fz}, step), mul(vel[i], o.momentum));
                mv = sub(mv, mul(ni, dot(ni, mv))); // tangent plane
                const double len = length(mv);
                if (len > maxStep) mv = mul(mv, maxStep / len);
                nextPos[i] = p, nextNrm[i] = ni, nextTri[i] = tri[i], nextVel[i] = {0, 0, 0};
                V3 q{}, bc{};
                uint32_t t = kNoTriangle;
                if (len > 0 && surface.closest(add(p, mv), ni, tri[i], q, bc, t)) {
                    nextPos[i] = q, nextTri[i] = t, nextNrm[i] = surface.normalAt(t, bc);
                    nextVel[i] = sub(q, p);
                }
            }
        });
        std::swap(pos, nextPos), std::swap(nrm, nextNrm), std::swap(tri, nextTri);
        std::swap(vel, nextVel);
        toFloat();
    }
    for (size_t i = 0; i < n; ++i) {
        Point& out = cloud.points[i];
        for (int k = 0; k < 3; ++k)
            out.p[k] = float(pos[i][k]), out.n[k] = float(nrm[i][k]);
        out.triangle = tri[i];
    }
    return cloud;
}

} // namespace pointcloud
