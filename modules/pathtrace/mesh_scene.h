// pathtrace/mesh_scene: an Embree 3 scene of one triangle mesh for the lit-mesh tracer.
//   Built once (RTC_BUILD_QUALITY_HIGH, RTC_SCENE_FLAG_ROBUST: Embree's watertight
//   intersection, so rays do not slip through shared edges), queried with rtcIntersect1 from
//   any thread. Face normals are computed here in double from the mesh's own vertices,
//   (v1 − v0) × (v2 − v0) normalised (outward for counter-clockwise winding), so inside and
//   outside never depend on Embree's normal convention. Nearest-triangle queries
//   (rtcPointQuery) take the closest point on a triangle from Ericson, Real-Time Collision
//   Detection §5.1.5, in double.
#pragma once

#include "pathtrace/mesh_alias.h"

#include <array>
#include <cstdint>
#include <vector>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace pathtrace {

class MeshScene {
  public:
    // Throws core::Error("embree", 0, ...) when Embree fails (the mesh is not checked here).
    explicit MeshScene(const Mesh& m);
    ~MeshScene();
    MeshScene(const MeshScene&) = delete;
    MeshScene& operator=(const MeshScene&) = delete;

    // First hit of org + t·dir for t in [tnear, tfar] (float precision inside Embree): true
    // with its distance and triangle.
    bool intersect(const double org[3], const double dir[3], double tnear, double tfar, double& t,
                   uint32_t& prim) const;
    const std::array<double, 3>& normal(uint32_t prim) const { return m_normals[prim]; }
    // The triangle nearest to p within `radius` (Embree's point query) and its point q closest
    // to p (in double): false when no triangle is that near.
    bool nearest(const double p[3], double radius, uint32_t& prim, double q[3]) const;
    // The point of triangle `prim` closest to p (in double).
    std::array<double, 3> closestPoint(uint32_t prim, const double p[3]) const;

  private:
    std::vector<std::array<double, 3>> m_vertices;
    std::vector<std::array<uint32_t, 3>> m_triangles;
    RTCDeviceTy* m_device = nullptr;
    RTCSceneTy* m_scene = nullptr;
    std::vector<std::array<double, 3>> m_normals;
};

} // namespace pathtrace
