// mesh shapes: the UV sphere, the box with sharp edges, the torus and the thin plate are
// closed, manifold, consistently wound and outward, with unit normals, and enclose their
// analytic volume (box and plate exactly, sphere and torus within the tessellation error).
#include "core/core.h"
#include "mesh/mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace mesh;

namespace {

void expectClosedOutward(const Mesh& m, const std::string& name) {
    const MeshTopology t = analyseTopology(m);
    EXPECT_EQ(t.boundaryEdges, 0u) << name;
    EXPECT_EQ(t.inconsistentEdges, 0u) << name;
    EXPECT_EQ(t.nonManifoldEdges, 0u) << name;
    EXPECT_GT(t.signedVolume, 0.0) << name;
    EXPECT_NO_THROW(checkClosedOutward(m, name));
    ASSERT_EQ(m.normals.size(), m.vertices.size()) << name;
    for (const auto& n : m.normals)
        EXPECT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-6) << name;
    // Every vertex normal points away from the face it belongs to's inside: n · face normal > 0.
    for (const auto& tri : m.triangles) {
        const auto &p = m.vertices[tri[0]], &q = m.vertices[tri[1]], &r = m.vertices[tri[2]];
        const double e1[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        const double e2[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
        const double f[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                             e1[0] * e2[1] - e1[1] * e2[0]};
        for (uint32_t v : tri)
            EXPECT_GT(f[0] * m.normals[v][0] + f[1] * m.normals[v][1] + f[2] * m.normals[v][2], 0.0)
                << name;
    }
}

} // namespace

TEST(Shapes, UvSphere) {
    const Mesh m = makeUvSphere(64, 128);
    expectClosedOutward(m, "sphere");
    const double ball = 4.0 / 3.0 * std::numbers::pi * 0.125;
    const double v = analyseTopology(m).signedVolume;
    EXPECT_LT(v, ball); // inscribed
    EXPECT_GT(v, 0.995 * ball);
    EXPECT_TRUE(m.uvs.empty());
    EXPECT_THROW(makeUvSphere(1, 8), core::Error);
}

TEST(Shapes, BoxWithSharpEdges) {
    const Mesh m = makeBox(1.0, 2.0, 0.5);
    ASSERT_EQ(m.vertices.size(), 24u);
    ASSERT_EQ(m.triangles.size(), 12u);
    ASSERT_EQ(m.uvs.size(), 24u);
    expectClosedOutward(m, "box");
    EXPECT_EQ(analyseTopology(m).signedVolume, 1.0); // exact
    // Flat normals: each face's 4 vertices share the axis normal, pointing away from the centre.
    for (size_t i = 0; i < 24; ++i) {
        int axis = -1;
        for (int a = 0; a < 3; ++a)
            if (m.normals[i][a] != 0.0f) {
                EXPECT_EQ(axis, -1);
                axis = a;
            }
        ASSERT_GE(axis, 0);
        EXPECT_EQ(std::fabs(m.normals[i][axis]), 1.0f);
        EXPECT_GT(m.normals[i][axis] * m.vertices[i][axis], 0.0f);
        EXPECT_EQ(m.normals[i / 4 * 4], m.normals[i]);
    }
    EXPECT_THROW(makeBox(1, 0, 1), core::Error);
}

TEST(Shapes, Torus) {
    const double R = 0.35, r = 0.15;
    const Mesh m = makeTorus(R, r, 128, 64);
    EXPECT_EQ(m.vertices.size(), 128u * 64u);
    expectClosedOutward(m, "torus");
    const double exact = 2.0 * std::numbers::pi * std::numbers::pi * R * r * r;
    const double v = analyseTopology(m).signedVolume;
    EXPECT_LT(v, exact); // inscribed
    EXPECT_GT(v, 0.995 * exact);
    // Euler characteristic 0 (genus 1).
    const MeshTopology t = analyseTopology(m);
    EXPECT_EQ(int64_t(m.vertices.size()) - int64_t(t.edges) + int64_t(m.triangles.size()), 0);
    EXPECT_THROW(makeTorus(0.1, 0.2, 16, 8), core::Error);
}

TEST(Shapes, ThinPlate) {
    const Mesh m = makeThinPlate(1.0, 0.8, 0.01);
    ASSERT_EQ(m.vertices.size(), 24u);
    expectClosedOutward(m, "plate");
    EXPECT_NEAR(analyseTopology(m).signedVolume, 0.008, 1e-8); // float sizes
    Mesh n = m;
    EXPECT_DOUBLE_EQ(normalizeMesh(n, "plate"), 1.0);
    EXPECT_THROW(makeThinPlate(1, 1, 0), core::Error);
}
