// Octree construction, thesis 3.3.1 (centroid split, octant labels, counting sort [Knu98]) with
// the breadth-first node numbering and 32-bit child descriptors of thesis 3.3.3 (Figs. 3.4,
// 3.5). Each level is split in parallel (disjoint slices); children are numbered sequentially
// in node order, so the result does not depend on the thread count.
#include "octree/internal.h"
#include "octree/octree.h"

#include "core/core.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace octree {
namespace detail {

void fail(const std::string& message) {
    throw core::Error("octree", 0, message);
}

} // namespace detail

namespace {

struct Item {
    float p[3];
    uint32_t input; // input index of the point
};

enum class SplitKind : uint8_t { Leaf, Interior, TooManyCoincident };

struct Split {
    SplitKind kind = SplitKind::Leaf;
    std::array<uint32_t, 8> counts{}; // points per octant (Interior)
};

// Splits items[begin, end) in place (stable counting sort on the octant code).
Split splitNode(std::vector<Item>& items, std::vector<Item>& scratch, std::vector<uint8_t>& codes,
                size_t begin, size_t end) {
    Split s;
    const size_t n = end - begin;
    if (n <= size_t(kMaxLeafPoints)) return s;
    double sum[3] = {0, 0, 0};
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a)
        lo[a] = hi[a] = items[begin].p[a];
    for (size_t k = begin; k < end; ++k) {
        for (int a = 0; a < 3; ++a) {
            const float v = items[k].p[a];
            sum[a] += double(v);
            lo[a] = std::min(lo[a], v);
            hi[a] = std::max(hi[a], v);
        }
    }
    if (lo[0] == hi[0] && lo[1] == hi[1] && lo[2] == hi[2]) {
        // Coincident points: one leaf if the 4-bit point count can hold them.
        s.kind = n <= size_t(kMaxCoincidentPoints) ? SplitKind::Leaf : SplitKind::TooManyCoincident;
        return s;
    }
    double c[3];
    for (int a = 0; a < 3; ++a)
        c[a] = sum[a] / double(n);
    auto label = [&] {
        s.counts.fill(0);
        for (size_t k = begin; k < end; ++k) {
            const Item& it = items[k];
            const uint8_t o =
                uint8_t((double(it.p[0]) >= c[0] ? 1 : 0) | (double(it.p[1]) >= c[1] ? 2 : 0) |
                        (double(it.p[2]) >= c[2] ? 4 : 0));
            codes[k] = o;
            ++s.counts[o];
        }
        int nonEmpty = 0;
        for (uint32_t cnt : s.counts)
            nonEmpty += cnt > 0 ? 1 : 0;
        return nonEmpty;
    };
    if (label() < 2) {
        // The exact mean always separates distinct points; a rounded one could fail to (points
        // a few ulps apart). Fall back to the box midpoint, which always separates them.
        for (int a = 0; a < 3; ++a)
            c[a] = 0.5 * (double(lo[a]) + double(hi[a]));
        label();
    }
    std::array<size_t, 8> fill{};
    size_t off = begin;
    for (int o = 0; o < 8; ++o) {
        fill[o] = off;
        off += s.counts[o];
    }
    for (size_t k = begin; k < end; ++k)
        scratch[fill[codes[k]]++] = items[k];
    std::copy(scratch.begin() + std::ptrdiff_t(begin), scratch.begin() + std::ptrdiff_t(end),
              items.begin() + std::ptrdiff_t(begin));
    s.kind = SplitKind::Interior;
    return s;
}

} // namespace

Octree build(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
             const std::vector<float>& areas) {
    return build(positions, normals, areas, BuildOptions{});
}

