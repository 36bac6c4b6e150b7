// render/raster_rule: a G-buffer checked against the mesh and camera by an independent ray
// caster (raster_rule.h).
#include "render/raster_rule.h"

#include "core/core.h"
#include "pathtrace/mesh_scene.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace render {

namespace {

struct Geometry {
    const mesh::Mesh& mesh;
    const pathtrace::MeshScene& scene;
    glm::dmat4 viewProjection, inverse;
    glm::dvec3 eye;
    int width, height;
    double pixelAngle; // a pixel's size at unit distance (image centre)

    // The pixel coordinates (x right, y down, centres at +0.5) a point projects to.
    glm::dvec2 project(const glm::dvec3& p) const {
        const glm::dvec4 c = viewProjection * glm::dvec4(p, 1.0);
        return {(c.x / c.w + 1.0) * 0.5 * width, (c.y / c.w + 1.0) * 0.5 * height};
    }
    // The triangle first hit by the ray from the camera through pixel coordinates s, at a
    // distance from the camera of at least `from`, and that distance.
    bool firstHit(glm::dvec2 s, double from, uint32_t& prim, double& t) const {
        const glm::dvec2 ndc(2.0 * s.x / width - 1.0, 2.0 * s.y / height - 1.0);
        const glm::dvec4 b = inverse * glm::dvec4(ndc, 1.0, 1.0);
        const glm::dvec3 to = glm::dvec3(b) / b.w;
        const glm::dvec3 dir = glm::normalize(to - eye);
        const double org[3] = {eye.x, eye.y, eye.z}, d[3] = {dir.x, dir.y, dir.z};
        return scene.intersect(org, d, from, glm::length(to - eye), t, prim);
    }
    bool hitThrough(double px, double py) const {
        uint32_t prim = 0;
        double t = 0;
        return firstHit(glm::dvec2(px, py), 0.0, prim, t);
    }
    glm::dvec3 vertex(uint32_t prim, int k) const {
        const auto& v = mesh.vertices[mesh.triangles[prim][size_t(k)]];
        return {v[0], v[1], v[2]};
    }
    glm::dvec3 faceNormal(uint32_t prim) const {
        const auto& n = scene.normal(prim);
        return {n[0], n[1], n[2]};
    }
    // The mesh's interpolated vertex normal at point q of triangle `prim` (normalised; (0, 0, 1)
    // where it vanishes, as render_gbuffer.frag).
    glm::dvec3 normalAt(uint32_t prim, const glm::dvec3& q) const {
        const auto& tri = mesh.triangles[prim];
        auto vtx = [&](int k) {
            const auto& v = mesh.vertices[tri[size_t(k)]];
            return glm::dvec3(v[0], v[1], v[2]);
        };
        auto nrm = [&](int k) {
            const auto& v = mesh.normals[tri[size_t(k)]];
            return glm::dvec3(v[0], v[1], v[2]);
        };
        const glm::dvec3 a = vtx(0), e1 = vtx(1) - a, e2 = vtx(2) - a, r = q - a;
        // barycentric coordinates of q's projection onto the triangle's plane
        const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
        const double r1 = glm::dot(r, e1), r2 = glm::dot(r, e2);
        const double den = d11 * d22 - d12 * d12;
        if (!(den > 0)) return nrm(0);
        const double b1 = (d22 * r1 - d12 * r2) / den, b2 = (d11 * r2 - d12 * r1) / den;
        const glm::dvec3 n = (1.0 - b1 - b2) * nrm(0) + b1 * nrm(1) + b2 * nrm(2);
        const double len = glm::length(n);
        return len > 0 ? n / len : glm::dvec3(0, 0, 1);
    }
};

} // namespace

// The mesh with its normals, its ray caster and the triangles around each vertex.
struct RasterRule::Prepared {
    mesh::Mesh mesh;
    pathtrace::MeshScene scene;
    std::vector<std::vector<uint32_t>> around;

    static mesh::Mesh withNormals(const mesh::Mesh& input) {
        if (input.vertices.empty() || input.triangles.empty())
            throw core::Error("render", 0, "the mesh to check against has no triangles");
        mesh::Mesh m = input;
        if (m.normals.size() != m.vertices.size()) mesh::computeVertexNormals(m);
        return m;
    }
    explicit Prepared(const mesh::Mesh& input)
        : mesh(withNormals(input)), scene(mesh), around(mesh.vertices.size()) {
        for (uint32_t t = 0; t < uint32_t(mesh.triangles.size()); ++t)
            for (const uint32_t v : mesh.triangles[t])
                around[v].push_back(t);
    }
};

RasterRule::RasterRule(const mesh::Mesh& m) : m_prepared(std::make_unique<Prepared>(m)) {}
RasterRule::~RasterRule() = default;

