// Tests for pointcloud: area-uniform sampling (chi-square over box faces), surface membership
// (barycentrics in the point's triangle), determinism across thread counts, Turk repulsion and
// weighted sample elimination uniformity, binary PLY round trip and header validation.
#include "pointcloud/pointcloud.h"

#include "core/core.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>

namespace {

using pointcloud::PointCloud;

// Distance of p to the plane of its triangle and its smallest barycentric coordinate.
void membership(const mesh::Mesh& m, const pointcloud::Point& pt, double& planeDist,
                double& minBary) {
    const auto& t = m.triangles[pt.triangle];
    double a[3], e1[3], e2[3], d[3];
    for (int k = 0; k < 3; ++k) {
        a[k] = m.vertices[t[0]][k];
        e1[k] = m.vertices[t[1]][k] - a[k];
        e2[k] = m.vertices[t[2]][k] - a[k];
        d[k] = pt.p[k] - a[k];
    }
    double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    double nl = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    planeDist = std::abs(n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / nl;
    auto dot = [](const double* x, const double* y) {
        return x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    };
    double d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2);
    double d20 = dot(d, e1), d21 = dot(d, e2);
    double den = d00 * d11 - d01 * d01;
    double v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
    minBary = std::min({1 - v - w, v, w});
}

void expectOnSurface(const mesh::Mesh& m, const PointCloud& c) {
    double worstPlane = 0, worstBary = 0;
    for (const auto& p : c.points) {
        ASSERT_LT(p.triangle, m.triangles.size());
        double pd, mb;
        membership(m, p, pd, mb);
        worstPlane = std::max(worstPlane, pd);
        worstBary = std::min(worstBary, mb);
        double nl = std::sqrt(p.n[0] * p.n[0] + p.n[1] * p.n[1] + p.n[2] * p.n[2]);
        ASSERT_NEAR(nl, 1.0, 1e-5);
    }
    EXPECT_LT(worstPlane, 1e-6);
    EXPECT_GT(worstBary, -1e-5);
}

bool sameCloud(const PointCloud& a, const PointCloud& b) {
    if (a.points.size() != b.points.size() || a.totalArea != b.totalArea) return false;
    for (size_t i = 0; i < a.points.size(); ++i) {
        const auto &p = a.points[i], &q = b.points[i];
        if (std::memcmp(p.p, q.p, sizeof p.p) || std::memcmp(p.n, q.n, sizeof p.n) ||
            p.area != q.area || p.triangle != q.triangle)
            return false;
    }
    return true;
}

TEST(PointCloudSampling, UniformPerAreaOnBoxFaces) {
    mesh::Mesh box = mesh::makeBox(1.0, 2.0, 3.0); // face areas 6, 6, 3, 3, 2, 2
    const size_t n = 60000;
    PointCloud c = pointcloud::sampleUniform(box, n, 7);
    EXPECT_NEAR(c.totalArea, 22.0, 1e-9);
    double counts[6] = {};
    for (const auto& p : c.points) {
        int axis = 0;
        for (int k = 1; k < 3; ++k)
            if (std::abs(p.n[k]) > std::abs(p.n[axis])) axis = k;
        counts[axis * 2 + (p.n[axis] > 0 ? 1 : 0)] += 1;
    }
    const double areas[6] = {6, 6, 3, 3, 2, 2};
    double chi2 = 0;
    for (int f = 0; f < 6; ++f) {
        double expected = double(n) * areas[f] / 22.0;
        chi2 += (counts[f] - expected) * (counts[f] - expected) / expected;
    }
    EXPECT_LT(chi2, 20.515); // chi-square, 5 degrees of freedom, p = 1e-3
    for (const auto& p : c.points)
        ASSERT_FLOAT_EQ(p.area, float(22.0 / n));
    expectOnSurface(box, c);
}

TEST(PointCloudSampling, PointsLieOnTheirTriangle) {
    mesh::Mesh sphere = mesh::makeUvSphere(24, 48);
    PointCloud c = pointcloud::sampleUniform(sphere, 5000, 3);
    expectOnSurface(sphere, c);
    double maxOff = 0;
    for (const auto& p : c.points)
        maxOff = std::max(maxOff, std::abs(std::hypot(p.p[0], p.p[1], p.p[2]) - 0.5));
    EXPECT_LT(maxOff, 0.5 * (1 - std::cos(M_PI / 24)) + 1e-6); // chord sagitta
}

TEST(PointCloudSampling, DeterministicAndThreadIndependent) {
    mesh::Mesh torus = mesh::makeTorus(1.0, 0.3, 32, 16);
    PointCloud a = pointcloud::sampleUniform(torus, 3000, 11, 1);
    PointCloud b = pointcloud::sampleUniform(torus, 3000, 11, 2);
    PointCloud c = pointcloud::sampleUniform(torus, 3000, 11);
    PointCloud d = pointcloud::sampleUniform(torus, 3000, 12);
    EXPECT_TRUE(sameCloud(a, b));
    EXPECT_TRUE(sameCloud(a, c));
    EXPECT_FALSE(sameCloud(a, d));
}

class Relaxation : public ::testing::Test {
  protected:
    mesh::Mesh sphere = mesh::makeUvSphere(32, 64);
    static constexpr size_t kN = 2000;
};

TEST_F(Relaxation, RepulsionImprovesUniformityAndStaysOnSurface) {
    PointCloud random = pointcloud::sampleUniform(sphere, kN, 5);
    pointcloud::RepulsionOptions opt;
    opt.iterations = 40;
    opt.threads = 2;
    PointCloud relaxed = pointcloud::relaxRepulsion(sphere, random, opt);
    auto u0 = pointcloud::measureUniformity(random);
    auto u1 = pointcloud::measureUniformity(relaxed);
    std::printf("random: mean %.5f min %.5f cv %.4f; repulsion: mean %.5f min %.5f cv %.4f\n",
                u0.meanNN, u0.minNN, u0.cvNN, u1.meanNN, u1.minNN, u1.cvNN);
    EXPECT_LT(u1.cvNN, 0.5 * u0.cvNN);
    EXPECT_GT(u1.minNN, 3 * u0.minNN);
    ASSERT_EQ(relaxed.points.size(), kN);
    expectOnSurface(sphere, relaxed);
    opt.threads = 1;
    EXPECT_TRUE(sameCloud(relaxed, pointcloud::relaxRepulsion(sphere, random, opt)));
}

TEST_F(Relaxation, SampleEliminationExactCountUniformOnSurface) {
    pointcloud::EliminationOptions opt;
    opt.threads = 2;
    PointCloud e = pointcloud::sampleElimination(sphere, kN, 5, opt);
    ASSERT_EQ(e.points.size(), kN);
    PointCloud random = pointcloud::sampleUniform(sphere, kN, 5);
    auto u0 = pointcloud::measureUniformity(random);
    auto u1 = pointcloud::measureUniformity(e);
    std::printf("random: mean %.5f min %.5f cv %.4f; elimination: mean %.5f min %.5f cv %.4f\n",
                u0.meanNN, u0.minNN, u0.cvNN, u1.meanNN, u1.minNN, u1.cvNN);
    EXPECT_LT(u1.cvNN, 0.5 * u0.cvNN);
    EXPECT_GT(u1.minNN, 3 * u0.minNN);
    expectOnSurface(sphere, e);
    double sum = 0;
    for (const auto& p : e.points)
        sum += p.area;
    EXPECT_NEAR(sum, e.totalArea, 1e-3 * e.totalArea);
    opt.threads = 1;
    EXPECT_TRUE(sameCloud(e, pointcloud::sampleElimination(sphere, kN, 5, opt)));
}

TEST(PointCloudUniformity, KnownGrid) {
    PointCloud c;
    c.totalArea = 1;
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j)
            c.points.push_back({{0.1f * float(i), 0.1f * float(j), 0}, {0, 0, 1}, 0.01f, 0});
    auto u = pointcloud::measureUniformity(c);
    EXPECT_NEAR(u.meanNN, 0.1, 1e-6);
    EXPECT_NEAR(u.minNN, 0.1, 1e-6);
    EXPECT_NEAR(u.cvNN, 0.0, 1e-5);
}