Octree build(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
             const std::vector<float>& areas, const BuildOptions& options) {
    core::Stopwatch clock;
    using detail::fail;
    const size_t n = positions.size();
    if (n == 0) fail("cannot build an octree of no points");
    if (normals.size() != n || areas.size() != n) {
        std::ostringstream m;
        m << "positions, normals and areas differ in length (" << n << ", " << normals.size()
          << ", " << areas.size() << ")";
        fail(m.str());
    }
    const size_t maxCount = size_t(options.maxIndex) + 1;
    if (n > maxCount) {
        std::ostringstream m;
        m << n << " points exceed the point limit of " << maxCount
          << " (24-bit index field of the child descriptor)";
        fail(m.str());
    }
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3& p = positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            std::ostringstream m;
            m << "point " << i << " has a non-finite position (" << p.x << ", " << p.y << ", "
              << p.z << ")";
            fail(m.str());
        }
        if (!std::isfinite(areas[i]) || areas[i] < 0) {
            std::ostringstream m;
            m << "point " << i << " has an invalid area " << areas[i]
              << " (must be finite and >= 0)";
            fail(m.str());
        }
    }
    const int maxDepthAllowed = options.stackSize + 1;

    std::vector<Item> items(n), scratch(n);
    std::vector<uint8_t> codes(n);
    for (size_t i = 0; i < n; ++i)
        items[i] = Item{{positions[i].x, positions[i].y, positions[i].z}, uint32_t(i)};

    Octree t;
    struct Range {
        uint32_t begin, end;
    };
    std::vector<Range> range{{0, uint32_t(n)}};
    t.descriptors.push_back(0);
    t.depth.push_back(0);
    t.parent.push_back(0);

    size_t levelBegin = 0, levelEnd = 1;
    uint32_t level = 0;
    std::vector<Split> splits;
    while (levelBegin < levelEnd) {
        const size_t count = levelEnd - levelBegin;
        splits.assign(count, Split{});
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t k = r.begin(); k < r.end(); ++k) {
                                  const Range& rg = range[levelBegin + k];
                                  splits[k] = splitNode(items, scratch, codes, rg.begin, rg.end);
                              }
                          });
        for (size_t k = 0; k < count; ++k) {
            const size_t node = levelBegin + k;
            const Range rg = range[node];
            const Split& s = splits[k];
            if (s.kind == SplitKind::TooManyCoincident) {
                std::ostringstream m;
                m << (rg.end - rg.begin) << " coincident points at (" << items[rg.begin].p[0]
                  << ", " << items[rg.begin].p[1] << ", " << items[rg.begin].p[2]
                  << ") exceed the limit of " << kMaxCoincidentPoints
                  << " per leaf (4-bit point count)";
                fail(m.str());
            }
            if (s.kind == SplitKind::Leaf) {
                t.descriptors[node] = packDescriptor(0, rg.end - rg.begin, rg.begin);
                continue;
            }
            const size_t firstChild = t.descriptors.size();
            uint32_t children = 0, off = rg.begin;
            for (int o = 0; o < 8; ++o) {
                if (s.counts[o] == 0) continue;
                range.push_back({off, off + s.counts[o]});
                off += s.counts[o];
                t.descriptors.push_back(0);
                t.depth.push_back(level + 1);
                t.parent.push_back(uint32_t(node));
                ++children;
            }
            if (t.descriptors.size() > maxCount) {
                std::ostringstream m;
                m << "more than " << maxCount << " octree nodes (node limit of the 24-bit index "
                  << "field) for " << n << " points";
                fail(m.str());
            }
            t.descriptors[node] = packDescriptor(children, 0, uint32_t(firstChild));
        }
        levelBegin = levelEnd;
        levelEnd = t.descriptors.size();
        ++level;
        if (levelBegin<levelEnd&& int(level)> maxDepthAllowed) {
            std::ostringstream m;
            m << "octree depth " << level
              << " exceeds the traversal stack limit: " << options.stackSize
              << " stack entries allow depth " << maxDepthAllowed << " at most (" << n
              << " points too clustered)";
            fail(m.str());
        }
    }

    t.order.resize(n);
    t.points.resize(n);
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = items[k].input;
        t.order[k] = i;
        PointRecord& r = t.points[k];
        r = PointRecord{};
        r.positionArea[0] = positions[i].x;
        r.positionArea[1] = positions[i].y;
        r.positionArea[2] = positions[i].z;
        r.positionArea[3] = areas[i];
        r.normal[0] = normals[i].x;
        r.normal[1] = normals[i].y;
        r.normal[2] = normals[i].z;
    }
    t.nodes.assign(t.descriptors.size(), NodeRecord{});
    detail::computeNodeAttributes(t);

    BuildStats& st = t.stats;
    st.nodes = t.descriptors.size();
    st.points = n;
    st.maxDepth = int(t.depth.back());
    st.nodesPerDepth.assign(size_t(st.maxDepth) + 1, 0);
    st.leafOccupancy.assign(size_t(kMaxCoincidentPoints) + 1, 0);
    for (size_t v = 0; v < st.nodes; ++v) {
        ++st.nodesPerDepth[t.depth[v]];
        if (isLeaf(t.descriptors[v])) {
            ++st.leaves;
            ++st.leafOccupancy[pointCount(t.descriptors[v])];
        }
    }
    st.bytes = st.nodes * (sizeof(uint32_t) + sizeof(NodeRecord)) + n * sizeof(PointRecord);
    st.buildMs = clock.ms();
    return t;
}

} // namespace octree
