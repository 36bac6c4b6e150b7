// pathtrace/mesh_scene: the Embree scene (see mesh_scene.h).
#include "pathtrace/mesh_scene.h"

#include "core/core.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace pathtrace {
namespace {
std::string deviceError(RTCDevice d) {
    switch (rtcGetDeviceError(d)) {
    case RTC_ERROR_NONE:
        return "no error";
    case RTC_ERROR_INVALID_ARGUMENT:
        return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
        return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
        return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
        return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
        return "cancelled";
    default:
        return "unknown error";
    }
}
} // namespace

MeshScene::MeshScene(const Mesh& m) {
    m_device = rtcNewDevice(nullptr);
    if (!m_device)
        throw core::Error("embree", 0, "cannot create an Embree device: " + deviceError(nullptr));
    const size_t nv = m.vertices.size(), nt = m.triangles.size();
    RTCGeometry geom = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
    if (!vb || !ib) {
        const std::string e = deviceError(m_device);
        rtcReleaseGeometry(geom);
        rtcReleaseDevice(m_device);
        throw core::Error("embree", 0, "cannot allocate the mesh buffers: " + e);
    }
    m_vertices.resize(nv);
    for (size_t i = 0; i < nv; ++i) {
        std::memcpy(vb + 3 * i, m.vertices[i].data(), 3 * sizeof(float));
        m_vertices[i] = {m.vertices[i][0], m.vertices[i][1], m.vertices[i][2]};
    }
    m_triangles = m.triangles;
    m_normals.resize(nt);
    for (size_t i = 0; i < nt; ++i) {
        const auto& t = m.triangles[i];
        ib[3 * i] = t[0];
        ib[3 * i + 1] = t[1];
        ib[3 * i + 2] = t[2];
        const auto& a = m.vertices[t[0]];
        const auto& b = m.vertices[t[1]];
        const auto& c = m.vertices[t[2]];
        const double e1[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
        const double e2[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
        const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        m_normals[i] = len > 0 ? std::array<double, 3>{n[0] / len, n[1] / len, n[2] / len}
                               : std::array<double, 3>{0.0, 0.0, 0.0};
    }
    rtcCommitGeometry(geom);
    m_scene = rtcNewScene(m_device);
    rtcSetSceneFlags(m_scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_HIGH);
    rtcAttachGeometry(m_scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(m_scene);
    if (rtcGetDeviceError(m_device) != RTC_ERROR_NONE) {
        const std::string e = deviceError(m_device);
        rtcReleaseScene(m_scene);
        rtcReleaseDevice(m_device);
        throw core::Error("embree", 0, "cannot build the scene: " + e);
    }
}

MeshScene::~MeshScene() {
    if (m_scene) rtcReleaseScene(m_scene);
    if (m_device) rtcReleaseDevice(m_device);
}

bool MeshScene::intersect(const double org[3], const double dir[3], double tnear, double tfar,
                          double& t, uint32_t& prim) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(org[0]);
    rh.ray.org_y = static_cast<float>(org[1]);
    rh.ray.org_z = static_cast<float>(org[2]);
    rh.ray.dir_x = static_cast<float>(dir[0]);
    rh.ray.dir_y = static_cast<float>(dir[1]);
    rh.ray.dir_z = static_cast<float>(dir[2]);
    rh.ray.tnear = static_cast<float>(tnear);
    rh.ray.tfar = tfar < 1e30 ? static_cast<float>(tfar) : std::numeric_limits<float>::infinity();
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m_scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    t = rh.ray.tfar;
    prim = rh.hit.primID;
    return true;
}

std::array<double, 3> MeshScene::closestPoint(uint32_t prim, const double pt[3]) const {
    using V = std::array<double, 3>;
    auto sub = [](const V& x, const V& y) { return V{x[0] - y[0], x[1] - y[1], x[2] - y[2]}; };
    auto dot = [](const V& x, const V& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    auto along = [](const V& o, const V& d, double s) {
        return V{o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2]};
    };
    const auto& t = m_triangles[prim];
    const V a = m_vertices[t[0]], b = m_vertices[t[1]], c = m_vertices[t[2]];
    const V p{pt[0], pt[1], pt[2]};
    const V ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const V bp = sub(p, b);
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return along(a, ab, d1 / (d1 - d3));
    const V cp = sub(p, c);
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return along(a, ac, d2 / (d2 - d6));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return along(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const double den = 1.0 / (va + vb + vc);
    const V q = along(a, ab, vb * den);
    return along(q, ac, vc * den);
}

namespace {
struct NearestQuery {
    const MeshScene* scene;
    double p[3];
    double best2;
    uint32_t prim;
    std::array<double, 3> q;
};

bool nearestCallback(RTCPointQueryFunctionArguments* args) {
    auto* n = static_cast<NearestQuery*>(args->userPtr);
    const std::array<double, 3> q = n->scene->closestPoint(args->primID, n->p);
    const double d[3] = {q[0] - n->p[0], q[1] - n->p[1], q[2] - n->p[2]};
    const double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (!(d2 < n->best2)) return false;
    n->best2 = d2;
    n->prim = args->primID;
    n->q = q;
    args->query->radius = static_cast<float>(std::sqrt(d2)) * (1.0f + 1e-6f) + 1e-12f;
    return true; // the query's radius shrank
}
} // namespace

bool MeshScene::nearest(const double p[3], double radius, uint32_t& prim, double q[3]) const {
    NearestQuery n{this, {p[0], p[1], p[2]}, radius * radius, RTC_INVALID_GEOMETRY_ID, {}};
    RTCPointQuery query;
    query.x = static_cast<float>(p[0]);
    query.y = static_cast<float>(p[1]);
    query.z = static_cast<float>(p[2]);
    query.time = 0.0f;
    query.radius = static_cast<float>(radius);
    RTCPointQueryContext ctx;
    rtcInitPointQueryContext(&ctx);
    rtcPointQuery(m_scene, &query, &ctx, nearestCallback, &n);
    if (n.prim == RTC_INVALID_GEOMETRY_ID) return false;
    prim = n.prim;
    for (int k = 0; k < 3; ++k)
        q[k] = n.q[size_t(k)];
    return true;
}

} // namespace pathtrace
