// mesh geometry: the UV sphere is closed and outward, OBJ write/read round trip, welding of
// split vertices, normalisation, normals (kept or computed area-weighted) and UVs, and (d4) the
// errors: inward normals, one flipped triangle (inconsistent winding), open and non-manifold
// meshes, missing and malformed files — each naming the file.
#include "core/core.h"
#include "mesh/mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <string>
#include <unistd.h>

using namespace mesh;
namespace fs = std::filesystem;

namespace {

class TempDir {
  public:
    TempDir() {
        m_path = fs::temp_directory_path() /
                 ("bw_mesh_test_" + std::to_string(::getpid()) + "_" + std::to_string(s_count++));
        fs::create_directories(m_path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    fs::path operator/(const std::string& name) const { return m_path / name; }

  private:
    fs::path m_path;
    static inline int s_count = 0;
};

// Runs f, expects a core::Error whose text contains every word.
void expectError(const std::function<void()>& f, std::initializer_list<std::string> words) {
    try {
        f();
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        for (const auto& w : words)
            EXPECT_NE(std::string(e.what()).find(w), std::string::npos)
                << "'" << e.what() << "' lacks '" << w << "'";
    }
}

// A cube written the way exporters do: 4 own vertices per face (24), quads.
const char* kSplitCube = R"(# cube with split vertices
v 0 0 0
v 0 1 0
v 1 1 0
v 1 0 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
v 0 0 0
v 1 0 0
v 1 0 1
v 0 0 1
v 1 0 0
v 1 1 0
v 1 1 1
v 1 0 1
v 1 1 0
v 0 1 0
v 0 1 1
v 1 1 1
v 0 1 0
v 0 0 0
v 0 0 1
v 0 1 1
f 1 2 3 4
f 5 6 7 8
f 9 10 11 12
f 13 14 15 16
f 17 18 19 20
f 21 22 23 24
)";

void writeText(const fs::path& p, const std::string& text) {
    core::writeFile(p, text);
}

} // namespace

TEST(MeshGeometry, UvSphereIsClosedAndOutward) {
    for (auto [rings, segs] : {std::pair{2, 3}, std::pair{8, 16}, std::pair{64, 128}}) {
        const Mesh m = makeUvSphere(rings, segs);
        const MeshTopology t = analyseTopology(m);
        EXPECT_EQ(t.boundaryEdges, 0u);
        EXPECT_EQ(t.inconsistentEdges, 0u);
        EXPECT_EQ(t.nonManifoldEdges, 0u);
        EXPECT_GT(t.signedVolume, 0.0);
        // Euler: V − E + F = 2.
        EXPECT_EQ(int64_t(m.vertices.size()) - int64_t(t.edges) + int64_t(m.triangles.size()), 2);
        EXPECT_NO_THROW(checkClosedOutward(m, "uv"));
    }
    const MeshTopology fine = analyseTopology(makeUvSphere(128, 256));
    const double ball = 4.0 / 3.0 * std::numbers::pi * 0.125;
    EXPECT_LT(fine.signedVolume, ball);
    EXPECT_GT(fine.signedVolume, 0.999 * ball);
}

TEST(MeshGeometry, ObjRoundTripWeldAndNormalise) {
    TempDir dir;
    const Mesh m = makeUvSphere(6, 10);
    writeObj(dir / "s.obj", m);
    const Mesh back = loadObj(dir / "s.obj");
    ASSERT_EQ(back.vertices.size(), m.vertices.size());
    ASSERT_EQ(back.triangles.size(), m.triangles.size());
    for (size_t i = 0; i < m.vertices.size(); ++i)
        for (int a = 0; a < 3; ++a)
            EXPECT_EQ(back.vertices[i][a], m.vertices[i][a]);
    for (size_t i = 0; i < m.triangles.size(); ++i)
        EXPECT_EQ(back.triangles[i], m.triangles[i]);

    writeText(dir / "cube.obj", kSplitCube);
    Mesh cube = loadObj(dir / "cube.obj");
    EXPECT_EQ(cube.vertices.size(), 8u); // welded
    EXPECT_EQ(cube.triangles.size(), 12u);
    EXPECT_NO_THROW(checkClosedOutward(cube, "cube"));
    EXPECT_NEAR(analyseTopology(cube).signedVolume, 1.0, 1e-12);
    for (auto& v : cube.vertices)
        v = {v[0] * 4 + 3, v[1] * 2 - 1, v[2] * 3};
    EXPECT_DOUBLE_EQ(normalizeMesh(cube, "cube"), 4.0);
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
    for (const auto& v : cube.vertices)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], v[a]);
            hi[a] = std::max(hi[a], v[a]);
        }
    EXPECT_FLOAT_EQ(hi[0] - lo[0], 1.0f);
    EXPECT_FLOAT_EQ(hi[1] - lo[1], 0.5f);
    EXPECT_FLOAT_EQ(hi[2] - lo[2], 0.75f);
    for (int a = 0; a < 3; ++a)
        EXPECT_FLOAT_EQ(lo[a] + hi[a], 0.0f);
}

