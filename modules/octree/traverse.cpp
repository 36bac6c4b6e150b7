// CPU replica of the GPU octree traversal, thesis Algorithm 2 (3.3.3) with the solid-angle
// criterion of eq. 2.40 (Jensen–Buhler, thesis 2.6.4) and the second-order cluster rule
// (octree.h), recording every step. The float
// arithmetic is written exactly as shaders/octree_render.comp does it (no reassociation; the
// library is compiled with -ffp-contract=off so no multiply-add is fused).
#include "octree/octree.h"

#include "core/core.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace octree {

const char* decisionName(Decision d) {
    switch (d) {
    case Decision::Recurse:
        return "recurse";
    case Decision::EvaluateNode:
        return "node";
    case Decision::EvaluatePoints:
        return "points";
    }
    return "?";
}

namespace {

glm::vec3 vec(const float* v) {
    return glm::vec3(v[0], v[1], v[2]);
}

// d2 of the criterion, float arithmetic as in the header.
float criterionDistance2(const NodeRecord& r, const glm::vec3& xo, bool boundingBox) {
    glm::vec3 d;
    if (boundingBox) {
        const glm::vec3 lo = vec(r.boxMin), hi = vec(r.boxMax);
        d.x = std::max(lo.x - xo.x, 0.0f) + std::max(xo.x - hi.x, 0.0f);
        d.y = std::max(lo.y - xo.y, 0.0f) + std::max(xo.y - hi.y, 0.0f);
        d.z = std::max(lo.z - xo.z, 0.0f) + std::max(xo.z - hi.z, 0.0f);
    } else {
        d = xo - vec(r.meanPosition);
    }
    const float xx = d.x * d.x;
    const float yy = d.y * d.y;
    const float zz = d.z * d.z;
    return (xx + yy) + zz;
}

} // namespace

void clusterPoints(const NodeRecord& rec, const glm::vec3& xo, glm::vec3 out[3]) {
    const glm::vec3 mean = vec(rec.meanPosition);
    const glm::vec3 d = xo - mean;
    const float xx = d.x * d.x;
    const float yy = d.y * d.y;
    const float zz = d.z * d.z;
    const float r2 = (xx + yy) + zz;
    if (!(r2 > 0.0f)) {
        out[0] = out[1] = out[2] = mean;
        return;
    }
    const float* cd = rec.covarianceDiagonal;
    const float* co = rec.covarianceOffDiagonal;
    const float a = xx * cd[0] + yy * cd[1] + zz * cd[2];
    const float xy = d.x * d.y;
    const float xz = d.x * d.z;
    const float yz = d.y * d.z;
    const float b = xy * co[0] + xz * co[1] + yz * co[2];
    const float q = std::max((a + 2.0f * b) / r2, 0.0f);
    const float trace = (cd[0] + cd[1]) + cd[2];
    const float t2 = std::max(trace - q, 0.0f);
    const float r = std::sqrt(r2);
    const float s = std::sqrt(2.0f * q);
    const float m = r - s;
    const float p = r + s;
    const float rho[3] = {std::sqrt(r2 + t2), std::sqrt(m * m + t2), std::sqrt(p * p + t2)};
    for (int k = 0; k < 3; ++k)
        out[k] = xo - d * (rho[k] / r);
}

