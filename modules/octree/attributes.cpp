// Node attributes of thesis 3.3.3: per node Σ E·A (RGB), Σ A, the irradiance-weighted mean
// position Σ w·p / Σ w with w = (E_r + E_g + E_b)·A (area-weighted when Σ w = 0), the bounding
// box, and the covariance about the mean with the same weights (the second-order cluster rule,
// octree.h), accumulated bottom-up in double and stored as float. Also the content hash.
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

constexpr int kPairA[6] = {0, 1, 2, 0, 0, 1}; // (a, b) = xx, yy, zz, xy, xz, yz
constexpr int kPairB[6] = {0, 1, 2, 1, 2, 2};

// Weighted mean and central second moments M2_ab = Σ w (p_a − μ_a)(p_b − μ_b), updated one
// point at a time (West's weighted Welford) and merged pairwise (Chan et al.): stable where
// the raw moments Σ w p pᵀ − W μ μᵀ would cancel (a small cluster far from the origin).
struct Moments {
    double weight = 0;
    double mean[3] = {0, 0, 0};
    double m2[6] = {0, 0, 0, 0, 0, 0};

    void add(const double p[3], double w) {
        if (!(w > 0)) return;
        const double total = weight + w;
        double before[3], after[3];
        for (int c = 0; c < 3; ++c) {
            before[c] = p[c] - mean[c];
            mean[c] += before[c] * (w / total);
            after[c] = p[c] - mean[c];
        }
        for (int k = 0; k < 6; ++k)
            m2[k] += w * before[kPairA[k]] * after[kPairB[k]];
        weight = total;
    }
    void merge(const Moments& o) {
        if (!(o.weight > 0)) return;
        const double total = weight + o.weight;
        double delta[3];
        for (int c = 0; c < 3; ++c)
            delta[c] = o.mean[c] - mean[c];
        const double f = weight * o.weight / total;
        for (int k = 0; k < 6; ++k)
            m2[k] += o.m2[k] + delta[kPairA[k]] * delta[kPairB[k]] * f;
        for (int c = 0; c < 3; ++c)
            mean[c] += delta[c] * (o.weight / total);
        weight = total;
    }
};

struct Sums {
    double ea[3] = {0, 0, 0}; // Σ E·A
    double a = 0;             // Σ A
    double wp[3] = {0, 0, 0}; // Σ w·p
    double w = 0;             // Σ w
    double ap[3] = {0, 0, 0}; // Σ A·p
    Moments wm, am;           // irradiance- and area-weighted central moments
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
    const double p[3] = {r.positionArea[0], r.positionArea[1], r.positionArea[2]};
    s.wm.add(p, w);
    s.am.add(p, area);
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
    s.wm.merge(c.wm);
    s.am.merge(c.am);
    s.a += c.a;
    s.w += c.w;
}

void store(NodeRecord& r, const Sums& s) {
    r = NodeRecord{};
    double mean[3];
    for (int c = 0; c < 3; ++c) {
        r.irradianceArea[c] = float(s.ea[c]);
        if (s.w > 0)
            mean[c] = s.wp[c] / s.w;
        else if (s.a > 0)
            mean[c] = s.ap[c] / s.a;
        else
            mean[c] = 0.5 * (double(s.lo[c]) + double(s.hi[c])); // zero-area node: box centre
        r.meanPosition[c] = float(mean[c]);
        r.boxMin[c] = s.lo[c];
        r.boxMax[c] = s.hi[c];
    }
    r.irradianceArea[3] = float(s.a);
    // Covariance with the mean's weights (zero for a zero-area node). The moments' own mean
    // equals `mean` up to rounding; the shift (≈ 1e-16 of the extent) is far below float.
    const Moments& m = s.w > 0 ? s.wm : s.am;
    if (m.weight > 0) {
        for (int k = 0; k < 3; ++k) {
            r.covarianceDiagonal[k] = float(std::max(m.m2[k] / m.weight, 0.0));
            r.covarianceOffDiagonal[k] = float(m.m2[k + 3] / m.weight);
        }
    }
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
