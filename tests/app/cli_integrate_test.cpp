// `bssrdf-workbench integrate` end to end: the EXR it writes (R, G, B and their variances, read
// back), uniform and disk sampling of the same sphere agreeing where the picture is bright, and
// every rejected input named.
#include "../support/cli_fixture.h"
#include "../support/image_agreement.h"
#include "core/statistics.h"
#include "pathtrace/image_io.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

namespace {
using namespace clitest;
class IntegrateCli : public CliFixture {};
} // namespace

TEST_F(IntegrateCli, WritesTheImageWithVariancesAndBothSamplingsAgree) {
    const std::vector<std::string> base = {
        "integrate", "--sphere", "10",     "--model", "materials/dipole.bssrdf",
        "--preset",  "Skin1",    "--size", "12x12"};
    std::vector<std::string> disk = base, uni = base;
    disk.insert(disk.end(),
                {"--sampling", "disk", "--axes", "pbrt", "--spp", "1024", "--out", "disk.exr"});
    // another seed: the two estimates independent, as the z-test assumes
    uni.insert(uni.end(),
               {"--sampling", "uniform", "--spp", "16384", "--seed", "2", "--out", "uni.exr"});
    RunResult r = run(disk);
    ASSERT_EQ(r.code, 0) << describe(disk, r);
    EXPECT_NE(r.output.find("disk sampling (axes pbrt, R_m "), std::string::npos) << r.output;
    r = run(uni);
    ASSERT_EQ(r.code, 0) << describe(uni, r);
    const pathtrace::Image d = pathtrace::readExr(dir() / "disk.exr");
    const pathtrace::Image u = pathtrace::readExr(dir() / "uni.exr");
    ASSERT_EQ(d.width, 12);
    ASSERT_EQ(d.mean.size(), u.mean.size());
    size_t zeros = 0, lit = 0;
    for (size_t i = 0; i < u.mean.size(); ++i) {
        zeros += d.mean[i] == 0 && u.mean[i] == 0; // off the sphere
        if (u.mean[i] > 0) {
            ++lit;
            EXPECT_GT(d.variance[i], 0.0f) << i; // the file carries the variances
        }
    }
    EXPECT_GT(zeros, 0u);
    EXPECT_GT(lit, 200u);
    const testsupport::Agreement g = testsupport::agreePerPixel(d, u);
    EXPECT_GT(g.tested, 200u);
    EXPECT_LT(g.maxZ, g.threshold);
}

TEST_F(IntegrateCli, BadInputsAreNamed) {
    const std::vector<std::string> m = {"--model", "materials/dipole.bssrdf", "--preset", "Skin1"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = {"integrate"};
        a.insert(a.end(), m.begin(), m.end());
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    expectFailure(with({"--sphere", "10", "--sampling", "disk", "--spp", "0", "--out", "a.exr"}),
                  {"--spp"});
    expectFailure(with({"--sampling", "disk", "--spp", "4", "--out", "a.exr"}),
                  {"--mesh", "--sphere"});
    expectFailure(with({"--sphere", "10", "--mesh", "x.obj", "--sampling", "disk", "--spp", "4",
                        "--out", "a.exr"}),
                  {"exactly one"});
    expectFailure(
        with({"--sphere", "10", "--sampling", "importance", "--spp", "4", "--out", "a.exr"}),
        {"--sampling", "uniform | disk"});
    expectFailure(with({"--sphere", "10", "--sampling", "uniform", "--axes", "pbrt", "--spp", "4",
                        "--out", "a.exr"}),
                  {"--axes", "only with --sampling disk"});
    expectFailure(with({"--sphere", "10", "--sampling", "uniform", "--energy-loss", "0.01", "--spp",
                        "4", "--out", "a.exr"}),
                  {"--energy-loss: only with --sampling disk"});
    expectFailure(with({"--sphere", "nan", "--sampling", "disk", "--spp", "4", "--out", "a.exr"}),
                  {"--sphere"});
    expectFailure(with({"--sphere", "10", "--sampling", "disk", "--spp", "4", "--light", "0,0,0",
                        "--out", "a.exr"}),
                  {"--light"});
    expectFailure(with({"--sphere", "10", "--sampling", "disk", "--spp", "4", "--out", "a.png"}),
                  {"--out"});
    // an open mesh: one face of a cube missing
    {
        std::ofstream obj(dir() / "open.obj");
        obj << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
               "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\n"
               "f 3 4 8\nf 3 8 7\n";
    }
    expectFailure(
        with({"--mesh", "open.obj", "--sampling", "disk", "--spp", "4", "--out", "a.exr"}),
        {"open.obj"});
    EXPECT_FALSE(std::filesystem::exists(dir() / "a.exr"));
}
