// mesh/shapes: procedural closed, outward meshes for tests and demos (see mesh.h).
#include "mesh/mesh.h"

#include "core/core.h"

#include <cmath>
#include <numbers>

namespace mesh {

Mesh makeUvSphere(int rings, int segments) {
    if (rings < 2 || segments < 3)
        throw core::Error("uv sphere", 0,
                          "needs rings >= 2 and segments >= 3, got " + std::to_string(rings) +
                              " x " + std::to_string(segments));
    Mesh m;
    const double r = 0.5;
    m.vertices.push_back({0.0f, 0.0f, static_cast<float>(r)}); // north pole (index 0)
    m.normals.push_back({0.0f, 0.0f, 1.0f});
    for (int i = 1; i < rings; ++i) {
        const double theta = std::numbers::pi * i / rings;
        for (int j = 0; j < segments; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / segments;
            const double n[3] = {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                 std::cos(theta)};
            m.vertices.push_back({static_cast<float>(r * n[0]), static_cast<float>(r * n[1]),
                                  static_cast<float>(r * n[2])});
            m.normals.push_back(
                {static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2])});
        }
    }
    const uint32_t south = static_cast<uint32_t>(m.vertices.size());
    m.vertices.push_back({0.0f, 0.0f, static_cast<float>(-r)});
    m.normals.push_back({0.0f, 0.0f, -1.0f});
    auto ring = [&](int i, int j) { // vertex j of ring i (1 <= i < rings)
        return static_cast<uint32_t>(1 + (i - 1) * segments + (j % segments));
    };
    for (int j = 0; j < segments; ++j) {
        m.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
        for (int i = 1; i + 1 < rings; ++i) {
            m.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
            m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
        m.triangles.push_back({ring(rings - 1, j), south, ring(rings - 1, j + 1)});
    }
    return m;
}

Mesh makeBox(double sx, double sy, double sz) {
    if (!(sx > 0 && sy > 0 && sz > 0) || !std::isfinite(sx) || !std::isfinite(sy) ||
        !std::isfinite(sz))
        throw core::Error("box", 0, "needs finite sizes > 0");
    const double h[3] = {0.5 * sx, 0.5 * sy, 0.5 * sz};
    // Per face: the normal axis and sign, and tangent axes u, v with u × v = n.
    struct Face {
        int n;
        double sign;
        int u, v;
    };
    const Face faces[6] = {{0, +1, 1, 2}, {0, -1, 2, 1}, {1, +1, 2, 0},
                           {1, -1, 0, 2}, {2, +1, 0, 1}, {2, -1, 1, 0}};
    const double corner[4][2] = {{-1, -1}, {+1, -1}, {+1, +1}, {-1, +1}}; // counter-clockwise
    Mesh m;
    for (const Face& f : faces) {
        const auto base = static_cast<uint32_t>(m.vertices.size());
        std::array<float, 3> normal{0.0f, 0.0f, 0.0f};
        normal[static_cast<size_t>(f.n)] = static_cast<float>(f.sign);
        for (const auto& c : corner) {
            double p[3];
            p[f.n] = f.sign * h[f.n];
            p[f.u] = c[0] * h[f.u];
            p[f.v] = c[1] * h[f.v];
            m.vertices.push_back(
                {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])});
            m.normals.push_back(normal);
            m.uvs.push_back(
                {static_cast<float>(0.5 * (c[0] + 1)), static_cast<float>(0.5 * (c[1] + 1))});
        }
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base, base + 2, base + 3});
    }
    return m;
}

Mesh makeTorus(double major, double minor, int majorSegments, int minorSegments) {
    if (!(minor > 0 && minor < major) || !std::isfinite(major) || majorSegments < 3 ||
        minorSegments < 3)
        throw core::Error("torus", 0,
                          "needs 0 < minor < major and at least 3 x 3 segments, got major " +
                              std::to_string(major) + ", minor " + std::to_string(minor) + ", " +
                              std::to_string(majorSegments) + " x " +
                              std::to_string(minorSegments));
    Mesh m;
    for (int i = 0; i < majorSegments; ++i) {
        const double phi = 2.0 * std::numbers::pi * i / majorSegments;
        for (int j = 0; j < minorSegments; ++j) {
            const double theta = 2.0 * std::numbers::pi * j / minorSegments;
            const double n[3] = {std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi),
                                 std::sin(theta)};
            m.vertices.push_back({static_cast<float>(major * std::cos(phi) + minor * n[0]),
                                  static_cast<float>(major * std::sin(phi) + minor * n[1]),
                                  static_cast<float>(minor * n[2])});
            m.normals.push_back(
                {static_cast<float>(n[0]), static_cast<float>(n[1]), static_cast<float>(n[2])});
        }
    }
    auto at = [&](int i, int j) {
        return static_cast<uint32_t>((i % majorSegments) * minorSegments + (j % minorSegments));
    };
    // ∂p/∂φ × ∂p/∂θ points outward: (i, j) → (i+1, j) → (i+1, j+1) → (i, j+1) is
    // counter-clockwise seen from outside.
    for (int i = 0; i < majorSegments; ++i)
        for (int j = 0; j < minorSegments; ++j) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return m;
}

Mesh makeThinPlate(double width, double depth, double thickness) {
    if (!(thickness > 0)) throw core::Error("thin plate", 0, "needs a thickness > 0");
    return makeBox(width, depth, thickness);
}

} // namespace mesh