RasterCheck checkRasterisation(const Gbuffer& g, const mesh::Mesh& m, const Camera& camera) {
    return RasterRule(m).check(g, camera);
}

RasterCheck RasterRule::check(const Gbuffer& g, const Camera& camera) const {
    const size_t n = size_t(std::max(g.width, 0)) * size_t(std::max(g.height, 0));
    if (n == 0 || g.position.size() != n || g.normal.size() != n)
        throw core::Error("render", 0, "the G-buffer to check is empty or its images do not fit");
    const mesh::Mesh& m = m_prepared->mesh;
    const pathtrace::MeshScene& scene = m_prepared->scene;
    const std::vector<std::vector<uint32_t>>& around = m_prepared->around;
    Camera cam = camera;
    cam.aspect = float(g.width) / float(g.height);
    const glm::mat4 flip = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, -1.0f, 1.0f));
    const glm::dmat4 vp = glm::dmat4(flip * cam.projection() * cam.view());
    const Geometry geo{m,
                       scene,
                       vp,
                       glm::inverse(vp),
                       glm::dvec3(cam.position()),
                       g.width,
                       g.height,
                       2.0 * std::tan(0.5 * double(cam.fovY)) / g.height};

    RasterCheck r;
    r.pixels = n;
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const size_t p = size_t(y) * size_t(g.width) + size_t(x);
            const double cx = x + 0.5, cy = y + 0.5;
            if (!(g.position[p].w > 0.5f)) {
                bool inside = geo.hitThrough(cx, cy);
                for (int dy = -1; dy <= 1 && inside; ++dy)
                    for (int dx = -1; dx <= 1 && inside; ++dx)
                        if (dx != 0 || dy != 0)
                            inside = geo.hitThrough(cx + dx * kRasterShift, cy + dy * kRasterShift);
                r.uncoveredInside += inside;
                continue;
            }
            ++r.covered;
            const glm::dvec3 P(g.position[p]);
            const glm::dvec2 at = geo.project(P);
            const double off = std::max(std::fabs(at.x - cx), std::fabs(at.y - cy));
            r.worstOffCentre = std::max(r.worstOffCentre, off);
            r.offCentre += !(off <= kRasterShift);

            // P on the mesh: its nearest triangle has a point q within kSnap px of P in the
            // image, with P on its plane
            const double dist = glm::length(P - geo.eye);
            const double footprint = dist * geo.pixelAngle;
            const double pp[3] = {P.x, P.y, P.z};
            double qq[3] = {};
            uint32_t prim = 0;
            double plane = std::numeric_limits<double>::infinity();
            if (scene.nearest(pp, 4.0 * footprint, prim, qq)) {
                const glm::dvec3 q(qq[0], qq[1], qq[2]);
                const double image = glm::length(geo.project(q) - at);
                if (image <= kSnap) plane = std::fabs(glm::dot(P - q, geo.faceNormal(prim))) / dist;
            }
            r.worstDepth = std::max(r.worstDepth, plane);
            if (!(plane <= kDepthTolerance)) {
                ++r.offSurface;
                continue;
            }
            // P visible: some ray through its projection or a point kSnap px around it meets
            // nothing nearer than kVisibility of P's distance (a surface that close in front
            // may lose the depth test to P's: depth precision, a crevice)
            bool visible = false;
            for (int dy = -1; dy <= 1 && !visible; ++dy)
                for (int dx = -1; dx <= 1 && !visible; ++dx) {
                    uint32_t first = 0;
                    double t = 0;
                    visible = !geo.firstHit(glm::dvec2(at.x + dx * kSnap, at.y + dy * kSnap), 0.0,
                                            first, t) ||
                              t >= dist * (1.0 - kVisibility);
                }
            if (!visible) {
                ++r.hidden;
                continue;
            }
            // N: the vertex normals interpolated at P (extrapolated a little past an edge where
            // P lies there, as a rasteriser does) of the nearest triangle or one sharing a vertex
            // with it that P is on (where two triangles fold, the one the rasteriser drew)
            double dn = glm::length(glm::dvec3(g.normal[p]) - geo.normalAt(prim, P));
            for (const uint32_t v : m.triangles[prim])
                for (const uint32_t other : around[v]) {
                    const double q3[3] = {P.x, P.y, P.z};
                    const std::array<double, 3> c = scene.closestPoint(other, q3);
                    const glm::dvec3 q(c[0], c[1], c[2]);
                    if (glm::length(geo.project(q) - at) > kSnap ||
                        std::fabs(glm::dot(P - q, geo.faceNormal(other))) > kDepthTolerance * dist)
                        continue;
                    dn =
                        std::min(dn, glm::length(glm::dvec3(g.normal[p]) - geo.normalAt(other, P)));
                }
            r.worstNormal = std::max(r.worstNormal, dn);
            r.wrongNormal += !(dn <= kNormalTolerance);
        }
    return r;
}

} // namespace render
