// Fuzzes OBJ loading (mesh::loadObj, tinyobjloader underneath) and the preparation of a loaded
// mesh for rendering (prepareRenderable: degenerate triangles, normalisation, normals) plus the
// topology analysis. Point-cloud generation is not part of it.
#include "fuzz_common.h"

#include "mesh/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput(data, size, "mesh.obj");
    fuzz::expectCleanError([&] {
        mesh::Mesh m = mesh::loadObj(path);
        (void)mesh::analyseTopology(m);
        (void)mesh::prepareRenderable(m, "mesh.obj");
    });
    return 0;
}