std::filesystem::path tempDir() {
    auto d = std::filesystem::temp_directory_path() / "bw_pointcloud_test";
    std::filesystem::create_directories(d);
    return d;
}

TEST(PointCloudPly, RoundTripBitExact) {
    mesh::Mesh sphere = mesh::makeUvSphere(8, 16);
    PointCloud c = pointcloud::sampleUniform(sphere, 777, 9);
    c.totalArea = 3.141592653589793 / 3.0;
    auto path = tempDir() / "round_trip.ply";
    pointcloud::writePly(path, c);
    PointCloud r = pointcloud::readPly(path);
    ASSERT_EQ(r.points.size(), c.points.size());
    EXPECT_EQ(r.totalArea, c.totalArea);
    for (size_t i = 0; i < c.points.size(); ++i) {
        EXPECT_EQ(std::memcmp(r.points[i].p, c.points[i].p, sizeof c.points[i].p), 0);
        EXPECT_EQ(std::memcmp(r.points[i].n, c.points[i].n, sizeof c.points[i].n), 0);
        EXPECT_EQ(std::memcmp(&r.points[i].area, &c.points[i].area, sizeof(float)), 0);
        EXPECT_EQ(r.points[i].triangle, c.points[i].triangle);
    }
    // bitwise: what a capture hashes of a cloud read from the cache is what it hashes of the
    // cloud generated
    EXPECT_EQ(std::memcmp(r.points.data(), c.points.data(), c.points.size() * sizeof(c.points[0])),
              0);
}

