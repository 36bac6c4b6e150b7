// irradiance environment maps (no GL):
//   - Ft against pathtrace::fresnelDielectric (independent implementation);
//   - quadrature nodes: Σ Ω = 4π, the lat-long direction convention, the 2 × 2 reduction keeps
//     ∫ L dω, black texels dropped;
//   - environment samples: weights of a constant map are exactly 4π·L, the estimator of ∫ L dω
//     over a random map within a z bound, determinism, every prefix unbiased in expectation;
//   - EXR round trip; the shipped default sky matches its generator;
//   - bad files: missing, not EXR, truncated, without R/G/B, NaN, negative — each a core::Error
//     naming the file.
#include "core/core.h"
#include "irradiance/env_sampling.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <numbers>

namespace {
namespace fs = std::filesystem;
using namespace irradiance;
constexpr double kPi = std::numbers::pi;

fs::path shippedSky() {
    return fs::path(BW_SOURCE_ROOT) / "materials/env/default_sky.exr";
}

EnvironmentMap randomEnv(int w, int h, uint32_t seed) {
    EnvironmentMap e;
    e.width = w;
    e.height = h;
    uint32_t s = seed;
    for (int i = 0; i < 3 * w * h; ++i) {
        s = s * 1664525u + 1013904223u;
        e.rgb.push_back(static_cast<float>((s >> 8) * (1.0 / 16777216.0)) * 2.0f);
    }
    return e;
}

double integral(const EnvironmentMap& e, int c) {
    double s = 0;
    for (int y = 0; y < e.height; ++y)
        for (int x = 0; x < e.width; ++x)
            s += e.texel(x, y)[c] * texelSolidAngle(y, e.width, e.height);
    return s;
}

void expectErrorNaming(const fs::path& p, const std::string& reason) {
    try {
        readEnvironment(p);
        ADD_FAILURE() << "no error for " << p;
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), p.string());
        EXPECT_NE(e.message().find(reason), std::string::npos) << e.message();
    }
}

TEST(IrradianceFresnel, TransmittanceIsOneMinusExactReflectance) {
    for (double eta : {1.0, 1.3, 1.5, 2.4})
        for (int i = 0; i <= 100; ++i) {
            const double mu = i / 100.0;
            const double ref = mu == 0 ? 0.0 : 1.0 - pathtrace::fresnelDielectric(mu, eta);
            EXPECT_NEAR(fresnelTransmittance(mu, eta), ref, 1e-14) << eta << " " << mu;
        }
    EXPECT_EQ(fresnelTransmittance(-0.5, 1.3), 0.0);
}

TEST(IrradianceEnvironment, QuadratureNodesCoverTheSphere) {
    const EnvironmentMap e = irrtest::constantEnv(64, 32, glm::vec3(1.0f));
    const auto nodes = quadratureNodes(e, 2);
    ASSERT_EQ(nodes.size(), 64u * 32u * 4u);
    double total = 0;
    glm::dvec3 mean(0.0);
    for (const auto& n : nodes) {
        total += n.weight.r;
        mean += glm::dvec3(n.direction) * double(n.weight.r);
        EXPECT_NEAR(glm::length(n.direction), 1.0f, 1e-6f);
    }
    EXPECT_NEAR(total, 4.0 * kPi, 1e-4);       // Σ Ω = 4π (float weights)
    EXPECT_NEAR(glm::length(mean), 0.0, 1e-4); // symmetric
    // convention: texel (0, 0) is at the zenith, φ just above 0: +x side of the top
    EXPECT_GT(nodes.front().direction.y, 0.99f);
    EXPECT_GT(nodes.front().direction.x, 0.0f);
    EXPECT_NEAR(latLongDirection(kPi / 2, kPi / 2).z, 1.0f, 1e-7f);
    EXPECT_NEAR(latLongDirection(kPi / 2, 0).x, 1.0f, 1e-7f);
}

