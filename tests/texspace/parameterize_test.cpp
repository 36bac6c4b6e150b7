// The parameterisation of texture-space sampling (texspace/texspace.h, Chang 2007 §3.1.1):
// which UVs qualify (the failing triangle named), the atlas (inside [0, 1]², no overlaps, the
// gutter kept, area ratios A_S/A_T computed independently here, Σ A_T · A_S/A_T = the surface
// area exactly), the stretch of a known triangle, and the bunny and the procedural shapes.
#include "texspace/texspace.h"
#include "texspace/texture_space.h"

#include "core/core.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <glm/geometric.hpp>

namespace {

double meshArea(const mesh::Mesh& m) {
    double a = 0;
    for (const auto& t : m.triangles) {
        const auto& p = m.vertices[t[0]];
        const auto& q = m.vertices[t[1]];
        const auto& r = m.vertices[t[2]];
        const double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
        const double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
        const double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                             u[0] * v[1] - u[1] * v[0]};
        a += 0.5 * std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    return a;
}

// Two triangles forming the unit square in the xy plane, UVs = (x, y).
mesh::Mesh square() {
    mesh::Mesh m;
    m.vertices = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
    m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

} // namespace

TEST(Parameterize, QualifyingUvsAreUsedWithTheirAreaRatios) {
    const mesh::Mesh m = square();
    EXPECT_EQ(texspace::uvProblem(m), "");
    const texspace::Parameterization p = texspace::parameterize(m, 64);
    EXPECT_TRUE(p.fromMesh);
    EXPECT_TRUE(p.note.empty());
    for (size_t t = 0; t < 2; ++t) {
        EXPECT_DOUBLE_EQ(p.areaSurface[t], 1.0); // half of the 2 × 1 rectangle
        EXPECT_DOUBLE_EQ(p.areaTexture[t], 0.5); // half of the unit square
        EXPECT_DOUBLE_EQ(p.areaRatio(t), 2.0);
        EXPECT_NEAR(p.stretch[t], 2.0, 1e-12); // x stretched twice, y not
    }
}

TEST(Parameterize, BadUvsNameTheTriangleAndFallBackToTheAtlas) {
    mesh::Mesh outside = square();
    outside.uvs[2] = {1.5f, 1.0f};
    EXPECT_NE(texspace::uvProblem(outside).find("triangle 0: texture coordinate (1.5, 1)"),
              std::string::npos)
        << texspace::uvProblem(outside);
    mesh::Mesh overlapping = square();
    overlapping.uvs[3] = {1.0f, 0.2f}; // the second triangle folds over the first
    EXPECT_NE(texspace::uvProblem(overlapping).find("triangles 0 and 1 overlap"), std::string::npos)
        << texspace::uvProblem(overlapping);
    mesh::Mesh flat = square();
    flat.uvs[1] = {0.0f, 0.0f}; // triangle 0 collapses in the texture
    EXPECT_NE(texspace::uvProblem(flat).find("triangle 0: no area in the texture"),
              std::string::npos);
    mesh::Mesh none = square();
    none.uvs.clear();
    EXPECT_EQ(texspace::uvProblem(none), "the mesh has no texture coordinates");
    // the box's six faces all use [0, 1]²: they overlap, so the atlas is used with a note
    const texspace::Parameterization p = texspace::parameterize(mesh::makeBox(1, 2, 3), 256);
    EXPECT_FALSE(p.fromMesh);
    EXPECT_NE(p.note.find("overlap"), std::string::npos) << p.note;
    EXPECT_NE(p.note.find("atlas"), std::string::npos) << p.note;
}

TEST(Parameterize, TheAtlasIsValidKeepsItsGutterAndItsAreasAddUp) {
    std::vector<std::pair<const char*, mesh::Mesh>> shapes;
    shapes.emplace_back("sphere", mesh::makeUvSphere(24, 48));
    shapes.emplace_back("box", mesh::makeBox(1, 2, 3));
    shapes.emplace_back("torus", mesh::makeTorus(1.0, 0.3, 32, 16));
    shapes.emplace_back("bunny", mesh::loadObj(std::filesystem::path(BW_SOURCE_ROOT) /
                                               "third_party/bunny/bunny.obj"));
    for (const auto& [name, m] : shapes) {
        const int size = 2048;
        const texspace::Parameterization p = texspace::packAtlas(m, size);
        ASSERT_EQ(p.uv.size(), m.triangles.size()) << name;
        EXPECT_EQ(texspace::uvProblem(p.uv, p.areaSurface), "") << name;
        double sum = 0;
        for (size_t t = 0; t < p.uv.size(); ++t) {
            sum += p.areaTexture[t] * p.areaRatio(t);
            EXPECT_GE(p.stretch[t], 1.0 - 1e-9) << name << " " << t;
        }
        EXPECT_NEAR(sum, meshArea(m), 1e-9 * meshArea(m)) << name;
        // the gutter: every atlas triangle lies at least one texel inside its grid cell
        const double cell = 1.0 / p.gridCells, texel = 1.0 / size;
        for (size_t t = 0; t < p.uv.size(); ++t) {
            const size_t c = t / 2;
            const double x0 = double(c % size_t(p.gridCells)) * cell,
                         y0 = double(c / size_t(p.gridCells)) * cell;
            for (const auto& q : p.uv[t]) {
                ASSERT_GE(q.x - x0, texel * (1 - 1e-9)) << name << " " << t;
                ASSERT_GE(q.y - y0, texel * (1 - 1e-9)) << name << " " << t;
                ASSERT_GE(x0 + cell - q.x, texel * (1 - 1e-9)) << name << " " << t;
                ASSERT_GE(y0 + cell - q.y, texel * (1 - 1e-9)) << name << " " << t;
            }
        }
    }
}

TEST(Parameterize, AnEquilateralTriangleOnARightIsoscelesOneIsStretchedBySqrt3) {
    mesh::Mesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0.5f, float(std::sqrt(3.0) / 2), 0}};
    m.triangles = {{0, 1, 2}};
    const texspace::Parameterization p = texspace::packAtlas(m, 64);
    EXPECT_NEAR(p.stretch[0], std::sqrt(3.0), 1e-6);
    EXPECT_NEAR(p.areaSurface[0], std::sqrt(3.0) / 4, 1e-7);
}

