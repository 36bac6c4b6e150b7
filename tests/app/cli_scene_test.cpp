// End-to-end tests of the `pointcloud` and `render` subcommands (thesis 3.3): each runs the real
// bssrdf-workbench executable (BW_EXE) with --root BW_SOURCE_ROOT in a fresh temporary working
// folder at small sizes (2000 points, 64×48 pixels, no point-cloud cache), checks the outputs
// (the PLY reads back with the requested point count and unit normals; the EXR reads back with
// the requested size and finite, non-negative, non-zero radiance on the covered pixels), and
// that every rejected input — bad OBJ files, point counts, methods, lights, environment maps,
// eps, sizes, models — exits non-zero with a message naming the argument or the file.
#include "pathtrace/image_io.h"
#include "pointcloud/pointcloud.h"

#include "../support/cli_fixture.h"
#include "../support/raw_exr.h"
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {
namespace fs = std::filesystem;
using namespace clitest;
using testsupport::writeRawExr;

bool contains(const std::string& hay, const std::string& needle) {
    return hay.find(needle) != std::string::npos;
}

std::string randomBytes(size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::string s;
    for (size_t i = 0; i < n; ++i)
        s.push_back(char(rng() & 0xff));
    return s;
}

const std::string kBunny = std::string(BW_SOURCE_ROOT) + "/third_party/bunny/bunny.obj";
const std::string kDipole = "materials/dipole.bssrdf";
const std::string kSky = std::string(BW_SOURCE_ROOT) + "/materials/env/default_sky.exr";

// The bad meshes of the issue: file name, contents, and a word the message must contain
// besides the file name.
struct BadMesh {
    std::string name, text, fragment;
};
std::vector<BadMesh> badMeshes() {
    return {
        {"empty.obj", "", "no triangles"},
        {"garbage.obj", randomBytes(4096, 5), "OBJ"},
        {"malformed.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n", "vertex line"},
        {"out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "OBJ"},
        {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n", "finite"},
        {"points_only.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n", "no triangles"},
        {"no_area.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n",
         "no surface area"},
    };
}

class CliScene : public CliFixture {
  protected:
    void writeBadMeshes() {
        for (const auto& m : badMeshes())
            writeText(dir() / m.name, m.text);
    }
};

// Arguments of a small render of `mesh` into out.exr, plus `extra`.
std::vector<std::string> renderArgs(const std::string& mesh, std::vector<std::string> extra = {}) {
    std::vector<std::string> a = {"render", "--mesh",     mesh,    "--model", kDipole, "--preset",
                                  "Marble", "--points",   "2000",  "--width", "64",    "--height",
                                  "48",     "--no-cache", "--out", "out.exr"};
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

// `args` with the value of `option` replaced (or appended when absent).
std::vector<std::string> with(std::vector<std::string> args, const std::string& option,
                              const std::string& value) {
    for (size_t i = 0; i + 1 < args.size(); ++i)
        if (args[i] == option) {
            args[i + 1] = value;
            return args;
        }
    args.push_back(option);
    args.push_back(value);
    return args;
}

// Checks out.exr: the size, finite non-negative radiance, and some covered (non-zero) pixels.
void expectRenderedExr(const fs::path& file, int width, int height) {
    ASSERT_TRUE(fs::exists(file));
    const pathtrace::Image img = pathtrace::readExr(file);
    EXPECT_EQ(img.width, width);
    EXPECT_EQ(img.height, height);
    ASSERT_EQ(img.mean.size(), size_t(3 * width * height));
    size_t lit = 0, bad = 0;
    for (size_t p = 0; p < size_t(width * height); ++p) {
        bool any = false;
        for (int c = 0; c < 3; ++c) {
            const float v = img.mean[3 * p + size_t(c)];
            if (!std::isfinite(v) || v < 0) ++bad;
            any |= v > 0;
        }
        lit += any;
    }
    EXPECT_EQ(bad, 0u) << "non-finite or negative radiance";
    EXPECT_GT(lit, size_t(width * height) / 20) << "the mesh should cover part of the frame";
    EXPECT_LT(lit, size_t(width * height)) << "the background should stay black";
}

// ---- pointcloud -----------------------------------------------------------------------------

TEST_F(CliScene, PointCloudWritesPlyWithTheRequestedPoints) {
    const std::vector<std::string> args = {"pointcloud", "--mesh",   kBunny, "--points",
                                           "2000",       "--seed",   "3",    "--no-cache",
                                           "--out",      "bunny.ply"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    EXPECT_TRUE(contains(r.output, "2000 points")) << r.output;
    EXPECT_TRUE(contains(r.output, "wrote bunny.ply")) << r.output;
    const pointcloud::PointCloud c = pointcloud::readPly(dir() / "bunny.ply");
    ASSERT_EQ(c.points.size(), 2000u);
    double area = 0;
    for (const auto& p : c.points) {
        const double len =
            std::sqrt(double(p.n[0]) * p.n[0] + double(p.n[1]) * p.n[1] + double(p.n[2]) * p.n[2]);
        EXPECT_NEAR(len, 1.0, 1e-5);
        EXPECT_GT(p.area, 0.0f);
        for (float v : p.p)
            EXPECT_LE(std::fabs(v), 0.5f + 1e-5f) << "the mesh is normalised to one unit";
        area += p.area;
    }
    // The point areas partition the surface: Σ area = A.
    EXPECT_NEAR(area, c.totalArea, 1e-4 * c.totalArea);
}

TEST_F(CliScene, PointCloudRejectsBadInputs) {
    writeBadMeshes();
    expectFailure({"pointcloud", "--mesh", "missing.obj", "--points", "2000", "--out", "x.ply"},
                  {"missing.obj"});
    for (const auto& m : badMeshes()) {
        SCOPED_TRACE(m.name);
        expectFailure(
            {"pointcloud", "--mesh", m.name, "--points", "2000", "--no-cache", "--out", "x.ply"},
            {m.name, m.fragment});
    }
    expectFailure({"pointcloud", "--mesh", kBunny, "--points", "0", "--out", "x.ply"},
                  {"--points", "between 1 and 16777216, got 0"});
    expectFailure({"pointcloud", "--mesh", kBunny, "--points", "50000000", "--out", "x.ply"},
                  {"--points", "16777216"});
    expectFailure({"pointcloud", "--mesh", kBunny, "--method", "poisson", "--out", "x.ply"},
                  {"--method", "poisson"});
    expectFailure({"pointcloud", "--mesh", kBunny, "--points", "2000", "--no-cache", "--out",
                   "/proc/nope/x.ply"},
                  {"/proc/nope/x.ply"});
    EXPECT_FALSE(fs::exists(dir() / "x.ply"));
}

// Meshes that once made work unbounded: one vertex far away (1e20 and 4e10 mesh units, in a
// triangle with two bunny vertices: after normalisation the bunny is a speck and the points
// lie on a needle triangle), a lone needle triangle, and 100 000 coincident vertices in
// degenerate triangles. Each run ends with the metrics printed (the nearest-neighbour metric
// was a grid ring search that took minutes on the far vertex; a relapse shows as this test
// hanging); nothing is asserted on time.
TEST_F(CliScene, PointCloudOnExtremeMeshesEnds) {
    const std::string bunny = readText(fs::path(BW_SOURCE_ROOT) / kBunny);
    std::string coincident = bunny + "\n";
    for (int i = 0; i < 100000; ++i)
        coincident += "v 0.25 0.25 0.25\n";
    for (int i = 0; i < 100000 - 2; ++i)
        coincident += "f " + std::to_string(1840 + i) + " " + std::to_string(1841 + i) + " " +
                      std::to_string(1842 + i) + "\n";
    const std::vector<std::pair<std::string, std::string>> meshes = {
        {"far 1e20", bunny + "\nv 1e20 0 0\nf 1 2 1840\n"},
        {"far 4e10", bunny + "\nv 4e10 0 0\nf 1 2 1840\n"},
        {"needle", "v 0 0 0\nv 1 0 0\nv 0.5 1e-9 0\nf 1 2 3\n"},
        {"coincident", coincident}};
    for (const auto& [name, text] : meshes) {
        SCOPED_TRACE(name);
        std::ofstream(dir() / "far.obj") << text;
        // On the far meshes every point lies on one sliver whose box holds the rest of the mesh,
        // and the neighbour cells are multiples of 2^15: per-triangle projection candidates and
        // a linear cell hash made each iteration n·T and n² (2000 points took 23 s under ASan).
        RunResult r = run({"pointcloud", "--mesh", "far.obj", "--points", "2000", "--no-cache",
                           "--out", "far.ply"});
        EXPECT_EQ(r.code, 0) << r.output;
        EXPECT_TRUE(contains(r.output, "nearest neighbour: mean")) << r.output;
        EXPECT_TRUE(contains(r.output, "wrote far.ply")) << r.output;
    }
}

// ---- render -------------------------------------------------------------------------------

TEST_F(CliScene, RenderWritesExrOfTheMesh) {
    const auto args = renderArgs(kBunny, {"--png", "out.png"});
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    EXPECT_TRUE(contains(r.output, "2000 points")) << r.output;
    EXPECT_TRUE(contains(r.output, "64x48")) << r.output;
    EXPECT_TRUE(contains(r.output, "wrote out.exr")) << r.output;
    // the progress line names every step of the pipeline as it starts
    for (const char* step :
         {"render: mesh", "render: point cloud", "render: irradiance", "render: render"})
        EXPECT_TRUE(contains(r.output, step)) << step << "\n" << r.output;
    expectRenderedExr(dir() / "out.exr", 64, 48);
    const std::string png = readText(dir() / "out.png");
    ASSERT_GE(png.size(), 8u);
    EXPECT_EQ(png.substr(1, 3), "PNG");
}

TEST_F(CliScene, RenderWithImageBasedLighting) {
    const auto args = renderArgs(kBunny, {"--light", "ibl:" + kSky});
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    expectRenderedExr(dir() / "out.exr", 64, 48);
}

TEST_F(CliScene, RenderRejectsBadMeshes) {
    writeBadMeshes();
    expectFailure(renderArgs("missing.obj"), {"missing.obj"});
    for (const auto& m : badMeshes()) {
        SCOPED_TRACE(m.name);
        expectFailure(renderArgs(m.name), {m.name, m.fragment});
    }
    EXPECT_FALSE(fs::exists(dir() / "out.exr"));
}

// A mesh that fails to load is one error, and the steps after it are not announced: a model
// file given as --mesh used to print the error twice and the progress of every later step.
TEST_F(CliScene, AFailedMeshIsOneErrorAndTheRunStopsThere) {
    const RunResult r = run(renderArgs(std::string(BW_SOURCE_ROOT) + "/" + kDipole));
    EXPECT_EQ(r.code, 1) << r.output;
    size_t errors = 0;
    for (size_t at = r.output.find("error"); at != std::string::npos;
         at = r.output.find("error", at + 1))
        ++errors;
    EXPECT_EQ(errors, 1u) << r.output;
    EXPECT_NE(r.output.find("no triangles"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("point cloud"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("render: render"), std::string::npos) << r.output;
    // the progress line ("\rrender: mesh ...") is ended before the error, which starts a line
    EXPECT_NE(r.output.find("render: mesh"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\nerror: "), std::string::npos) << r.output;
}

TEST_F(CliScene, RenderRejectsBadArguments) {
    expectFailure(with(renderArgs(kBunny), "--points", "0"),
                  {"--points", "between 1 and 16777216, got 0"});
    expectFailure(with(renderArgs(kBunny), "--points", "50000000"), {"--points", "16777216"});
    expectFailure(renderArgs(kBunny, {"--method", "poisson"}), {"--method", "poisson"});
    expectFailure(renderArgs(kBunny, {"--light", "garbage"}), {"--light", "garbage"});
    expectFailure(renderArgs(kBunny, {"--light", "dir:0,0,0"}), {"--light"});
    expectFailure(renderArgs(kBunny, {"--occluded"}), {"--occluded", "ibl"});
    expectFailure(renderArgs(kBunny, {"--eps", "-0.1"}), {"--eps"});
    expectFailure(renderArgs(kBunny, {"--eps", "nan"}), {"--eps"});
    expectFailure(with(renderArgs(kBunny), "--width", "0"), {"--width"});
    expectFailure(with(renderArgs(kBunny), "--height", "9000"), {"height"});
    EXPECT_FALSE(fs::exists(dir() / "out.exr"));
}

TEST_F(CliScene, RenderRejectsBadEnvironmentMaps) {
    writeText(dir() / "corrupt.exr", randomBytes(2000, 9));
    writeRawExr(dir() / "luminance.exr", 8, 4, {"Y"}, std::vector<float>(32, 1.0f));
    expectFailure(renderArgs(kBunny, {"--light", "ibl:missing.exr"}),
                  {"missing.exr", "--light ibl: cannot open"});
    // a missing map is refused before the point cloud is made, not after the irradiance
    const RunResult missing = run(renderArgs(kBunny, {"--light", "ibl:missing.exr"}));
    EXPECT_FALSE(contains(missing.output, "point cloud")) << missing.output;
    expectFailure(renderArgs(kBunny, {"--light", "ibl:corrupt.exr"}), {"corrupt.exr"});
    expectFailure(renderArgs(kBunny, {"--light", "ibl:luminance.exr"}),
                  {"luminance.exr", "no channel 'R'"});
    EXPECT_FALSE(fs::exists(dir() / "out.exr"));
}

TEST_F(CliScene, RenderRejectsMissingAndBrokenModels) {
    expectFailure(with(renderArgs(kBunny), "--model", "does/not/exist.bssrdf"),
                  {"--model", "does/not/exist.bssrdf"});

    // A GLSL error in the shader section: the message names the model file and the line.
    const std::string original = readText(fs::path(BW_SOURCE_ROOT) / kDipole);
    const std::string good = "vec3 Dr = sqrt(R + Zr*Zr);";
    const size_t at = original.find(good);
    ASSERT_NE(at, std::string::npos);
    const std::string text =
        original.substr(0, at) + "vec3 Dr = ;" + original.substr(at + good.size());
    int line = 1;
    for (size_t i = 0; i < at; ++i)
        line += original[i] == '\n';
    const fs::path broken = dir() / "broken.bssrdf";
    writeText(broken, text);
    expectFailure(with(renderArgs(kBunny), "--model", broken.string()),
                  {broken.string() + ":" + std::to_string(line)});
    EXPECT_FALSE(fs::exists(dir() / "out.exr"));
}

} // namespace