TEST(IrradianceEnvironment, ReductionKeepsTheIntegralAndBlackTexelsAreDropped) {
    const EnvironmentMap e = randomEnv(64, 32, 7);
    for (int c = 0; c < 3; ++c) {
        double full = 0, reduced = 0;
        for (const auto& n : quadratureNodes(e, 1, 256))
            full += n.weight[c];
        for (const auto& n : quadratureNodes(e, 1, 16)) // 64 -> 32 -> 16 wide
            reduced += n.weight[c];
        EXPECT_NEAR(reduced, integral(e, c), 1e-5 * integral(e, c));
        EXPECT_NEAR(full, integral(e, c), 1e-5 * integral(e, c));
    }
    EXPECT_EQ(quadratureNodes(e, 1, 16).size(), 16u * 8u);
    EnvironmentMap half = irrtest::constantEnv(8, 4, glm::vec3(1.0f));
    for (int i = 0; i < 8 * 2 * 3; ++i)
        half.rgb[3 * 8 * 2 + i] = 0.0f; // bottom two rows black
    for (const auto& n : quadratureNodes(half, 2))
        EXPECT_GT(n.direction.y, 0.0f);
    EXPECT_EQ(quadratureNodes(half, 2).size(), 8u * 2u * 4u);
}

TEST(IrradianceEnvironment, WorldRotation) {
    const glm::mat3 R = worldFromEnvironment(static_cast<float>(kPi / 2));
    const glm::vec3 x = R * glm::vec3(1, 0, 0), z = R * glm::vec3(0, 0, 1);
    EXPECT_NEAR(x.z, -1.0f, 1e-6f);
    EXPECT_NEAR(z.x, 1.0f, 1e-6f);
}

TEST(IrradianceSampling, ConstantMapGivesUniformWeights) {
    const EnvironmentMap e = irrtest::constantEnv(16, 8, glm::vec3(0.5f, 1.0f, 2.0f));
    for (const auto& s : sampleEnvironment(e, 200, 3)) {
        EXPECT_NEAR(s.pdf, 1.0 / (4 * kPi), 1e-6);
        EXPECT_NEAR(s.weight.g, 4 * kPi, 4 * kPi * 1e-5);
        EXPECT_NEAR(s.weight.b, 8 * kPi, 8 * kPi * 1e-5);
        EXPECT_NEAR(glm::length(s.direction), 1.0f, 1e-6f);
    }
}

TEST(IrradianceSampling, EstimatesTheIntegralAndIsDeterministic) {
    EnvironmentMap e = randomEnv(32, 16, 11);
    // a bright spot, so importance sampling matters
    for (int c = 0; c < 3; ++c)
        e.rgb[3 * (5 * 32 + 9) + c] = 500.0f;
    const int K = 4000;
    const auto a = sampleEnvironment(e, K, 42), b = sampleEnvironment(e, K, 42);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
        EXPECT_EQ(std::memcmp(&a[i], &b[i], sizeof(EnvSample)), 0);
    const auto other = sampleEnvironment(e, K, 43);
    EXPECT_NE(std::memcmp(&a[0], &other[0], sizeof(EnvSample)), 0);
    // whole set and the first K/4 (a random subset of strata): z against ∫ L dω with the iid
    // standard error (conservative under stratification); 6 tests, |z| < 4
    for (int c = 0; c < 3; ++c)
        for (int n : {K, K / 4}) {
            double s = 0, s2 = 0;
            for (int k = 0; k < n; ++k) {
                s += a[k].weight[c];
                s2 += double(a[k].weight[c]) * a[k].weight[c];
            }
            const double mean = s / n, se = std::sqrt((s2 / n - mean * mean) / (n - 1));
            EXPECT_LT(std::abs(mean - integral(e, c)) / se, 4.0) << c << " " << n;
        }
}

