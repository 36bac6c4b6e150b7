// pointcloud internals: SplitMix64 counter-based random numbers, double-precision vector
// helpers, a uniform hash grid over points (cells of a given size hashed into a power-of-two
// bucket table, counting sort by bucket) and a thread-count-controlled parallel for (TBB).
#pragma once

#include "pointcloud/pointcloud.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

namespace pointcloud::detail {

using V3 = std::array<double, 3>;

inline V3 sub(const V3& a, const V3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline V3 add(const V3& a, const V3& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline V3 mul(const V3& a, double s) {
    return {a[0] * s, a[1] * s, a[2] * s};
}
inline double dot(const V3& a, const V3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline V3 cross(const V3& a, const V3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double length(const V3& a) {
    return std::sqrt(dot(a, a));
}
inline V3 toV3(const float* p) {
    return {p[0], p[1], p[2]};
}
inline V3 toV3(const std::array<float, 3>& p) {
    return {p[0], p[1], p[2]};
}

inline uint64_t splitMix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// Random stream for one sample index: SplitMix64 sequence seeded from (seed, index).
struct CounterRng {
    uint64_t state;
    CounterRng(uint64_t seed, uint64_t index)
        : state(splitMix64(seed) ^ splitMix64(index * 0xD1B54A32D192ED03ull + 1)) {}
    uint64_t next() {
        state += 0x9E3779B97F4A7C15ull;
        uint64_t z = state;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * 0x1.0p-53; } // [0, 1)
};

// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5);
// returns the barycentrics (u, v, w) of the closest point, u·a + v·b + w·c (relaxation.cpp).
V3 closestBarycentric(const V3& p, const V3& a, const V3& b, const V3& c);

// Runs body(begin, end) over [0, n) in parallel with `threads` threads (0 = all cores).
void parallelFor(size_t n, int threads, const std::function<void(size_t, size_t)>& body);

// Uniform hash grid over a fixed set of positions.
class PointGrid {
  public:
    PointGrid(const std::vector<V3>& points, double cellSize);
    double cellSize() const { return m_cell; }
    // Calls f(j) for every point j in the cells of ring `ring` (Chebyshev distance in cells)
    // around the cell of p; buckets are visited once per call (hash collisions only add
    // candidates, never duplicates).
    template <class F> void forRing(const V3& p, int ring, F&& f) const;
    // Calls f(j, d) for every j != self with |p_j − p| < radius (radius <= cellSize).
    template <class F> void forNeighbours(const V3& p, size_t self, double radius, F&& f) const;
    // Clamped to ±2^62 (monotone, so neighbours stay in adjacent cells): a point far out still
    // has a cell that converts to int64 and survives the ring offsets.
    std::array<int64_t, 3> cellOf(const V3& p) const {
        constexpr double kLimit = 4611686018427387904.0;
        auto cell = [&](double x) {
            return int64_t(std::clamp(std::floor(x / m_cell), -kLimit, kLimit));
        };
        return {cell(p[0]), cell(p[1]), cell(p[2])};
    }
    const std::vector<V3>& points() const { return *m_points; }

  private:
    size_t bucketOf(int64_t x, int64_t y, int64_t z) const {
        uint64_t h =
            uint64_t(x) * 73856093ull ^ uint64_t(y) * 19349663ull ^ uint64_t(z) * 83492791ull;
        return size_t(splitMix64(h) & m_mask);
    }
    template <class F> void visitBuckets(std::vector<size_t>& buckets, F&& f) const;

    const std::vector<V3>* m_points;
    double m_cell;
    uint64_t m_mask;
    std::vector<uint32_t> m_start; // bucket -> first index into m_order (size buckets + 1)
    std::vector<uint32_t> m_order; // point indices sorted by bucket
};

template <class F> void PointGrid::visitBuckets(std::vector<size_t>& buckets, F&& f) const {
    std::sort(buckets.begin(), buckets.end());
    buckets.erase(std::unique(buckets.begin(), buckets.end()), buckets.end());
    for (size_t b : buckets)
        for (uint32_t k = m_start[b]; k < m_start[b + 1]; ++k)
            f(size_t(m_order[k]));
}

template <class F> void PointGrid::forRing(const V3& p, int ring, F&& f) const {
    auto c = cellOf(p);
    std::vector<size_t> buckets;
    for (int dz = -ring; dz <= ring; ++dz)
        for (int dy = -ring; dy <= ring; ++dy)
            for (int dx = -ring; dx <= ring; ++dx) {
                if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != ring) continue;
                buckets.push_back(bucketOf(c[0] + dx, c[1] + dy, c[2] + dz));
            }
    visitBuckets(buckets, f);
}

template <class F>
void PointGrid::forNeighbours(const V3& p, size_t self, double radius, F&& f) const {
    auto c = cellOf(p);
    std::vector<size_t> buckets;
    buckets.reserve(27);
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                buckets.push_back(bucketOf(c[0] + dx, c[1] + dy, c[2] + dz));
    const auto& pts = *m_points;
    visitBuckets(buckets, [&](size_t j) {
        if (j == self) return;
        double d = length(sub(pts[j], p));
        if (d < radius) f(j, d);
    });
}

} // namespace pointcloud::detail