TEST(Parameterize, AnAtlasThatCannotKeepItsGuttersIsRefused) {
    const mesh::Mesh m = mesh::makeUvSphere(64, 128); // ~16 000 triangles
    try {
        texspace::packAtlas(m, 16);
        ADD_FAILURE() << "accepted";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("texture larger than 16"), std::string::npos)
            << e.what();
    }
}

// ---- stages 1 and 2 on the CPU side (texspace/texture_space.h) --------------------------------

TEST(TextureSpace, TexelsCoverEveryTriangleOnceAndTheirAreasAddUp) {
    const mesh::Mesh m = mesh::makeUvSphere(12, 24);
    const texspace::Parameterization p = texspace::packAtlas(m, 512);
    const texspace::Texels t = texspace::rasterize(m, p, 512);
    // Σ over covered texels of A_texel · A_S/A_T estimates the surface area (midpoint rule over
    // the texture): within 2 % at 512² for this atlas (each triangle covers ~50 texels)
    const double texel = 1.0 / (512.0 * 512.0);
    double area = 0;
    std::vector<int> perTriangle(m.triangles.size(), 0);
    for (size_t k = 0; k < t.triangle.size(); ++k)
        if (t.triangle[k] >= 0) {
            area += texel * t.areaRatio[k];
            ++perTriangle[size_t(t.triangle[k])];
            EXPECT_NEAR(glm::length(t.position[k]), 0.5, 0.02); // on the sphere of radius 0.5
        }
    EXPECT_NEAR(area, meshArea(m), 0.02 * meshArea(m));
    for (size_t f = 0; f < perTriangle.size(); ++f)
        EXPECT_GT(perTriangle[f], 0) << f;
    EXPECT_EQ(size_t(std::count_if(t.triangle.begin(), t.triangle.end(),
                                   [](int32_t v) { return v >= 0; })),
              t.covered);
}

TEST(TextureSpace, ASharedEdgeBelongsToOneTriangle) {
    // the square's diagonal passes through texel centres of a 4 × 4 texture: the top-left rule
    // gives each to exactly one of the two triangles, so all 16 texels are covered once
    const texspace::Parameterization p = texspace::parameterize(square(), 4);
    ASSERT_TRUE(p.fromMesh);
    const texspace::Texels t = texspace::rasterize(square(), p, 4);
    EXPECT_EQ(t.covered, 16u);
}

TEST(TextureSpace, MipDescentDrawsTexelsInProportionToTheirWeight) {
    // Algorithm 3.1 on a 16 × 16 texture with random weights (some 0): chi-square of 2·10^5
    // draws against w_t/Σw, p-value threshold 1e-3 (normal approximation of χ² with ν dof)
    const int size = 16;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u01(0, 1);
    std::vector<double> w(size * size);
    for (double& x : w)
        x = u01(rng) < 0.2 ? 0.0 : u01(rng) * u01(rng);
    const texspace::MipCdf cdf = texspace::buildMipCdf(w, size);
    const int n = 200000;
    std::vector<double> count(w.size(), 0);
    for (int i = 0; i < n; ++i)
        count[texspace::sampleMip(cdf, u01(rng))] += 1;
    double chi2 = 0;
    int dof = -1;
    for (size_t k = 0; k < w.size(); ++k) {
        const double expected = n * w[k] / cdf.total();
        if (w[k] == 0) {
            EXPECT_EQ(count[k], 0) << "texel " << k << " has no weight";
            continue;
        }
        chi2 += (count[k] - expected) * (count[k] - expected) / expected;
        ++dof;
    }
    const double z = (chi2 - dof) / std::sqrt(2.0 * dof);
    EXPECT_LT(z, 3.09) << "chi2 " << chi2 << " dof " << dof;
    // the descent is monotone in u: u = 0 gives the first texel with weight
    const uint32_t first = texspace::sampleMip(cdf, 0.0);
    EXPECT_GT(w[first], 0.0);
}

TEST(TextureSpace, BadCdfInputsAreRefused) {
    EXPECT_THROW(texspace::buildMipCdf(std::vector<double>(9, 1.0), 3), core::Error);
    EXPECT_THROW(texspace::buildMipCdf(std::vector<double>(4, 0.0), 2), core::Error);
    EXPECT_THROW(texspace::buildMipCdf({1.0, -1.0, 1.0, 1.0}, 2), core::Error);
    EXPECT_THROW(texspace::buildMipCdf({1.0, NAN, 1.0, 1.0}, 2), core::Error);
}
