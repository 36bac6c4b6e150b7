// One irradiance::Stage per GL test binary (shaders compiled once), on the shared headless
// context; the bunny with a light frame that holds still while its vertices move.
#pragma once

#include "../support/gl_fixture.h"
#include "irradiance/irradiance.h"
#include "irradiance/light_frame.h"
#include "mesh/mesh.h"

#include <glm/geometric.hpp>

#include <cstdint>
#include <cstring>
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
// each triangle's centroid (its face normal), plus six points 1.05 bounding radii from the
// centre along the axes: they hold every light frame's bounding sphere (light_frame.h) fixed
// when the vertices move by a fraction of a texel (movedVertices).
struct PointsOnMesh {
    mesh::Mesh mesh;
    std::vector<glm::vec3> P, N;
};
inline PointsOnMesh bunnyWithFixedFrame() {
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
    const irradiance::BoundingSphere b = irradiance::boundingSphere(s.mesh, s.P);
    for (int axis = 0; axis < 3; ++axis)
        for (const float side : {-1.0f, 1.0f}) {
            glm::vec3 q = b.centre;
            q[axis] += side * 1.05f * b.radius;
            s.P.push_back(q);
            s.N.emplace_back(0.0f, 1.0f, 0.0f);
        }
    return s;
}

// `m` with every vertex moved by move(r), r() a uniform number in [-1, 1) drawn from a hash of
// the vertex's position and `seed`: vertices at one position move alike, as a rasteriser snaps
// a shared vertex once, and each position moves on its own.
template <class Move> mesh::Mesh movedVertices(const mesh::Mesh& m, uint32_t seed, Move move) {
    mesh::Mesh out = m;
    for (auto& p : out.vertices) {
        uint32_t h = seed * 0x9E3779B9u;
        for (const float x : p) {
            uint32_t bits = 0;
            std::memcpy(&bits, &x, sizeof bits);
            h = (h ^ bits) * 0x85EBCA6Bu;
            h ^= h >> 13;
        }
        auto r = [&h] {
            h = h * 1664525u + 1013904223u;
            return static_cast<float>(h >> 8) / 8388608.0f - 1.0f;
        };
        const glm::vec3 d = move(r);
        for (int k = 0; k < 3; ++k)
            p[k] += d[k];
    }
    return out;
}

} // namespace irrtest
