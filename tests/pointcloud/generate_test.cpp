// pointcloud::generate: method dispatch, request checks (count, method, memory cap) and the PLY
// cache — a miss writes the file, a hit returns the same points bitwise, a corrupt or
// mismatched cache file is regenerated and rewritten, the key depends on the method's
// parameters.
#include "../support/scratch_dir.h"
#include "pointcloud/generate.h"

#include "core/core.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace {
namespace fs = std::filesystem;

bool samePoints(const pointcloud::PointCloud& a, const pointcloud::PointCloud& b) {
    if (a.points.size() != b.points.size()) return false;
    for (size_t i = 0; i < a.points.size(); ++i)
        if (std::memcmp(a.points[i].p, b.points[i].p, sizeof a.points[i].p) != 0 ||
            std::memcmp(a.points[i].n, b.points[i].n, sizeof a.points[i].n) != 0 ||
            a.points[i].area != b.points[i].area)
            return false;
    return true;
}

std::string errorOf(const pointcloud::GenerateOptions& o) {
    try {
        pointcloud::checkOptions(o);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(PointCloudGenerate, CacheMissWritesHitReadsCorruptRegenerates) {
    const fs::path dir = fs::temp_directory_path() / ("bw_pc_cache_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    testsupport::removeAtExit(dir);
    const mesh::Mesh m = mesh::makeTorus(0.35, 0.12, 32, 16);
    pointcloud::GenerateOptions o;
    o.points = 1500;
    const pointcloud::Generated first = pointcloud::generate(m, o, dir);
    EXPECT_FALSE(first.fromCache);
    ASSERT_TRUE(fs::exists(first.cacheFile));
    EXPECT_EQ(first.cloud.points.size(), 1500u);

    const pointcloud::Generated second = pointcloud::generate(m, o, dir);
    EXPECT_TRUE(second.fromCache);
    EXPECT_EQ(second.cacheFile, first.cacheFile);
    // the PLY stores positions, normals and areas as float32: bitwise the same points
    EXPECT_TRUE(samePoints(first.cloud, second.cloud));
    EXPECT_DOUBLE_EQ(first.cloud.totalArea, second.cloud.totalArea);

    std::ofstream(first.cacheFile, std::ios::binary | std::ios::trunc) << "ply\ngarbage";
    const pointcloud::Generated third = pointcloud::generate(m, o, dir);
    EXPECT_FALSE(third.fromCache);
    EXPECT_TRUE(samePoints(first.cloud, third.cloud));
    EXPECT_TRUE(pointcloud::generate(m, o, dir).fromCache); // rewritten

    // different method parameters and seeds are different entries
    pointcloud::GenerateOptions other = o;
    other.stratifiedIterations = 10;
    EXPECT_NE(pointcloud::generate(m, other, dir).cacheFile, first.cacheFile);
    other = o;
    other.seed = 2;
    EXPECT_NE(pointcloud::generate(m, other, dir).cacheFile, first.cacheFile);
    fs::remove_all(dir);
}

TEST(PointCloudGenerate, EveryMethodGivesNPointsOfAreaAOverN) {
    const mesh::Mesh m = mesh::makeTorus(0.35, 0.12, 32, 16);
    const double area = pointcloud::meshArea(m);
    for (const auto& [method, name] : enumNames(pointcloud::Method{})) {
        pointcloud::GenerateOptions o;
        o.points = 800;
        o.method = method;
        o.repulsionIterations = 5;
        const pointcloud::Generated g = pointcloud::generate(m, o);
        EXPECT_TRUE(g.cacheFile.empty());
        ASSERT_EQ(g.cloud.points.size(), 800u) << name;
        for (const auto& p : g.cloud.points)
            ASSERT_NEAR(p.area, area / 800.0, 1e-6 * area) << name;
    }
}

// Progress: the relaxing methods report every iteration, in order, ending at the total; the
// others report nothing; the cloud is the same with or without a listener.
TEST(PointCloudGenerate, RelaxationReportsEveryIteration) {
    const mesh::Mesh m = mesh::makeTorus(0.35, 0.12, 32, 16);
    for (const auto& [method, name] : enumNames(pointcloud::Method{})) {
        pointcloud::GenerateOptions o;
        o.points = 600;
        o.method = method;
        o.repulsionIterations = 6;
        o.stratifiedIterations = 7;
        std::vector<std::pair<int, int>> calls;
        const auto g = pointcloud::generate(
            m, o, {}, [&](int done, int total) { calls.emplace_back(done, total); });
        const int expect = method == pointcloud::Method::StratifiedRepulsion ? 7
                           : method == pointcloud::Method::Repulsion         ? 6
                                                                             : 0;
        ASSERT_EQ(calls.size(), size_t(expect)) << name;
        for (size_t i = 0; i < calls.size(); ++i)
            EXPECT_EQ(calls[i], std::make_pair(int(i) + 1, expect)) << name;
        const auto quiet = pointcloud::generate(m, o);
        ASSERT_EQ(quiet.cloud.points.size(), g.cloud.points.size());
        for (size_t i = 0; i < g.cloud.points.size(); ++i)
            for (int k = 0; k < 3; ++k)
                ASSERT_EQ(quiet.cloud.points[i].p[k], g.cloud.points[i].p[k]) << name;
    }
}

TEST(PointCloudGenerate, BadRequestsNameTheArgument) {
    pointcloud::GenerateOptions o;
    o.points = 0;
    EXPECT_NE(errorOf(o).find("--points"), std::string::npos);
    o.points = (size_t(1) << 24) + 1;
    EXPECT_NE(errorOf(o).find("24-bit"), std::string::npos);
    o.points = 1000;
    o.method = pointcloud::Method::Elimination;
    o.memoryCapBytes = 1000;
    const std::string e = errorOf(o);
    EXPECT_NE(e.find("over the cap"), std::string::npos) << e;
    EXPECT_NE(e.find("MiB"), std::string::npos) << e;
    o.memoryCapBytes = size_t(4) << 30;
    o.stratifiedIterations = -1;
    EXPECT_NE(errorOf(o).find("--iterations"), std::string::npos);
}
