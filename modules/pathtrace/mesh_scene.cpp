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
    for (size_t i = 0; i < nv; ++i)
        std::memcpy(vb + 3 * i, m.vertices[i].data(), 3 * sizeof(float));
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

} // namespace pathtrace
