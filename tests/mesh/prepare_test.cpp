// mesh::prepareRenderable: the bad meshes the point-cloud pipeline must refuse or repair, each
// with a message naming the file — NaN/Inf vertices, degenerate triangles (dropped and counted),
// a mesh with no area, a point-only OBJ, an empty and a binary file — and normalisation of a
// good mesh.
#include "../support/scratch_dir.h"
#include "core/core.h"
#include "mesh/mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;

namespace {

fs::path writeTemp(const std::string& name, const std::string& text) {
    fs::path dir = fs::temp_directory_path() / ("bw_prepare_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    testsupport::removeAtExit(dir);
    std::ofstream(dir / name, std::ios::binary) << text;
    return dir / name;
}

std::string errorOf(const fs::path& p) {
    try {
        mesh::Mesh m = mesh::loadObj(p);
        mesh::prepareRenderable(m, p.string());
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(PrepareRenderable, NonFiniteVerticesAreRefused) {
    for (const char* bad : {"nan", "inf", "-inf"}) {
        auto p = writeTemp(std::string("v_") + bad + ".obj",
                           std::string("v 0 0 0\nv 1 0 0\nv 0 ") + bad + " 0\nf 1 2 3\n");
        std::string e = errorOf(p);
        EXPECT_NE(e.find(p.filename().string()), std::string::npos) << e;
        EXPECT_TRUE(e.find("non-finite") != std::string::npos ||
                    e.find("malformed") != std::string::npos)
            << e;
    }
}

TEST(PrepareRenderable, DegenerateTrianglesAreDroppedAndCounted) {
    // A unit square (two triangles) plus a collinear sliver (zero area).
    auto p = writeTemp("sliver.obj",
                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 3 4\nf 1 2 5\n");
    mesh::Mesh m = mesh::loadObj(p);
    ASSERT_EQ(m.triangles.size(), 3u);
    auto r = mesh::prepareRenderable(m, p.string());
    EXPECT_EQ(r.droppedDegenerate, 1u);
    EXPECT_EQ(m.triangles.size(), 2u);
    // the box of the vertices the remaining triangles use: vertex 5 (x = 2) went with the sliver
    EXPECT_DOUBLE_EQ(r.originalLongestAxis, 1.0);
}

TEST(PrepareRenderable, NoAreaPointOnlyEmptyAndBinaryAreRefused) {
    std::string e = errorOf(writeTemp("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"));
    EXPECT_NE(e.find("flat.obj"), std::string::npos) << e;
    EXPECT_NE(e.find("no surface area"), std::string::npos) << e;

    e = errorOf(writeTemp("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n"));
    EXPECT_NE(e.find("points.obj"), std::string::npos) << e;
    EXPECT_NE(e.find("no triangles"), std::string::npos) << e;

    e = errorOf(writeTemp("empty.obj", ""));
    EXPECT_NE(e.find("empty.obj"), std::string::npos) << e;
    EXPECT_FALSE(e.empty());

    // 12 bytes: an ELF header's start with its NULs (the length from the array, not counted)
    const char elf[] = "\x7f"
                       "ELF\x02\x01\x01\0\0\0\xff\xfe";
    e = errorOf(writeTemp("binary.obj", std::string(elf, sizeof elf - 1)));
    EXPECT_NE(e.find("binary.obj"), std::string::npos) << e;
    EXPECT_FALSE(e.empty());

    e = errorOf(writeTemp("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"));
    EXPECT_NE(e.find("range.obj"), std::string::npos) << e;

    EXPECT_NE(errorOf("/nonexistent/missing.obj").find("missing.obj"), std::string::npos);
}

TEST(PrepareRenderable, NormalisesTheBunny) {
    fs::path p = fs::path(BW_SOURCE_ROOT) / "third_party/bunny/bunny.obj";
    mesh::Mesh m = mesh::loadObj(p);
    auto r = mesh::prepareRenderable(m, p.string());
    EXPECT_EQ(r.droppedDegenerate, 0u);
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
    for (const auto& v : m.vertices)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], v[a]);
            hi[a] = std::max(hi[a], v[a]);
        }
    float longest = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    EXPECT_NEAR(longest, 1.0f, 1e-6f);
}
