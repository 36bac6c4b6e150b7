// Material parameters: validation messages, presets file, derived quantities, swatch.
#include "core/color.h"
#include "core/core.h"
#include "material/material.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {
std::string errorOf(const material::MaterialParams& p) {
    try {
        material::validate(p);
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}
} // namespace

TEST(MaterialParams, ValidationNamesFieldAndChannel) {
    material::MaterialParams p;
    EXPECT_EQ(errorOf(p), "");
    p.sigmaA = {0, 0, 0}; // Spectralon: no absorption is valid
    EXPECT_EQ(errorOf(p), "");
    p.sigmaA.y = -0.1;
    EXPECT_NE(errorOf(p).find("sigma_a must be >= 0"), std::string::npos);
    EXPECT_NE(errorOf(p).find("channel G"), std::string::npos);
    p = {};
    p.sigmaS.z = 0.0;
    EXPECT_NE(errorOf(p).find("sigma_s must be > 0"), std::string::npos);
    EXPECT_NE(errorOf(p).find("channel B"), std::string::npos);
    p = {};
    p.sigmaS.x = NAN;
    EXPECT_NE(errorOf(p).find("finite"), std::string::npos);
    p = {};
    p.sigmaA.x = INFINITY;
    EXPECT_NE(errorOf(p).find("finite"), std::string::npos);
    p = {};
    p.eta = 0.0;
    EXPECT_NE(errorOf(p).find("eta"), std::string::npos);
    p.eta = -1.3;
    EXPECT_NE(errorOf(p).find("eta"), std::string::npos);
    p = {};
    p.g = 1.0;
    EXPECT_NE(errorOf(p).find("|g| < 1"), std::string::npos);
    p.g = -1.0;
    EXPECT_NE(errorOf(p).find("|g| < 1"), std::string::npos);
    p.g = 0.99;
    EXPECT_EQ(errorOf(p), "");
}

TEST(MaterialParams, PresetsMatchJensen2001) {
    auto presets = material::loadPresets(std::string(BW_SOURCE_ROOT) + "/materials/presets.json");
    ASSERT_EQ(presets.size(), 12u);
    const auto* marble = material::findPreset(presets, "Marble");
    ASSERT_NE(marble, nullptr);
    EXPECT_DOUBLE_EQ(marble->sigmaSPrime.x, 2.19);
    EXPECT_DOUBLE_EQ(marble->sigmaA.z, 0.0071);
    EXPECT_DOUBLE_EQ(marble->eta, 1.3);
    const auto* ketchup = material::findPreset(presets, "Ketchup");
    ASSERT_NE(ketchup, nullptr);
    EXPECT_DOUBLE_EQ(ketchup->sigmaA.y, 0.97);
    // σs = σ′s / (1 − g)
    material::MaterialParams base;
    base.g = 0.5;
    auto p = material::applyPreset(*marble, base);
    EXPECT_DOUBLE_EQ(p.sigmaS.x, 2.19 / 0.5);
    EXPECT_DOUBLE_EQ(p.g, 0.5);
    for (const auto& pr : presets)
        EXPECT_NO_THROW(material::validate(material::applyPreset(pr, {})));
}

TEST(MaterialParams, BadPresetFileNamesLine) {
    auto dir = std::filesystem::temp_directory_path() / "bw_presets_test";
    std::filesystem::create_directories(dir);
    core::writeFile(dir / "p.json", "{\n \"presets\": [\n  {\"name\": \"x\",, }\n ]\n}\n");
    try {
        material::loadPresets(dir / "p.json");
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_EQ(e.line(), 3);
        EXPECT_NE(std::string(e.what()).find("p.json:3"), std::string::npos);
    }
}

TEST(MaterialParams, DerivedQuantities) {
    material::MaterialParams p;
    p.sigmaA = glm::dvec3(0.01);
    p.sigmaS = glm::dvec3(2.0);
    p.g = 0.5; // σ′s = 1, σ′t = 1.01
    auto a = material::reducedAlbedo(p);
    EXPECT_NEAR(a.x, 1.0 / 1.01, 1e-15);
    auto ld = material::diffuseMeanFreePath(p);
    EXPECT_NEAR(ld.x, 1.0 / std::sqrt(3 * 0.01 * 1.01), 1e-12);
    p.sigmaA = glm::dvec3(0.0);
    EXPECT_TRUE(std::isinf(material::diffuseMeanFreePath(p).x));
}

TEST(MaterialParams, SwatchHasLuminance075) {
    glm::dvec3 s = material::swatch({2.19, 2.62, 3.0});
    EXPECT_NEAR(core::luminance(s), 0.75, 1e-12);
    EXPECT_NEAR(s.x / s.y, 2.19 / 2.62, 1e-12); // hue kept
    glm::dvec3 z = material::swatch({0, 0, 0});
    EXPECT_NEAR(core::luminance(z), 0.75, 1e-12);
}