// A PLY without the triangle property (another program's) still reads, with kNoTriangle.
TEST(PointCloudPly, WithoutTrianglesReadsAsUnknown) {
    const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
                               "property float x\nproperty float y\nproperty float z\n"
                               "property float nx\nproperty float ny\nproperty float nz\n"
                               "property float area\nend_header\n";
    const float v[7] = {1, 2, 3, 0, 0, 1, 0.5f};
    const auto path = tempDir() / "no_triangles.ply";
    core::writeFile(path, header + std::string(reinterpret_cast<const char*>(v), sizeof v));
    const PointCloud r = pointcloud::readPly(path);
    ASSERT_EQ(r.points.size(), 1u);
    EXPECT_EQ(r.points[0].p[1], 2.0f);
    EXPECT_EQ(r.points[0].area, 0.5f);
    EXPECT_EQ(r.points[0].triangle, pointcloud::kNoTriangle);
    EXPECT_EQ(r.totalArea, 0.5);
}

void expectPlyError(const std::string& fileName, const std::string& bytes,
                    const std::string& fragment) {
    auto path = tempDir() / fileName;
    core::writeFile(path, bytes);
    try {
        pointcloud::readPly(path);
        ADD_FAILURE() << "no error for " << fileName;
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find(fileName), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

TEST(PointCloudPly, MalformedInputNamesTheFile) {
    const std::string props = "property float x\nproperty float y\nproperty float z\n"
                              "property float nx\nproperty float ny\nproperty float nz\n"
                              "property float area\n";
    expectPlyError("magic.ply", "plx\n", "magic");
    expectPlyError("ascii.ply", "ply\nformat ascii 1.0\nend_header\n", "format");
    expectPlyError("noend.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1\n" + props,
                   "end_header");
    expectPlyError("prop.ply",
                   "ply\nformat binary_little_endian 1.0\nelement vertex 0\n"
                   "property double x\nend_header\n",
                   "property");
    expectPlyError("face.ply", "ply\nformat binary_little_endian 1.0\nelement face 1\nend_header\n",
                   "element");
    expectPlyError("short.ply",
                   "ply\nformat binary_little_endian 1.0\nelement vertex 2\n" + props +
                       "end_header\n" + std::string(28, '\0'),
                   "data size");
    EXPECT_THROW(pointcloud::readPly(tempDir() / "missing.ply"), core::Error);
}

TEST(PointCloudCache, KeyDependsOnEverything) {
    mesh::Mesh a = mesh::makeUvSphere(8, 16), b = mesh::makeUvSphere(8, 17);
    std::string k = pointcloud::cacheKey(a, 1000, "repulsion", 1);
    EXPECT_EQ(k.size(), 16u);
    EXPECT_EQ(k, pointcloud::cacheKey(a, 1000, "repulsion", 1));
    EXPECT_NE(k, pointcloud::cacheKey(b, 1000, "repulsion", 1));
    EXPECT_NE(k, pointcloud::cacheKey(a, 1001, "repulsion", 1));
    EXPECT_NE(k, pointcloud::cacheKey(a, 1000, "elimination", 1));
    EXPECT_NE(k, pointcloud::cacheKey(a, 1000, "repulsion", 2));
}

} // namespace
