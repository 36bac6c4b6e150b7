// render/raster_rule: whether a G-buffer is a rasterisation of a mesh by a camera as OpenGL 4.5
// allows one (§14.6: a fragment's attributes are interpolated at its sample point, the pixel
// centre, from the window coordinates of the vertices, whose sub-pixel precision —
// GL_SUBPIXEL_BITS, at least 4 — and rounding are the implementation's). Two conforming drivers
// place each pixel's sample a fraction of a pixel apart (an NVIDIA H200 and llvmpipe: ~0.04 px
// on the bunny scene), which changes a surface point by up to its whole difference across an
// occluding edge; so a G-buffer is checked against the geometry, not against another driver's:
// an independent ray caster (Embree, pathtrace::MeshScene) on the CPU in double, per pixel:
//   - covered pixel, surface point P:
//       off centre:   P projects farther than kRasterShift px from the pixel's centre (either
//                     axis) through the camera's view-projection;
//       off surface:  P is not on the mesh: the triangle nearest to it (Embree's point query)
//                     has no point q within kSnap px of P in the image with P on its plane
//                     (|(P − q)·n| within kDepthTolerance of P's distance from the camera);
//                     kSnap is GL's coarsest vertex grid: a rasteriser may extend a triangle that
//                     far past its edge;
//       hidden:       every ray through P's projection and the eight points kSnap px around it
//                     meets the mesh nearer than (1 − kVisibility) of P's distance (the depth
//                     test kept a surface behind another);
//       wrong normal: N differs by more than kNormalTolerance from the vertex normals
//                     interpolated at P (barycentric coordinates on the triangle's plane,
//                     extrapolated where P lies just past its edge, normalised as
//                     render_gbuffer.frag does) of that triangle and of every triangle sharing a
//                     vertex with it that P is on (where two fold, the one drawn);
//   - uncovered pixel: the mesh covers the pixel's centre and every point kRasterShift px from it
//     along both axes and diagonals ("uncovered inside").
// Counts of each; a conforming rasterisation of the same mesh and camera has none (tests: the
// renderer's own, drawn with its samples moved by up to 0.2 px, and with each vertex snapped on
// its own to GL's coarsest grid, gl/vertex_snap.h). A camera ½ px off, normals
// tilted by 0.02 rad, a mesh 1 % larger, the surface behind or a hole make many.
// Rays start at the camera, not at the near plane (the scene's camera frames the mesh whole).
#pragma once

#include "mesh/mesh.h"
#include "render/camera.h"
#include "render/render.h"

#include <cstddef>
#include <memory>

namespace render {

// The sample point's freedom, in pixels: 8× the coarsest vertex snapping GL allows (1/32 px
// when rounding to a 1/16 px grid).
inline constexpr double kRasterShift = 0.25;
// GL's coarsest sub-pixel grid (GL_SUBPIXEL_BITS = 4), px.
inline constexpr double kSnap = 1.0 / 16.0;
// Float32 interpolation of coordinates of order one (relative to the distance from the camera;
// llvmpipe's own G-buffers stay within 1e-6), and of unit normals (within 1e-4).
inline constexpr double kDepthTolerance = 1e-4;
// Surfaces this close in front (relative to the distance) may lose the depth test.
inline constexpr double kVisibility = 1e-3;
inline constexpr double kNormalTolerance = 1e-3;

struct RasterCheck {
    size_t pixels = 0, covered = 0;
    size_t offCentre = 0, offSurface = 0, hidden = 0, wrongNormal = 0, uncoveredInside = 0;
    // The largest residuals over the covered pixels (px; distance from the plane relative to the
    // distance from the camera; normal difference).
    double worstOffCentre = 0, worstDepth = 0, worstNormal = 0;
    size_t failures() const {
        return offCentre + offSurface + hidden + wrongNormal + uncoveredInside;
    }
};

// The rule for one mesh: its ray caster and the triangles around each vertex, built once for
// every G-buffer checked against it (a scene capture checks two).
class RasterRule {
  public:
    // `m` with normals computed as the renderer does when it has none; core::Error for a mesh
    // without triangles.
    explicit RasterRule(const mesh::Mesh& m);
    ~RasterRule();
    RasterRule(const RasterRule&) = delete;
    RasterRule& operator=(const RasterRule&) = delete;

    // `g` against the mesh seen by `camera` (its aspect replaced by g.width / g.height) under
    // the renderer's image conventions (render.h: row 0 at the top). core::Error for an empty
    // G-buffer.
    RasterCheck check(const Gbuffer& g, const Camera& camera) const;

  private:
    struct Prepared;
    std::unique_ptr<Prepared> m_prepared;
};

// RasterRule(m).check(g, camera), for a single G-buffer.
RasterCheck checkRasterisation(const Gbuffer& g, const mesh::Mesh& m, const Camera& camera);

} // namespace render
