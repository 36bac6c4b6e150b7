// pathtrace/mesh_alias: the triangle meshes of the lit-mesh tracer come from modules/mesh
// (mesh/mesh.h); these names keep pathtrace code and its tests unqualified.
#pragma once

#include "mesh/mesh.h"

namespace pathtrace {
using mesh::analyseTopology;
using mesh::checkClosedOutward;
using mesh::loadObj;
using mesh::makeUvSphere;
using mesh::Mesh;
using mesh::MeshTopology;
using mesh::normalizeMesh;
using mesh::weldVertices;
using mesh::writeObj;
} // namespace pathtrace
