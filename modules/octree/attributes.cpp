// Node attributes of thesis 3.3.3: per node Σ E·A (RGB), Σ A, the irradiance-weighted mean
// position Σ w·p / Σ w with w = (E_r + E_g + E_b)·A (area-weighted when Σ w = 0) and the bounding
// box, accumulated bottom-up in double and stored as float. Also the content hash.
#include "octree/internal.h"
#include "octree/octree.h"

#include "core/core.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace octree {
namespace detail {

namespace {

struct Sums {
    double ea[3] = {0, 0, 0}; // Σ E·A
    double a = 0;             // Σ A
    double wp[3] = {0, 0, 0}; // Σ w·p
    double w = 0;             // Σ w
    double ap[3] = {0, 0, 0}; // Σ A·p
    float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
};

void addPoint(Sums& s, const PointRecord& r, bool first) {
    const double area = r.positionArea[3];
    const double w =
        (double(r.irradiance[0]) + double(r.irradiance[1]) + double(r.irradiance[2])) * area;
    for (int c = 0; c < 3; ++c) {
        const double p = r.positionArea[c];
        s.ea[c] += double(r.irradiance[c]) * area;
        s.wp[c] += w * p;
        s.ap[c] += area * p;
        s.lo[c] = first ? r.positionArea[c] : std::min(s.lo[c], r.positionArea[c]);
        s.hi[c] = first ? r.positionArea[c] : std::max(s.hi[c], r.positionArea[c]);
    }
    s.a += area;
    s.w += w;
}

void addChild(Sums& s, const Sums& c, bool first) {
    for (int k = 0; k < 3; ++k) {
        s.ea[k] += c.ea[k];
        s.wp[k] += c.wp[k];
        s.ap[k] += c.ap[k];
        s.lo[k] = first ? c.lo[k] : std::min(s.lo[k], c.lo[k]);
        s.hi[k] = first ? c.hi[k] : std::max(s.hi[k], c.hi[k]);
    }
    s.a += c.a;
    s.w += c.w;
}

void store(NodeRecord& r, const Sums& s) {
    r = NodeRecord{};
    for (int c = 0; c < 3; ++c) {
        r.irradianceArea[c] = float(s.ea[c]);
        double mean;
        if (s.w > 0)
            mean = s.wp[c] / s.w;
        else if (s.a > 0)
            mean = s.ap[c] / s.a;
        else
            mean = 0.5 * (double(s.lo[c]) + double(s.hi[c])); // zero-area node: box centre
        r.meanPosition[c] = float(mean);
        r.boxMin[c] = s.lo[c];
        r.boxMax[c] = s.hi[c];
    }
    r.irradianceArea[3] = float(s.a);
}

} // namespace

void computeNodeAttributes(Octree& t) {
    const size_t nodes = t.descriptors.size();
    t.nodes.assign(nodes, NodeRecord{});
    std::vector<Sums> sums(nodes);
    // Breadth-first numbering: depth is non-decreasing with the node index, so each level is a
    // contiguous range; handle the deepest first, each level in parallel.
    size_t end = nodes;
    while (end > 0) {
        const uint32_t d = t.depth[end - 1];
        size_t begin = end;
        while (begin > 0 && t.depth[begin - 1] == d)
            --begin;
        tbb::parallel_for(tbb::blocked_range<size_t>(begin, end),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t v = r.begin(); v < r.end(); ++v) {
                                  const uint32_t desc = t.descriptors[v];
                                  Sums s;
                                  const uint32_t first = descriptorIndex(desc);
                                  if (isLeaf(desc)) {
                                      for (uint32_t k = 0; k < pointCount(desc); ++k)
                                          addPoint(s, t.points[first + k], k == 0);
                                  } else {
                                      for (uint32_t k = 0; k < childCount(desc); ++k)
                                          addChild(s, sums[first + k], k == 0);
                                  }
                                  sums[v] = s;
                                  store(t.nodes[v], s);
                              }
                          });
        end = begin;
    }
}

} // namespace detail

void setIrradiance(Octree& t, const std::vector<glm::vec3>& irradiance) {
    if (irradiance.size() != t.points.size()) {
        std::ostringstream m;
        m << "irradiance has " << irradiance.size() << " values for " << t.points.size()
          << " points";
        detail::fail(m.str());
    }
    for (size_t k = 0; k < t.points.size(); ++k) {
        const glm::vec3& e = irradiance[t.order[k]];
        PointRecord& r = t.points[k];
        r.irradiance[0] = e.x;
        r.irradiance[1] = e.y;
        r.irradiance[2] = e.z;
        r.irradiance[3] = 0;
    }
    detail::computeNodeAttributes(t);
}

std::string hash(const Octree& t) {
    std::string bytes;
    bytes.reserve(t.descriptors.size() * 4 + t.points.size() * sizeof(PointRecord) +
                  t.nodes.size() * sizeof(NodeRecord));
    bytes.append(reinterpret_cast<const char*>(t.descriptors.data()), t.descriptors.size() * 4);
    bytes.append(reinterpret_cast<const char*>(t.points.data()),
                 t.points.size() * sizeof(PointRecord));
    bytes.append(reinterpret_cast<const char*>(t.nodes.data()),
                 t.nodes.size() * sizeof(NodeRecord));
    return core::hashHex(bytes);
}

} // namespace octree
