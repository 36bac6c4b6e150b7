// One irradiance::Stage per GL test binary (shaders compiled once), on the shared headless
// context.
#pragma once

#include "../support/gl_fixture.h"
#include "irradiance/irradiance.h"

#include <memory>

namespace irrtest {

inline irradiance::Stage& stage() {
    testsupport::context();
    static std::unique_ptr<irradiance::Stage> s =
        std::make_unique<irradiance::Stage>(testsupport::sourceRoot() / "shaders");
    return *s;
}

inline std::vector<glm::vec3> vertexPositions(const mesh::Mesh& m) {
    std::vector<glm::vec3> p;
    for (const auto& v : m.vertices)
        p.emplace_back(v[0], v[1], v[2]);
    return p;
}
inline std::vector<glm::vec3> vertexNormals(const mesh::Mesh& m) {
    std::vector<glm::vec3> n;
    for (const auto& v : m.normals)
        n.emplace_back(v[0], v[1], v[2]);
    return n;
}

} // namespace irrtest
