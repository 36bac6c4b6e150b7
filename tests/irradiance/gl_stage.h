// One irradiance::Stage per GL test binary (shaders compiled once), on the shared headless
// context; points on the bunny.
#pragma once

#include "../support/gl_fixture.h"
#include "irradiance/irradiance.h"
#include "mesh/mesh.h"

#include <glm/geometric.hpp>

#include <cstdint>
#include <memory>
#include <vector>

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

// The bunny (third_party/bunny/bunny.obj, prepared as the scene prepares it) with a point at
// each triangle's centroid and its face normal.
struct PointsOnMesh {
    mesh::Mesh mesh;
    std::vector<glm::vec3> P, N;
};
inline PointsOnMesh bunnyPoints() {
    PointsOnMesh s;
    s.mesh = mesh::loadObj(testsupport::sourceRoot() / "third_party" / "bunny" / "bunny.obj");
    mesh::prepareRenderable(s.mesh, "bunny");
    auto at = [&](uint32_t k) {
        return glm::vec3(s.mesh.vertices[k][0], s.mesh.vertices[k][1], s.mesh.vertices[k][2]);
    };
    for (const auto& t : s.mesh.triangles) {
        const glm::vec3 a = at(t[0]), b = at(t[1]), c = at(t[2]);
        const glm::vec3 n = glm::cross(b - a, c - a);
        if (glm::length(n) == 0.0f) continue;
        s.P.push_back((a + b + c) / 3.0f);
        s.N.push_back(glm::normalize(n));
    }
    return s;
}

} // namespace irrtest