TEST(IrradianceEnvironmentFile, RoundTripAndShippedDefaultSky) {
    const fs::path dir = irrtest::tempDir("env");
    if (std::getenv("BW_REGENERATE_DEFAULT_SKY")) writeDefaultEnvironment(shippedSky());
    const EnvironmentMap e = randomEnv(20, 10, 5);
    writeEnvironment(dir / "r.exr", e);
    const EnvironmentMap r = readEnvironment(dir / "r.exr");
    EXPECT_EQ(r.width, 20);
    EXPECT_EQ(r.height, 10);
    EXPECT_EQ(r.rgb, e.rgb);

    ASSERT_TRUE(fs::exists(shippedSky())) << "regenerate with BW_REGENERATE_DEFAULT_SKY=1";
    EXPECT_LT(fs::file_size(shippedSky()), 200u * 1024u);
    const EnvironmentMap shipped = readEnvironment(shippedSky());
    const EnvironmentMap gen = makeDefaultSky();
    ASSERT_EQ(shipped.width, 128);
    ASSERT_EQ(shipped.height, 64);
    for (size_t i = 0; i < gen.rgb.size(); ++i)
        ASSERT_NEAR(shipped.rgb[i], gen.rgb[i], 1e-5f * (1.0f + gen.rgb[i])) << i;
    // sky above, darker ground, the sun the brightest texel at elevation 35°, azimuth 30°
    size_t best = 0;
    for (size_t i = 0; i < gen.rgb.size(); i += 3)
        if (gen.rgb[i] > gen.rgb[best]) best = i;
    const int bx = static_cast<int>(best / 3 % 128), by = static_cast<int>(best / 3 / 128);
    EXPECT_NEAR((by + 0.5) * 180.0 / 64, 55.0, 180.0 / 64);
    EXPECT_NEAR((bx + 0.5) * 360.0 / 128, 30.0, 360.0 / 128);
    EXPECT_GT(gen.texel(64, 10).b, gen.texel(64, 60).b * 3);
}

TEST(IrradianceEnvironmentFile, BadFilesAreClearErrors) {
    const fs::path dir = irrtest::tempDir("bad");
    expectErrorNaming(dir / "missing.exr", "");
    { std::ofstream(dir / "text.exr") << "this is not an EXR file\n"; }
    expectErrorNaming(dir / "text.exr", "cannot read EXR");
    writeDefaultEnvironment(dir / "full.exr");
    const std::string bytes = core::readFile(dir / "full.exr");
    core::writeFile(dir / "truncated.exr", bytes.substr(0, bytes.size() / 2));
    expectErrorNaming(dir / "truncated.exr", "cannot read EXR");
    irrtest::writeRawExr(dir / "y.exr", 4, 2, {"Y"}, std::vector<float>(8, 1.0f));
    expectErrorNaming(dir / "y.exr", "no channel 'R'");
    irrtest::writeRawExr(dir / "rg.exr", 4, 2, {"R", "G"}, std::vector<float>(16, 1.0f));
    expectErrorNaming(dir / "rg.exr", "no channel 'B'");
    std::vector<float> v(24, 1.0f);
    v[3 * 5 + 1] = std::nanf("");
    irrtest::writeRawExr(dir / "nan.exr", 4, 2, {"R", "G", "B"}, v);
    expectErrorNaming(dir / "nan.exr", "non-finite radiance at texel (1, 1) channel G");
    v[3 * 5 + 1] = 1.0f;
    v[3 * 2 + 2] = -0.5f;
    irrtest::writeRawExr(dir / "neg.exr", 4, 2, {"R", "G", "B"}, v);
    expectErrorNaming(dir / "neg.exr", "negative radiance at texel (2, 0) channel B");
    v[3 * 2 + 2] = INFINITY;
    irrtest::writeRawExr(dir / "inf.exr", 4, 2, {"R", "G", "B"}, v);
    expectErrorNaming(dir / "inf.exr", "non-finite");
}

} // namespace
