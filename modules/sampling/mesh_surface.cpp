// sampling/mesh_surface: see mesh_surface.h.
#include "sampling/mesh_surface.h"

#include "core/core.h"

#include <embree3/rtcore.h>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace sampling {
namespace {

// The intersection context handed to the filter: Embree passes the pointer it was given,
// so the extra member travels with it (the context must come first).
struct CollectContext {
    RTCIntersectContext ctx;
    std::vector<uint32_t>* prims;
};

void collectAndReject(const RTCFilterFunctionNArguments* args) {
    auto* cc = reinterpret_cast<CollectContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        cc->prims->push_back(RTCHitN_primID(args->hit, args->N, i));
        args->valid[i] = 0; // reject: traversal continues past this triangle
    }
}

void throwEmbree(RTCDevice d, const std::string& what) {
    throw core::Error("embree", 0,
                      what + " (Embree error " + std::to_string(int(rtcGetDeviceError(d))) + ")");
}

} // namespace

MeshSurface::MeshSurface(const mesh::Mesh& m, double scale, const std::string& name) {
    if (m.triangles.empty()) throw core::Error(name, 0, "the mesh has no triangles");
    if (!(std::isfinite(scale) && scale > 0))
        throw core::Error(name, 0, "the scale must be finite and > 0");
    m_vertices.reserve(m.vertices.size());
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        const auto& v = m.vertices[i];
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
            throw core::Error(name, 0, "vertex " + std::to_string(i) + " is not finite");
        m_vertices.push_back(scale * glm::dvec3(v[0], v[1], v[2]));
    }
    m_tris = m.triangles;
    m_normals.resize(m_tris.size());
    m_cumArea.resize(m_tris.size());
    for (size_t i = 0; i < m_tris.size(); ++i) {
        const auto& t = m_tris[i];
        for (uint32_t k : t)
            if (k >= m_vertices.size())
                throw core::Error(name, 0,
                                  "triangle " + std::to_string(i) + " refers to a missing vertex");
        const glm::dvec3 c =
            glm::cross(m_vertices[t[1]] - m_vertices[t[0]], m_vertices[t[2]] - m_vertices[t[0]]);
        const double len = glm::length(c);
        m_normals[i] = len > 0 ? c / len : glm::dvec3(0.0);
        m_area += 0.5 * len;
        m_cumArea[i] = m_area;
    }
    if (!(m_area > 0)) throw core::Error(name, 0, "the mesh has no surface area");

    m_device = rtcNewDevice(nullptr);
    if (!m_device) throwEmbree(nullptr, "cannot create an Embree device");
    RTCGeometry geom = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m_vertices.size()));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m_tris.size()));
    if (!vb || !ib) {
        rtcReleaseGeometry(geom);
        rtcReleaseDevice(m_device);
        m_device = nullptr;
        throw core::Error("embree", 0, "cannot allocate the mesh buffers");
    }
    for (size_t i = 0; i < m_vertices.size(); ++i)
        for (int k = 0; k < 3; ++k)
            vb[3 * i + k] = static_cast<float>(m_vertices[i][k]);
    for (size_t i = 0; i < m_tris.size(); ++i)
        for (int k = 0; k < 3; ++k)
            ib[3 * i + k] = m_tris[i][k];
    rtcCommitGeometry(geom);
    m_scene = rtcNewScene(m_device);
    rtcSetSceneFlags(m_scene,
                     RTCSceneFlags(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION));
    rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_HIGH);
    rtcAttachGeometry(m_scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(m_scene);
    if (rtcGetDeviceError(m_device) != RTC_ERROR_NONE) {
        const RTCError e = rtcGetDeviceError(m_device);
        rtcReleaseScene(m_scene);
        rtcReleaseDevice(m_device);
        m_scene = nullptr;
        m_device = nullptr;
        throw core::Error("embree", 0,
                          "cannot build the scene (Embree error " + std::to_string(int(e)) + ")");
    }
}

MeshSurface::~MeshSurface() {
    if (m_scene) rtcReleaseScene(m_scene);
    if (m_device) rtcReleaseDevice(m_device);
}

void MeshSurface::intersectAll(const glm::dvec3& org, const glm::dvec3& dir, double tMin,
                               double tMax, std::vector<SurfaceHit>& out) const {
    if (!(tMax >= tMin)) return;
    thread_local std::vector<uint32_t> prims;
    prims.clear();
    CollectContext cc;
    rtcInitIntersectContext(&cc.ctx);
    cc.ctx.filter = collectAndReject;
    cc.prims = &prims;

    // Pad the float segment so that no hit within [tMin, tMax] in double is lost to rounding.
    const double pad = 8 * std::numeric_limits<float>::epsilon() *
                       (std::max(std::fabs(tMin), std::fabs(tMax)) + std::fabs(org.x) +
                        std::fabs(org.y) + std::fabs(org.z));
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(org.x);
    rh.ray.org_y = static_cast<float>(org.y);
    rh.ray.org_z = static_cast<float>(org.z);
    rh.ray.dir_x = static_cast<float>(dir.x);
    rh.ray.dir_y = static_cast<float>(dir.y);
    rh.ray.dir_z = static_cast<float>(dir.z);
    rh.ray.tnear = static_cast<float>(std::max(0.0, tMin - pad));
    rh.ray.tfar = static_cast<float>(tMax + pad);
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_scene, &cc.ctx, &rh);

    std::sort(prims.begin(), prims.end());
    prims.erase(std::unique(prims.begin(), prims.end()), prims.end());
    for (uint32_t prim : prims) {
        const glm::dvec3& n = m_normals[prim];
        const double denom = glm::dot(dir, n);
        if (denom == 0) continue; // parallel (or zero area): no point of area
        const double t = glm::dot(m_vertices[m_tris[prim][0]] - org, n) / denom;
        if (!(t >= tMin && t <= tMax)) continue;
        SurfaceHit h;
        h.t = t;
        h.point.x = org + t * dir;
        h.point.n = n;
        out.push_back(h);
    }
}

SurfacePoint MeshSurface::sampleArea(double u0, double u1, double u2) const {
    const double target = u0 * m_area;
    size_t i =
        size_t(std::upper_bound(m_cumArea.begin(), m_cumArea.end(), target) - m_cumArea.begin());
    i = std::min(i, m_tris.size() - 1);
    while (m_normals[i] == glm::dvec3(0.0) && i > 0) // rounding into a zero-area slot
        --i;
    const double su = std::sqrt(u1);
    const double b0 = 1 - su, b1 = su * (1 - u2), b2 = su * u2;
    const auto& t = m_tris[i];
    SurfacePoint p;
    p.x = b0 * m_vertices[t[0]] + b1 * m_vertices[t[1]] + b2 * m_vertices[t[2]];
    p.n = m_normals[i];
    return p;
}

} // namespace sampling
