// Area-weighted uniform surface sampling: cumulative triangle-area table + binary search for
// the triangle, uniform barycentrics by the sqrt trick (b0 = 1 − √u1, b1 = u2·√u1,
// b2 = 1 − b0 − b1), counter-based SplitMix64 random numbers per sample index (deterministic
// for any thread count). Also the shared hash grid and parallel-for helpers.
#include "pointcloud/internal.h"
#include "pointcloud/pointcloud.h"

#include "core/core.h"

#include <algorithm>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

namespace pointcloud {
namespace detail {

void parallelFor(size_t n, int threads, const std::function<void(size_t, size_t)>& body) {
    if (n == 0) return;
    auto run = [&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256),
                          [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
    };
    if (threads == 1) {
        body(0, n);
    } else if (threads > 1) {
        tbb::task_arena arena(threads);
        arena.execute(run);
    } else {
        run();
    }
}

PointGrid::PointGrid(const std::vector<V3>& points, double cellSize)
    : m_points(&points), m_cell(cellSize) {
    if (!(cellSize > 0) || !std::isfinite(cellSize)) throw core::Error("bad hash grid cell size");
    size_t buckets = 64;
    while (buckets < 2 * points.size())
        buckets *= 2;
    m_mask = buckets - 1;
    std::vector<uint32_t> bucketOfPoint(points.size());
    m_start.assign(buckets + 1, 0);
    for (size_t i = 0; i < points.size(); ++i) {
        auto c = cellOf(points[i]);
        bucketOfPoint[i] = uint32_t(bucketOf(c[0], c[1], c[2]));
        ++m_start[bucketOfPoint[i] + 1];
    }
    for (size_t b = 0; b < buckets; ++b)
        m_start[b + 1] += m_start[b];
    m_order.resize(points.size());
    std::vector<uint32_t> fill(m_start.begin(), m_start.end() - 1);
    for (size_t i = 0; i < points.size(); ++i)
        m_order[fill[bucketOfPoint[i]]++] = uint32_t(i);
}

} // namespace detail

using namespace detail;

double meshArea(const mesh::Mesh& m) {
    double a = 0;
    for (const auto& t : m.triangles) {
        V3 v0 = toV3(m.vertices[t[0]]), v1 = toV3(m.vertices[t[1]]), v2 = toV3(m.vertices[t[2]]);
        a += 0.5 * length(cross(sub(v1, v0), sub(v2, v0)));
    }
    return a;
}

PointCloud sampleUniform(const mesh::Mesh& m, size_t n, uint64_t seed, int threads) {
    if (n == 0) throw core::Error("sampleUniform: the point count must be > 0");
    if (n >= kNoTriangle) throw core::Error("sampleUniform: too many points");
    std::vector<double> cdf(m.triangles.size());
    double total = 0;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        const auto& tri = m.triangles[t];
        V3 v0 = toV3(m.vertices[tri[0]]), v1 = toV3(m.vertices[tri[1]]);
        V3 v2 = toV3(m.vertices[tri[2]]);
        total += 0.5 * length(cross(sub(v1, v0), sub(v2, v0)));
        cdf[t] = total;
    }
    if (!(total > 0) || !std::isfinite(total))
        throw core::Error("sampleUniform: the mesh has no surface area");
    const bool vertexNormals = m.normals.size() == m.vertices.size();
    PointCloud cloud;
    cloud.totalArea = total;
    cloud.points.resize(n);
    const float area = float(total / double(n));
    parallelFor(n, threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            CounterRng rng(seed, i);
            double u0 = rng.uniform() * total, u1 = rng.uniform(), u2 = rng.uniform();
            size_t t = size_t(std::upper_bound(cdf.begin(), cdf.end(), u0) - cdf.begin());
            t = std::min(t, cdf.size() - 1);
            const auto& tri = m.triangles[t];
            double su = std::sqrt(u1);
            double b0 = 1 - su, b1 = u2 * su, b2 = 1 - b0 - b1;
            V3 v0 = toV3(m.vertices[tri[0]]), v1 = toV3(m.vertices[tri[1]]);
            V3 v2 = toV3(m.vertices[tri[2]]);
            V3 p = add(add(mul(v0, b0), mul(v1, b1)), mul(v2, b2));
            V3 nrm =
                vertexNormals
                    ? add(add(mul(toV3(m.normals[tri[0]]), b0), mul(toV3(m.normals[tri[1]]), b1)),
                          mul(toV3(m.normals[tri[2]]), b2))
                    : cross(sub(v1, v0), sub(v2, v0));
            double len = length(nrm);
            if (!(len > 0)) nrm = cross(sub(v1, v0), sub(v2, v0)), len = length(nrm);
            Point& out = cloud.points[i];
            for (int k = 0; k < 3; ++k) {
                out.p[k] = float(p[k]);
                out.n[k] = float(nrm[k] / len);
            }
            out.area = area;
            out.triangle = uint32_t(t);
        }
    });
    return cloud;
}

} // namespace pointcloud