// (d4) Inverted, one flipped triangle, open, non-manifold: each a clear error naming the file.
TEST(MeshGeometry, RejectsBadTopologyNamingTheFile) {
    TempDir dir;
    Mesh inward = makeUvSphere(8, 16);
    for (auto& t : inward.triangles)
        std::swap(t[1], t[2]);
    writeObj(dir / "inward.obj", inward);
    expectError(
        [&] { checkClosedOutward(loadObj(dir / "inward.obj"), (dir / "inward.obj").string()); },
        {"inward.obj", "inward", "signed volume < 0", "flip the winding"});

    Mesh oneFlipped = makeUvSphere(8, 16);
    std::swap(oneFlipped.triangles[20][1], oneFlipped.triangles[20][2]);
    writeObj(dir / "flipped.obj", oneFlipped);
    expectError(
        [&] { checkClosedOutward(loadObj(dir / "flipped.obj"), (dir / "flipped.obj").string()); },
        {"flipped.obj", "inconsistent", "3 edges"});

    Mesh open = makeUvSphere(8, 16);
    open.triangles.erase(open.triangles.begin() + 30);
    writeObj(dir / "open.obj", open);
    expectError([&] { checkClosedOutward(loadObj(dir / "open.obj"), (dir / "open.obj").string()); },
                {"open.obj", "open mesh", "not watertight", "3 boundary edges"});

    Mesh twice = makeUvSphere(8, 16); // every edge shared by four triangles
    const auto tris = twice.triangles;
    twice.triangles.insert(twice.triangles.end(), tris.begin(), tris.end());
    expectError([&] { checkClosedOutward(twice, "twice"); }, {"twice", "non-manifold"});

    expectError([&] { checkClosedOutward(Mesh{}, "empty"); }, {"empty"});
}

TEST(MeshGeometry, MissingAndMalformedFilesNameTheFile) {
    TempDir dir;
    expectError([&] { loadObj(dir / "nope.obj"); }, {"nope.obj"});
    expectError([&] { checkClosedOutward(loadObj(dir / "nope.obj"), (dir / "nope.obj").string()); },
                {"nope.obj"});
    writeText(dir / "badv.obj", "v 0 0 0\nv 1 0 zero\nv 0 1 0\nf 1 2 3\n");
    expectError([&] { loadObj(dir / "badv.obj"); }, {"badv.obj:2", "malformed"});
    writeText(dir / "badf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    expectError([&] { loadObj(dir / "badf.obj"); }, {"badf.obj", "malformed"});
    writeText(dir / "garbage.obj", "hello\nf x y z\n");
    expectError([&] { loadObj(dir / "garbage.obj"); }, {"garbage.obj", "malformed"});
    writeText(dir / "noface.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    expectError([&] { loadObj(dir / "noface.obj"); }, {"noface.obj", "no triangles"});
    writeText(dir / "short.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expectError([&] { loadObj(dir / "short.obj"); }, {"short.obj:1", "malformed"});
}

// Normals: computed area-weighted when the OBJ has none, kept when it has them; UVs kept; a
// vertex split by normals (sharp edges) still counts once for the topology.
TEST(MeshGeometry, NormalsAndUvs) {
    TempDir dir;
    writeText(dir / "cube.obj", kSplitCube);
    const Mesh cube = loadObj(dir / "cube.obj"); // no vn: 8 welded vertices, smooth normals
    ASSERT_EQ(cube.normals.size(), cube.vertices.size());
    EXPECT_TRUE(cube.uvs.empty());
    // Corner normals point out of the corner (the three faces' triangles meeting there weigh by
    // area, so the quads' diagonals tilt them off the exact diagonal).
    for (size_t i = 0; i < cube.vertices.size(); ++i)
        for (int a = 0; a < 3; ++a)
            EXPECT_GT(cube.normals[i][a] * (cube.vertices[i][a] - 0.5f), 0.1f);

    // Two right triangles sharing vertices 1 and 2, of areas 2 (normal +z) and 1 (normal +y):
    // the shared normals are the area-weighted mean, the others their face's normal.
    writeText(dir / "two.obj", "v 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\n");
    const Mesh two = loadObj(dir / "two.obj");
    ASSERT_EQ(two.normals.size(), 4u);
    const double w1 = 4.0, w2 = 2.0; // |(v1−v0) × (v2−v0)| of each face
    const double len = std::hypot(w1, w2);
    EXPECT_NEAR(two.normals[0][2], w1 / len, 1e-6);
    EXPECT_NEAR(two.normals[0][1], w2 / len, 1e-6);
    EXPECT_NEAR(two.normals[2][2], 1.0, 1e-6); // only in face 1
    EXPECT_NEAR(two.normals[3][1], 1.0, 1e-6); // only in face 2

    // Box with sharp edges and UVs: written and read back with its 24 vertices.
    const Mesh box = makeBox(1, 2, 3);
    writeObj(dir / "box.obj", box);
    const Mesh back = loadObj(dir / "box.obj");
    ASSERT_EQ(back.vertices.size(), 24u);
    ASSERT_EQ(back.normals.size(), 24u);
    ASSERT_EQ(back.uvs.size(), 24u);
    for (size_t i = 0; i < 24; ++i) {
        EXPECT_EQ(back.vertices[i], box.vertices[i]);
        EXPECT_EQ(back.normals[i], box.normals[i]);
        EXPECT_EQ(back.uvs[i], box.uvs[i]);
    }
    const MeshTopology t = analyseTopology(back);
    EXPECT_EQ(t.edges, 18u); // 12 box edges + 6 face diagonals
    EXPECT_EQ(t.boundaryEdges, 0u);
    EXPECT_NO_THROW(checkClosedOutward(back, "box.obj"));

    // One position used with two normals becomes two vertices; equal triples weld.
    writeText(dir / "split.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 2\nvn 0 1 0\n"
                                 "vt 0 0\nf 1/1/1 2/1/1 3/1/1\nf 1/1/2 4/1/2 2/1/2\n");
    const Mesh split = loadObj(dir / "split.obj");
    EXPECT_EQ(split.vertices.size(), 6u);
    ASSERT_EQ(split.normals.size(), 6u);
    EXPECT_EQ(split.normals[0], (std::array<float, 3>{0, 0, 1})); // normalised
    EXPECT_EQ(split.uvs.size(), 6u);
}
