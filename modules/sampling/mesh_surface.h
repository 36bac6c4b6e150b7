// sampling/mesh_surface: a closed triangle mesh as probe target and area sampler (see
// surface.h), for King et al. 2013's probe rays on meshes.
//   Every hit along a segment: one Embree 3 traversal (rtcIntersect1) whose intersection-
//   context filter records each candidate triangle and rejects it, so traversal goes on to the
//   end of the segment and reports every triangle it crosses, with no re-launching and hence
//   no ε offset that could skip two close surfaces or find one twice. A spatial-split BVH may
//   report a triangle more than once, so triangles are de-duplicated; the distance is then
//   recomputed in double from the triangle's plane (t = (v0 − org)·n / (dir·n)), and hits with
//   t outside [tMin, tMax] in double are dropped (the Embree segment is padded by a few float
//   ulps so that none is lost to float rounding). Watertight ("robust") intersection: no ray
//   slips through a shared edge; one that passes exactly through an edge may be reported by
//   both triangles (a set of rays of measure zero). Triangles of zero area are never hit.
//   pathtrace::MeshScene answers first hits only, and pathtrace links GL; this module stays
//   free of both, so it keeps its own small scene.
//   Uniform area sampling: a triangle with probability ∝ its area (binary search in the
//   cumulative areas), then a uniform point by the square-root warp
//   (1 − √u1, √u1·(1 − u2), √u1·u2).
//   Errors: core::Error("embree", 0, …) when Embree fails, core::Error(name, 0, …) for an
//   empty mesh, a non-finite vertex or no area.
#pragma once

#include "mesh/mesh.h"
#include "sampling/surface.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

struct RTCDeviceTy;
struct RTCSceneTy;

namespace sampling {

class MeshSurface final : public Surface, public AreaSampler {
  public:
    explicit MeshSurface(const mesh::Mesh& m, double scale = 1.0, const std::string& name = "mesh");
    ~MeshSurface() override;
    MeshSurface(const MeshSurface&) = delete;
    MeshSurface& operator=(const MeshSurface&) = delete;

    void intersectAll(const glm::dvec3& org, const glm::dvec3& dir, double tMin, double tMax,
                      std::vector<SurfaceHit>& out) const override;
    double area() const override { return m_area; }
    SurfacePoint sampleArea(double u0, double u1, double u2) const override;

    size_t triangleCount() const { return m_tris.size(); }
    const glm::dvec3& faceNormal(size_t tri) const { return m_normals[tri]; }

  private:
    RTCDeviceTy* m_device = nullptr;
    RTCSceneTy* m_scene = nullptr;
    std::vector<glm::dvec3> m_vertices; // scaled, double
    std::vector<std::array<uint32_t, 3>> m_tris;
    std::vector<glm::dvec3> m_normals; // unit, (v1 − v0) × (v2 − v0); 0 for zero area
    std::vector<double> m_cumArea;
    double m_area = 0;
};

} // namespace sampling
