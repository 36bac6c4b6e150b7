// pathtrace/mesh_geometry: triangle meshes for the lit-mesh path tracer — OBJ loading
// (tinyobjloader, faces triangulated), normalisation to one unit on the longest axis (centred
// on the bounding box; the tracer multiplies by its scale, the mm of the longest axis), a
// procedural UV sphere, OBJ writing, and the checks a volumetric tracer needs: a closed
// (watertight), consistently wound, outward-oriented surface.
//   Topology (analyseTopology): vertices with bitwise-equal positions are welded first (OBJ
//   exporters split vertices at UV seams); every triangle contributes its three directed
//   edges. An undirected edge used once is a boundary edge (open mesh); used by two triangles
//   in the same direction, an inconsistent-winding edge (a flipped triangle shows as its three
//   edges); used more than twice, a non-manifold edge. The signed volume
//       V = (1/6) Σ_triangles v0 · (v1 × v2)
//   (divergence theorem) is > 0 when the counter-clockwise normals (v1 − v0) × (v2 − v0)
//   point outward, < 0 when the winding is inverted everywhere.
//   Errors are core::Error(name, 0, message), `name` the file (or the caller's label).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace pathtrace {

struct Mesh {
    std::vector<std::array<float, 3>> vertices;
    std::vector<std::array<uint32_t, 3>> triangles; // counter-clockwise seen from outside
};

// Loads the triangles of every shape of an OBJ file (polygons fan-triangulated), welds equal
// positions and drops triangles that repeat a vertex. Throws core::Error(path, line or 0, ...)
// when the file is missing or unreadable, a vertex line is malformed, a face is malformed or
// refers to a missing vertex, or there are no triangles. No normalisation, no topology check.
Mesh loadObj(const std::filesystem::path& path);
// Writes "v" and "f" lines (1-based); throws core::Error(path, 0, ...) when it cannot.
void writeObj(const std::filesystem::path& path, const Mesh& m);

// A closed UV sphere of radius 0.5 at the origin, counter-clockwise seen from outside: poles
// plus (rings − 1) latitude rings of `segments` vertices; rings >= 2, segments >= 3.
Mesh makeUvSphere(int rings, int segments);

struct MeshTopology {
    uint64_t edges = 0;             // undirected edges
    uint64_t boundaryEdges = 0;     // used by one triangle
    uint64_t inconsistentEdges = 0; // used twice in the same direction
    uint64_t nonManifoldEdges = 0;  // used by more than two triangles
    double signedVolume = 0;        // in the mesh's units³
};
MeshTopology analyseTopology(const Mesh& m);
// Throws core::Error(name, 0, ...) unless the mesh is closed, manifold, consistently wound and
// outward (signed volume > 0): "open mesh (not watertight): N boundary edges", "inconsistent
// winding: N edges are used twice in the same direction (flipped triangles)", "non-manifold:
// N edges are shared by more than two triangles", "mesh normals point inward (signed volume
// < 0): flip the winding". Also rejects empty meshes and non-finite vertices.
void checkClosedOutward(const Mesh& m, const std::string& name);

// Centres the bounding box at the origin and scales the longest axis to 1 (in place).
// Returns the original length of the longest axis (throws core::Error(name, 0, ...) when it is
// 0 or not finite).
double normalizeMesh(Mesh& m, const std::string& name);

// Welds bitwise-equal positions and drops triangles that repeat a vertex (in place).
void weldVertices(Mesh& m);

} // namespace pathtrace