Trace traverse(const Octree& t, const glm::vec3& xo, const glm::vec3& no, const Criterion& c) {
    Trace tr;
    tr.xo = xo;
    tr.no = no;
    if (t.descriptors.empty()) return tr;
    const size_t stackSize = size_t(std::max(c.stackSize, 0));
    std::vector<uint32_t> stack;
    stack.reserve(stackSize);
    uint32_t node = 0, childnum = 0;
    uint32_t steps = 0;
    for (;;) {
        if (steps >= c.maxSteps) {
            tr.flags |= kFlagIterationCap;
            break;
        }
        ++steps;
        const uint32_t desc = t.descriptors[node];
        const NodeRecord& rec = t.nodes[node];
        const float area = rec.irradianceArea[3];
        const float d2 = criterionDistance2(rec, xo, c.boundingBox);
        Step s;
        s.node = node;
        s.depth = t.depth[node];
        s.solidAngle = d2 > 0.0f ? area / d2 : std::numeric_limits<float>::infinity();
        s.firstEvaluation = uint32_t(tr.evaluations.size());
        bool subdivide = false;
        if (!isLeaf(desc)) {
            const float threshold = c.eps * d2;
            const bool accept = area < threshold;
            const float larger = std::max(area, threshold);
            if (larger > 0.0f) {
                const float margin = std::fabs(area - threshold) / larger;
                tr.closestMargin = std::min(tr.closestMargin, margin);
            }
            subdivide = !accept;
        }
        if (subdivide) {
            s.decision = Decision::Recurse;
            if (node != 0) {
                if (stack.size() >= stackSize) {
                    tr.flags |= kFlagStackOverflow;
                    s.stack = stack;
                    tr.steps.push_back(std::move(s));
                    break;
                }
                stack.push_back(packStackEntry(node, childnum));
                tr.maxStackDepth = std::max(tr.maxStackDepth, uint32_t(stack.size()));
            }
            childnum = childCount(desc) - 1;
            node = descriptorIndex(desc) + childnum;
            s.stack = stack;
            tr.steps.push_back(std::move(s));
            continue;
        }
        if (isLeaf(desc)) {
            s.decision = Decision::EvaluatePoints;
            const uint32_t first = descriptorIndex(desc);
            for (uint32_t k = 0; k < pointCount(desc); ++k) {
                const PointRecord& p = t.points[first + k];
                const glm::vec3 e = vec(p.irradiance);
                tr.evaluations.push_back(
                    {vec(p.positionArea), vec(p.normal), e * p.positionArea[3]});
            }
        } else {
            s.decision = Decision::EvaluateNode;
            if (c.secondOrder) {
                glm::vec3 xi[3];
                clusterPoints(rec, xo, xi);
                for (int k = 0; k < 3; ++k)
                    tr.evaluations.push_back(
                        {xi[k], no, vec(rec.irradianceArea) * kClusterWeights[k]});
            } else {
                tr.evaluations.push_back({vec(rec.meanPosition), no, vec(rec.irradianceArea)});
            }
        }
        s.evaluationCount = uint32_t(tr.evaluations.size()) - s.firstEvaluation;
        // next node
        bool done = false;
        while (childnum == 0) {
            if (stack.empty()) {
                done = true;
                break;
            }
            const uint32_t e = stack.back();
            stack.pop_back();
            node = stackNode(e);
            childnum = stackChildnum(e);
        }
        s.stack = stack;
        tr.steps.push_back(std::move(s));
        if (done) break;
        node -= 1;
        childnum -= 1;
    }
    return tr;
}

void accumulate(Trace& trace, const std::vector<glm::vec3>& bssrdfValues, float scale) {
    if (bssrdfValues.size() != trace.evaluations.size()) {
        std::ostringstream m;
        m << bssrdfValues.size() << " BSSRDF values for " << trace.evaluations.size()
          << " evaluations";
        throw core::Error("octree", 0, m.str());
    }
    glm::vec3 m(0.0f);
    for (Step& s : trace.steps) {
        glm::vec3 step(0.0f);
        for (uint32_t k = s.firstEvaluation; k < s.firstEvaluation + s.evaluationCount; ++k) {
            const Evaluation& e = trace.evaluations[k];
            const glm::vec3& value = bssrdfValues[k];
            const glm::vec3 c = e.weight * (scale * scale) * value; // GLSL: the same expression
            step += c;
            m += c;
        }
        s.contribution = step;
        s.runningSum = m;
    }
    trace.radiantExitance = m;
}

} // namespace octree
