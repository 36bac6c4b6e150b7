// mesh: triangle meshes — OBJ loading (tinyobjloader, faces triangulated), normalisation to one
// unit on the longest axis (centred on the bounding box; a consumer multiplies by its scale,
// the mm of the longest axis), procedural shapes (UV sphere, box with sharp edges, torus, thin
// plate), OBJ writing, and the checks a volumetric tracer needs: a closed (watertight),
// consistently wound, outward-oriented surface.
//   Vertices: positions, plus per-vertex normals (always filled by loadObj and the shapes:
//   kept from the OBJ when every face corner has one, otherwise computed area-weighted) and
//   per-vertex UVs (kept when every face corner of the OBJ has one, else empty). A vertex is a
//   (position, normal, UV) triple, so a sharp edge or a UV seam splits it: topology is
//   therefore analysed on positions (see below), never on vertex indices.
//   Topology (analyseTopology): vertices with bitwise-equal positions count as one; every
//   triangle contributes its three directed edges. An undirected edge used once is a boundary
//   edge (open mesh); used by two triangles in the same direction, an inconsistent-winding edge
//   (a flipped triangle shows as its three edges); used more than twice, a non-manifold edge.
//   The signed volume
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

namespace mesh {

struct Mesh {
    std::vector<std::array<float, 3>> vertices;
    std::vector<std::array<uint32_t, 3>> triangles; // counter-clockwise seen from outside
    std::vector<std::array<float, 3>> normals;      // per vertex, unit; empty or vertices.size()
    std::vector<std::array<float, 2>> uvs;          // per vertex; empty or vertices.size()
};

// Loads the triangles of every shape of an OBJ file (polygons fan-triangulated), welds equal
// vertices (position, and normal/UV when present) and drops triangles that repeat a vertex.
// Normals are kept when every face corner has a "vn" (normalised), else computed area-weighted
// from the faces; UVs are kept when every face corner has a "vt", else left empty. Throws
// core::Error(path, line or 0, ...) when the file is missing or unreadable, a vertex line is
// malformed, a face is malformed or refers to a missing vertex, or there are no triangles.
// No normalisation, no topology check.
Mesh loadObj(const std::filesystem::path& path);
// Writes "v" (and "vt", "vn" when present) and "f" lines (1-based); throws
// core::Error(path, 0, ...) when it cannot.
void writeObj(const std::filesystem::path& path, const Mesh& m);

// Area-weighted vertex normals: each vertex gets the normalised sum of the unnormalised face
// normals (v1 − v0) × (v2 − v0) of its triangles (a vertex in no triangle gets (0, 0, 1)).
void computeVertexNormals(Mesh& m);

// Procedural shapes, closed, consistently wound counter-clockwise seen from outside, centred at
// the origin, with normals.
// A UV sphere of radius 0.5: poles plus (rings − 1) latitude rings of `segments` vertices;
// rings >= 2, segments >= 3; normals radial, no UVs.
Mesh makeUvSphere(int rings, int segments);
// An axis-aligned box of size sx × sy × sz with sharp edges: 24 vertices (4 per face), flat
// face normals, per-face UVs over [0, 1]². Sizes must be > 0 and finite.
Mesh makeBox(double sx, double sy, double sz);
// A torus around the z axis: ring radius `major`, tube radius `minor` (0 < minor < major),
// majorSegments >= 3 around z, minorSegments >= 3 around the tube; normals from the tube
// centre, no UVs. Analytic volume 2π²·major·minor².
Mesh makeTorus(double major, double minor, int majorSegments, int minorSegments);
// A thin plate: a makeBox of width × depth in x, y and `thickness` in z (thickness > 0).
Mesh makeThinPlate(double width, double depth, double thickness);

struct MeshTopology {
    uint64_t edges = 0;             // undirected edges (between welded positions)
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

// Centres the bounding box at the origin and scales the longest axis to 1 (in place; normals
// unchanged). Returns the original length of the longest axis (throws core::Error(name, 0, ...)
// when it is 0 or not finite).
double normalizeMesh(Mesh& m, const std::string& name);

// Prepares a loaded mesh for the point-cloud pipeline (thesis 3.3): rejects non-finite vertex
// coordinates ("vertex K has a non-finite coordinate"), drops triangles of zero area (returns
// how many; the caller reports them), rejects a mesh left with no area ("the mesh has no
// surface area"), then normalises it (normalizeMesh). Errors are core::Error(name, 0, ...).
struct RenderablePrep {
    size_t droppedDegenerate = 0;
    double originalLongestAxis = 0;
};
RenderablePrep prepareRenderable(Mesh& m, const std::string& name);

// Welds bitwise-equal vertices (position, and normal/UV when present) and drops triangles that
// repeat a vertex (in place).
void weldVertices(Mesh& m);

} // namespace mesh
