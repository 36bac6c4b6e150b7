// mesh/suite: the geometry stress suite — canonical closed shapes on which diffusion models,
// derived for a flat semi-infinite medium, are known to fail (thin parts, edges, corners,
// cavities, small radii of curvature, coarse tessellation). Every length is in units of the
// medium's diffuse mean free path l_d = 1/√(3σa σt'), so one suite serves every medium and
// channel: a consumer multiplies by the channel's l_d in mm.
//   A shape is named by a spec "kind" or "kind:param=value,…" (values in l_d unless the table
//   says otherwise). Kinds, parameters and ranges (kSuiteKinds has the same table):
//     slab         t (thickness, 0.05–20, default 1), w (width, 1–100, default 20),
//                  view = front (lit from the camera side) | back (lit from behind: transmission)
//     edge         s (edge length of the square cross-section, 1–50, default 8): a 90° edge
//                  towards the camera, one face lit more than the other
//     corner       s (cube side, 1–50, default 8): a cube corner towards the camera
//     fin          t (fin thickness, 0.05–4, default 0.5), h (fin height, 0.5–20, default 5): a
//                  thin wall on a block, lit from one side
//     groove       r (radius of the half-cylinder groove, 0.2–2.8, default 2) in a 12 × 6 block
//     sphere       r (radius, 0.1–50, default 2), 48 rings × 96 segments
//     tessellation level (1–6, default 3): the sphere of radius 2 at (rings, segments) =
//                  (4,8) (6,12) (8,16) (12,24) (24,48) (48,96), coarse to fine
//   The canonical spec of a shape (its name, the cache key of its reference) lists every
//   parameter in the table's order with %g values: "slab:t=0.3,w=20,view=front".
//   Orientation: the camera looks along −z (orthographic, the lit-sphere picture of
//   pathtrace/camera.h); each shape is rotated so that the feature faces the camera, and carries
//   its light direction (towards the light, unit). The mesh is centred on its bounding box.
//   Flat faces keep split vertices with face normals (as mesh::makeBox); the spheres keep radial
//   vertex normals. Extruded profiles (fin, groove) are triangulated by ear clipping (written by
//   hand: a dozen lines, no Debian package triangulates a simple polygon for us).
//   Errors: core::Error(label, 0, …) naming the kind or the parameter, its value and its range.
#pragma once

#include "mesh/mesh.h"

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace mesh {

struct SuiteParam {
    const char* name;
    double lo, hi, dflt;
    const char* meaning;
};
struct SuiteKind {
    const char* name;
    const char* description;
    std::vector<SuiteParam> params; // numeric; slab's view is text (front | back)
};
const std::vector<SuiteKind>& suiteKinds();

struct SuiteShape {
    std::string spec;                                   // canonical
    std::string kind;                                   // slab, edge, …
    std::vector<std::pair<std::string, double>> params; // numeric, in the table's order
    std::string view;                                   // slab: front | back; else ""
    std::array<double, 3> light{0, 0, 1};               // towards the light, unit, camera frame
    Mesh mesh;                                          // l_d units, centred, in the camera frame
    double longestAxis = 0;                             // of the bounding box, l_d
};

// The shape of a spec (see above); `label` names the source in errors (e.g. "--shapes").
SuiteShape makeSuiteShape(const std::string& spec, const std::string& label);
// The default suite: slabs t = 0.1, 0.3, 1, 3, 10 seen from the front and from the back, the
// edge, the corner, the fin, the groove, spheres r = 0.5, 1, 2, 5, 20 and tessellation levels
// 1–6 (25 shapes), as canonical specs.
std::vector<std::string> defaultSuite();

// Ear-clipping triangulation of a simple polygon given counter-clockwise (indices into it,
// counter-clockwise triangles). Throws core::Error("polygon", 0, …) when it is not simple.
std::vector<std::array<uint32_t, 3>>
triangulatePolygon(const std::vector<std::array<double, 2>>& p);
// The prism of a counter-clockwise profile in the (y, z) plane extruded over x ∈ [−L/2, L/2]:
// closed, outward, flat face normals.
Mesh extrudeProfile(const std::vector<std::array<double, 2>>& profile, double length);

} // namespace mesh
