// Parameterisation for texture-space sampling (texspace.h).
#include "texspace/texspace.h"

#include "core/core.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace texspace {

namespace {

constexpr double kOverlapTolerance = 1e-9;

double cross2(const glm::dvec2& a, const glm::dvec2& b) {
    return a.x * b.y - a.y * b.x;
}

double textureArea(const std::array<glm::dvec2, 3>& t) {
    return 0.5 * std::abs(cross2(t[1] - t[0], t[2] - t[0]));
}

glm::dvec3 vertex(const mesh::Mesh& m, uint32_t i) {
    return {m.vertices[i][0], m.vertices[i][1], m.vertices[i][2]};
}

double surfaceArea(const mesh::Mesh& m, size_t t) {
    const auto& tri = m.triangles[t];
    const glm::dvec3 a = vertex(m, tri[0]), b = vertex(m, tri[1]), c = vertex(m, tri[2]);
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

// σ1/σ2 of the affine map from the texture triangle to the surface triangle.
double stretchOf(const mesh::Mesh& m, size_t t, const std::array<glm::dvec2, 3>& uv) {
    const auto& tri = m.triangles[t];
    const glm::dvec3 p0 = vertex(m, tri[0]), e1 = vertex(m, tri[1]) - p0,
                     e2 = vertex(m, tri[2]) - p0;
    const glm::dvec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
    const double det = cross2(d1, d2);
    if (det == 0) return INFINITY;
    // J = [e1 e2] · [d1 d2]⁻¹ (3×2); its Gram matrix G = JᵀJ gives σ² as eigenvalues
    const glm::dvec3 ju = (e1 * d2.y - e2 * d1.y) / det, jv = (e2 * d1.x - e1 * d2.x) / det;
    const double a = glm::dot(ju, ju), b = glm::dot(ju, jv), c = glm::dot(jv, jv);
    const double tr = a + c, disc = std::sqrt(std::max(0.0, 0.25 * (a - c) * (a - c) + b * b));
    const double l1 = 0.5 * tr + disc, l2 = 0.5 * tr - disc;
    return l2 > 0 ? std::sqrt(l1 / l2) : INFINITY;
}

// Interiors of two triangles overlap (separating axes: the six edge normals).
bool overlap(const std::array<glm::dvec2, 3>& a, const std::array<glm::dvec2, 3>& b) {
    for (const auto* t : {&a, &b})
        for (int e = 0; e < 3; ++e) {
            const glm::dvec2 d = (*t)[(e + 1) % 3] - (*t)[e];
            const glm::dvec2 n(-d.y, d.x);
            double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
            for (int k = 0; k < 3; ++k) {
                const double pa = glm::dot(n, a[k]), pb = glm::dot(n, b[k]);
                amin = std::min(amin, pa), amax = std::max(amax, pa);
                bmin = std::min(bmin, pb), bmax = std::max(bmax, pb);
            }
            const double scale = std::max(1e-300, glm::length(n));
            if (std::min(amax, bmax) - std::max(amin, bmin) <= kOverlapTolerance * scale)
                return false;
        }
    return true;
}

std::string num(double v) {
    std::ostringstream s;
    s.precision(6);
    s << v;
    return s.str();
}

} // namespace

std::string uvProblem(const std::vector<std::array<glm::dvec2, 3>>& uv,
                      const std::vector<double>& areaSurface) {
    const size_t n = uv.size();
    for (size_t t = 0; t < n; ++t) {
        for (int k = 0; k < 3; ++k) {
            const glm::dvec2 p = uv[t][size_t(k)];
            if (!(p.x >= 0 && p.x <= 1 && p.y >= 0 && p.y <= 1))
                return "triangle " + std::to_string(t) + ": texture coordinate (" + num(p.x) +
                       ", " + num(p.y) + ") outside [0, 1]²";
        }
        if (!(textureArea(uv[t]) > 1e-14))
            return "triangle " + std::to_string(t) + ": no area in the texture";
        if (t < areaSurface.size() && !(areaSurface[t] > 0))
            return "triangle " + std::to_string(t) + ": no area on the surface";
    }
    // bin by bounding box on a grid of about n cells, test the pairs that share a cell
    const int g = std::max(1, int(std::sqrt(double(n))));
    std::vector<std::vector<uint32_t>> cells(size_t(g) * size_t(g));
    auto cellOf = [&](double v) { return std::clamp(int(v * g), 0, g - 1); };
    for (size_t t = 0; t < n; ++t) {
        double x0 = 1, x1 = 0, y0 = 1, y1 = 0;
        for (const glm::dvec2& p : uv[t]) {
            x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
            y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
        }
        for (int j = cellOf(y0); j <= cellOf(y1); ++j)
            for (int i = cellOf(x0); i <= cellOf(x1); ++i)
                cells[size_t(j) * size_t(g) + size_t(i)].push_back(uint32_t(t));
    }
    for (const auto& c : cells)
        for (size_t a = 0; a < c.size(); ++a)
            for (size_t b = a + 1; b < c.size(); ++b)
                if (overlap(uv[c[a]], uv[c[b]]))
                    return "triangles " + std::to_string(std::min(c[a], c[b])) + " and " +
                           std::to_string(std::max(c[a], c[b])) + " overlap in the texture";
    return "";
}

std::string uvProblem(const mesh::Mesh& m) {
    if (m.uvs.empty()) return "the mesh has no texture coordinates";
    if (m.uvs.size() != m.vertices.size())
        return "the mesh has " + std::to_string(m.uvs.size()) + " texture coordinates for " +
               std::to_string(m.vertices.size()) + " vertices";
    std::vector<std::array<glm::dvec2, 3>> uv(m.triangles.size());
    std::vector<double> area(m.triangles.size());
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const auto& p = m.uvs[m.triangles[t][size_t(k)]];
            uv[t][size_t(k)] = {p[0], p[1]};
        }
        area[t] = surfaceArea(m, t);
    }
    return uvProblem(uv, area);
}

