// Texture-space stages on the CPU side (texture_space.h).
#include "texspace/texture_space.h"

#include "core/core.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace texspace {

namespace {

double edge(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) {
    return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
}
// Top-left rule for a counter-clockwise triangle: a centre exactly on an edge is inside only for
// a "top" or "left" edge, so it belongs to one of the two triangles sharing that edge.
bool topLeft(const glm::dvec2& a, const glm::dvec2& b) {
    const glm::dvec2 d = b - a;
    return (d.y == 0 && d.x < 0) || d.y > 0;
}

} // namespace

Texels rasterize(const mesh::Mesh& m, const Parameterization& p, int size) {
    if (size < 2 || size > 8192)
        throw core::Error("texture space", 0, "texture size must lie in [2, 8192]");
    Texels t;
    t.size = size;
    const size_t n = size_t(size) * size_t(size);
    t.triangle.assign(n, -1);
    t.position.assign(n, glm::dvec3(0.0));
    t.normal.assign(n, glm::dvec3(0, 0, 1));
    t.areaRatio.assign(n, 0.0);
    const bool normals = m.normals.size() == m.vertices.size();
    for (size_t f = 0; f < p.uv.size(); ++f) {
        std::array<glm::dvec2, 3> q = p.uv[f];
        std::array<uint32_t, 3> v = m.triangles[f];
        if (edge(q[0], q[1], q[2]) < 0) { // make it counter-clockwise in the texture
            std::swap(q[1], q[2]);
            std::swap(v[1], v[2]);
        }
        const double area2 = edge(q[0], q[1], q[2]);
        if (!(area2 > 0)) continue;
        double x0 = 1, x1 = 0, y0 = 1, y1 = 0;
        for (const auto& c : q) {
            x0 = std::min(x0, c.x), x1 = std::max(x1, c.x);
            y0 = std::min(y0, c.y), y1 = std::max(y1, c.y);
        }
        const int i0 = std::max(0, int(std::floor(x0 * size - 0.5))),
                  i1 = std::min(size - 1, int(std::ceil(x1 * size - 0.5))),
                  j0 = std::max(0, int(std::floor(y0 * size - 0.5))),
                  j1 = std::min(size - 1, int(std::ceil(y1 * size - 0.5)));
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const glm::dvec2 c((i + 0.5) / size, (j + 0.5) / size);
                const double w0 = edge(q[1], q[2], c), w1 = edge(q[2], q[0], c),
                             w2 = edge(q[0], q[1], c);
                auto in = [](double w, bool tl) { return w > 0 || (w == 0 && tl); };
                if (!in(w0, topLeft(q[1], q[2])) || !in(w1, topLeft(q[2], q[0])) ||
                    !in(w2, topLeft(q[0], q[1])))
                    continue;
                const size_t k = size_t(j) * size_t(size) + size_t(i);
                if (t.triangle[k] < 0) ++t.covered;
                t.triangle[k] = int32_t(f);
                glm::dvec3 x(0.0), nn(0.0);
                const double b[3] = {w0 / area2, w1 / area2, w2 / area2};
                for (int c3 = 0; c3 < 3; ++c3) {
                    const auto& pv = m.vertices[v[size_t(c3)]];
                    x += b[c3] * glm::dvec3(pv[0], pv[1], pv[2]);
                    if (normals) {
                        const auto& nv = m.normals[v[size_t(c3)]];
                        nn += b[c3] * glm::dvec3(nv[0], nv[1], nv[2]);
                    }
                }
                if (!normals) { // the face normal
                    const auto& a = m.vertices[v[0]];
                    const auto& bb = m.vertices[v[1]];
                    const auto& cc = m.vertices[v[2]];
                    nn = glm::cross(glm::dvec3(bb[0] - a[0], bb[1] - a[1], bb[2] - a[2]),
                                    glm::dvec3(cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]));
                }
                t.position[k] = x;
                t.normal[k] = glm::dot(nn, nn) > 0 ? glm::normalize(nn) : glm::dvec3(0, 0, 1);
                t.areaRatio[k] = p.areaRatio(f);
            }
    }
    return t;
}

MipCdf buildMipCdf(const std::vector<double>& weights, int size) {
    if (size < 1 || (size & (size - 1)) != 0)
        throw core::Error("texture space", 0, "the CDF texture side must be a power of two");
    if (weights.size() != size_t(size) * size_t(size))
        throw core::Error("texture space", 0, "weights and texture size differ");
    for (double w : weights)
        if (!(w >= 0) || !std::isfinite(w))
            throw core::Error("texture space", 0, "a texel weight is negative or not finite");
    MipCdf c;
    c.size = size;
    c.levels.push_back(weights);
    for (int s = size; s > 1; s /= 2) {
        const std::vector<double>& fine = c.levels.back();
        std::vector<double> coarse(size_t(s / 2) * size_t(s / 2));
        for (int j = 0; j < s / 2; ++j)
            for (int i = 0; i < s / 2; ++i)
                coarse[size_t(j) * size_t(s / 2) + size_t(i)] =
                    fine[size_t(2 * j) * size_t(s) + size_t(2 * i)] +
                    fine[size_t(2 * j) * size_t(s) + size_t(2 * i + 1)] +
                    fine[size_t(2 * j + 1) * size_t(s) + size_t(2 * i)] +
                    fine[size_t(2 * j + 1) * size_t(s) + size_t(2 * i + 1)];
        c.levels.push_back(std::move(coarse));
    }
    if (!(c.total() > 0)) throw core::Error("texture space", 0, "no texel has any weight");
    return c;
}

uint32_t sampleMip(const MipCdf& cdf, double u) {
    int i = 0, j = 0; // texel at the current level
    double p = std::clamp(u, 0.0, 1.0) * cdf.total();
    for (size_t l = cdf.levels.size() - 1; l-- > 0;) {
        const std::vector<double>& fine = cdf.levels[l];
        const int s = cdf.size >> l; // side of level l
        // the four children in the order of Algorithm 3.1's texel_next offsets
        const int ci[4] = {2 * i, 2 * i + 1, 2 * i + 1, 2 * i};
        const int cj[4] = {2 * j, 2 * j, 2 * j + 1, 2 * j + 1};
        int chosen = -1, lastNonZero = 0;
        for (int k = 0; k < 4; ++k) {
            const double w = fine[size_t(cj[k]) * size_t(s) + size_t(ci[k])];
            if (w > 0) lastNonZero = k;
            if (chosen < 0 && w > 0 && p < w) chosen = k;
            if (chosen < 0) p -= w;
        }
        if (chosen < 0) { // rounding left p at or beyond the last child: take the last with weight
            chosen = lastNonZero;
            p = fine[size_t(cj[chosen]) * size_t(s) + size_t(ci[chosen])] * (1 - 1e-16);
        }
        i = ci[chosen];
        j = cj[chosen];
    }
    return uint32_t(j) * uint32_t(cdf.size) + uint32_t(i);
}

} // namespace texspace
