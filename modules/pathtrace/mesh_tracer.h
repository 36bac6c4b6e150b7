// pathtrace/mesh_tracer: the path-traced lit mesh, CPU, Embree 3 (thesis 3.2 on a mesh, the
// picture of lit_sphere.h): the same light, camera, pixel value and estimator as the lit
// sphere (sphere_tracer.h, camera.h), the same walk (sphere_walk.h) against the mesh.
//   Geometry: the mesh is checked (closed, manifold, consistently wound, outward:
//   checkClosedOutward) and normalised to one unit on its longest axis, centred on its
//   bounding box; the tracer works in these units with σ·scale, scale = 2·radiusMm of the
//   setup = the mm of the longest axis (a sphere mesh is then the lit sphere of radius
//   radiusMm). The camera's image spans ±1.1·radiusMm (±0.55 units).
//   Inside/outside: from the face normals (outward for counter-clockwise winding): a flight
//   leaves through a face with u·n > 0; finding u·n <= 0 means the path is outside (a
//   numerical leak): it ends, its weight tallied as `leaked` (ChannelStats::leaks counts them).
//   After an internal reflection the walk restarts ε = clamp(0.01 mfp, 2e-6, 1e-5) units inside
//   along the normal (Embree's float precision is about 1e-7 units), and a collision that
//   would land within ε of the surface is pulled back to ε inside (a flight is tested against
//   the surface up to s + ε); without this, a path could start from a point that float rays
//   cannot tell from the surface and slip out (the leaks counted in ChannelStats::leaks, 0 in
//   the tests). The bias is O(ε/mfp) on the near-surface collision density.
//   Source: entry points are sampled uniformly on the rectangle that bounds the mesh's
//   projection on the plane perpendicular to the light (area A_src), each path carrying A_src/N;
//   the entry ray's first hit (if any) gets Fresnel as on the sphere (specular tallied and
//   dropped, refraction with 1 − F). Paths that miss count in N with nothing; so does an entry
//   ray whose first hit faces away from the light (it grazes a silhouette edge, where float
//   rounding can order the back face first; at cos θi ≈ 0, F ≈ 1 there anyway).
//   Pixels: covered iff the pixel-centre camera ray hits the mesh; footprint A_pix = Σ over a
//   k×k grid of subsample camera rays (k = TraceOptions::footprintSubsamples, at the centres of
//   the k×k sub-squares) that hit of (pixel area/k²)/|n·z| (n the hit face's normal: exact per
//   flat face, converging as k grows; silhouette pixels are the least accurate).
//   Exit → pixel: an exit point xo contributes to the pixel its (x, y) projection falls into
//   only if it is the camera-visible first hit of that pixel's camera ray through (xo.x, xo.y):
//   the ray from z = 1 along −z must hit a face with n·z > 0 at |z_hit − xo.z| < 1e-4 units.
//   Path count: N = samplesPerPixel × covered pixels.
#pragma once

#include "pathtrace/camera.h"
#include "pathtrace/lit_sphere.h"
#include "pathtrace/mesh_alias.h"
#include "pathtrace/pathtrace.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace pathtrace {

class MeshScene;

class LitMesh {
  public:
    // Checks the mesh (checkClosedOutward: core::Error(name, 0, ...)), normalises a copy and
    // builds its Embree scene.
    LitMesh(Mesh mesh, std::string name);
    ~LitMesh();
    LitMesh(LitMesh&&) noexcept;
    LitMesh& operator=(LitMesh&&) noexcept;

    const Mesh& mesh() const { return m_mesh; } // normalised
    const std::string& name() const { return m_name; }
    double originalExtent() const { return m_extent; } // longest axis in the file's units

    // Paths per channel: samplesPerPixel × covered pixels (validates the setup).
    uint64_t pathCount(const LitSphereSetup& s, const TraceOptions& o = {}) const;
    // Footprints (mm²) and n·lightDir at the centre ray's hit (0 where it misses).
    PixelGeometry footprints(const LitSphereSetup& s, const TraceOptions& o = {}) const;
    // The RGB exitance image; contract as traceLitSphere.
    Image trace(const std::array<Medium, 3>& media, const LitSphereSetup& setup,
                const std::function<void(uint64_t done)>& progress = {},
                const std::atomic<bool>* cancel = nullptr, const TraceOptions& options = {},
                ImageStats* stats = nullptr) const;

  private:
    // In normalised units², cached for the last (width, height, light, subsamples).
    PixelGeometry footprintsUnits(const LitSphereSetup& s, const TraceOptions& o) const;
    struct FootprintCache;
    Mesh m_mesh;
    std::string m_name;
    double m_extent = 0;
    std::unique_ptr<MeshScene> m_scene;
    std::unique_ptr<FootprintCache> m_cache;
};

// loadObj + LitMesh (errors name the file).
LitMesh loadLitMesh(const std::filesystem::path& path);

inline Image traceLitMesh(const LitMesh& mesh, const std::array<Medium, 3>& media,
                          const LitSphereSetup& setup,
                          const std::function<void(uint64_t done)>& progress = {},
                          const std::atomic<bool>* cancel = nullptr,
                          const TraceOptions& options = {}, ImageStats* stats = nullptr) {
    return mesh.trace(media, setup, progress, cancel, options, stats);
}

} // namespace pathtrace