Parameterization packAtlas(const mesh::Mesh& m, int textureSize, double gutterTexels) {
    if (textureSize < 2) throw core::Error("atlas", 0, "the texture needs at least 2×2 texels");
    const size_t n = m.triangles.size();
    if (n == 0) throw core::Error("atlas", 0, "the mesh has no triangles");
    Parameterization p;
    const int g = int(std::ceil(std::sqrt(std::ceil(double(n) / 2.0))));
    p.gridCells = g;
    const double cell = 1.0 / g, gutter = gutterTexels / textureSize;
    // a half cell's inscribed circle has radius (2 − √2)/2 · cell; the gutter must leave room
    if (!(gutter < 0.25 * (2 - std::sqrt(2.0)) * cell))
        throw core::Error("atlas", 0,
                          std::to_string(n) + " triangles need a texture larger than " +
                              std::to_string(textureSize) + "² for cells of " + std::to_string(g) +
                              " per side with " + num(gutterTexels) + "-texel gutters");
    p.uv.resize(n);
    p.areaSurface.resize(n);
    p.areaTexture.resize(n);
    p.stretch.resize(n);
    for (size_t t = 0; t < n; ++t) {
        const size_t c = t / 2;
        const glm::dvec2 o(double(c % size_t(g)) * cell, double(c / size_t(g)) * cell);
        std::array<glm::dvec2, 3> q;
        if (t % 2 == 0) // lower-left half: (0,0), (1,0), (0,1)
            q = {o, o + glm::dvec2(cell, 0), o + glm::dvec2(0, cell)};
        else // upper-right half: (1,1), (0,1), (1,0) — counter-clockwise as well
            q = {o + glm::dvec2(cell, cell), o + glm::dvec2(0, cell), o + glm::dvec2(cell, 0)};
        // shrink towards the incentre so every edge moves inwards by the gutter
        const double la = glm::length(q[1] - q[2]), lb = glm::length(q[2] - q[0]),
                     lc = glm::length(q[0] - q[1]);
        const glm::dvec2 inc = (la * q[0] + lb * q[1] + lc * q[2]) / (la + lb + lc);
        const double inradius = 2 * textureArea(q) / (la + lb + lc);
        const double k = (inradius - gutter) / inradius;
        for (int i = 0; i < 3; ++i)
            p.uv[t][size_t(i)] = inc + k * (q[size_t(i)] - inc);
        p.areaSurface[t] = surfaceArea(m, t);
        if (!(p.areaSurface[t] > 0))
            throw core::Error("atlas", 0, "triangle " + std::to_string(t) + " has no area");
        p.areaTexture[t] = textureArea(p.uv[t]);
        p.stretch[t] = stretchOf(m, t, p.uv[t]);
    }
    return p;
}

Parameterization parameterize(const mesh::Mesh& m, int textureSize) {
    const std::string problem = uvProblem(m);
    if (!problem.empty()) {
        Parameterization p = packAtlas(m, textureSize);
        p.note = "the mesh's UVs do not qualify (" + problem + "): a generated atlas is used";
        return p;
    }
    Parameterization p;
    p.fromMesh = true;
    const size_t n = m.triangles.size();
    p.uv.resize(n);
    p.areaSurface.resize(n);
    p.areaTexture.resize(n);
    p.stretch.resize(n);
    for (size_t t = 0; t < n; ++t) {
        for (int k = 0; k < 3; ++k) {
            const auto& q = m.uvs[m.triangles[t][size_t(k)]];
            p.uv[t][size_t(k)] = {q[0], q[1]};
        }
        p.areaSurface[t] = surfaceArea(m, t);
        p.areaTexture[t] = textureArea(p.uv[t]);
        p.stretch[t] = stretchOf(m, t, p.uv[t]);
    }
    return p;
}

} // namespace texspace
