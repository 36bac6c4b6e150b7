// Lit-sphere image helpers: merging passes, display mapping, difference view, readouts.
#include "pipeline/image_display.h"

#include "core/color.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {
pathtrace::Image flat(float value, float variance, uint64_t samples) {
    pathtrace::Image img;
    img.width = 4;
    img.height = 2;
    img.mean.assign(24, value);
    img.variance.assign(24, variance);
    img.samples = samples;
    return img;
}
} // namespace

TEST(ImageView, CombineWeightsBySampleCount) {
    // two independent passes: 100 samples with mean 1, 300 with mean 2
    auto c = app::combine(flat(1.0f, 0.04f, 100), flat(2.0f, 0.01f, 300));
    EXPECT_EQ(c.samples, 400u);
    EXPECT_FLOAT_EQ(c.mean[5], 1.75f);
    // variance of the mean: (100² · 0.04 + 300² · 0.01) / 400² = (400 + 900) / 160000
    EXPECT_FLOAT_EQ(c.variance[5], 1300.0f / 160000.0f);
    // merging equal halves of per-sample variance σ²: σ²/n_a → σ²/(n_a + n_b)
    auto h = app::combine(flat(1.0f, 1.0f / 50, 50), flat(1.0f, 1.0f / 50, 50));
    EXPECT_FLOAT_EQ(h.variance[0], 1.0f / 100);
    EXPECT_EQ(app::combine(pathtrace::Image{}, flat(3, 0, 7)).mean[0], 3.0f);
}

TEST(ImageView, TonemapExposureAndGamma) {
    auto img = flat(0.25f, 0, 1);
    auto px = app::tonemap(img, 1.0f, 1.0f); // 0.25 · 2 = 0.5
    EXPECT_EQ(px[0], 128);
    EXPECT_EQ(px[3], 255);
    px = app::tonemap(img, 2.0f, 2.0f); // (0.25 · 4)^(1/2) = 1
    EXPECT_EQ(px[1], 255);
    px = app::tonemap(img, 0.0f, 2.0f); // 0.25^(1/2) = 0.5
    EXPECT_EQ(px[2], 128);
    // a NaN or infinite value in any channel shows magenta
    for (float bad : {std::nanf(""), INFINITY, -INFINITY}) {
        auto im = flat(0.25f, 0, 1);
        im.mean[1] = bad;
        px = app::tonemap(im, 0.0f, 1.0f);
        EXPECT_EQ(px[0], 255);
        EXPECT_EQ(px[1], 0);
        EXPECT_EQ(px[2], 255);
    }
}

TEST(ImageView, DifferenceIsSignedAndReadoutHasStderr) {
    auto a = flat(1.0f, 0.04f, 10), b = flat(0.5f, 0.0f, 10);
    EXPECT_NEAR(app::maxAbsDifference(a, b), 0.5f, 1e-6);
    auto d = app::differenceMap(a, b, 0.5f);
    EXPECT_EQ(d[0], 255); // positive: red at full range
    EXPECT_LT(d[2], 60);
    auto e = app::differenceMap(b, a, 0.5f);
    EXPECT_EQ(e[2], 255); // negative: blue
    auto withNaN = a;
    withNaN.mean[0] = std::nanf(""); // a NaN difference shows magenta, like a NaN pixel
    auto m = app::differenceMap(withNaN, b, 0.5f);
    EXPECT_EQ(m[0], 255);
    EXPECT_EQ(m[1], 0);
    EXPECT_EQ(m[2], 255);
    auto v = app::pixelAt(a, 3, 1);
    ASSERT_TRUE(v.valid);
    EXPECT_FLOAT_EQ(v.mean[0], 1.0f);
    EXPECT_FLOAT_EQ(v.stderr_[0], 0.2f);
    EXPECT_FALSE(app::pixelAt(a, 4, 0).valid);
}

// z = ΔL / √(Var L_a + Var L_b): 0.5 / √(0.04) = 2.5 standard errors (channels equal, so the
// luminance's variance is Σ w² · 0.04); full colour at z = zRange, grey within 2.
TEST(ImageView, ZMapWeighsTheDifferenceByTheNoise) {
    const auto a = flat(1.0f, 0.04f, 10), b = flat(0.5f, 0.0f, 10);
    double w2 = 0;
    for (double w : core::kRec709Luminance)
        w2 += w * w;
    const float z = float(0.5 / std::sqrt(0.04 * w2));
    ASSERT_GT(z, 2.0f);
    auto m = app::zMap(a, b, z); // exactly at full colour: red
    EXPECT_EQ(m[0], 255);
    EXPECT_LT(m[2], 60);
    auto half = app::zMap(b, a, 2 * z); // negative, half way: blue, not saturated
    EXPECT_GT(half[2], half[0]);
    EXPECT_LT(half[2], 255);
    // within 2 standard errors: grey
    const auto close = flat(0.55f, 0.04f, 10);
    auto g = app::zMap(close, b, 4.0f);
    EXPECT_EQ(g[0], 90);
    EXPECT_EQ(g[1], 90);
    // black where both are black; magenta where they differ without any variance
    auto zero = app::zMap(flat(0, 0, 10), flat(0, 0, 10), 4.0f);
    EXPECT_EQ(zero[0] + zero[1] + zero[2], 0);
    auto exact = app::zMap(flat(1, 0, 10), flat(0.5f, 0, 10), 4.0f);
    EXPECT_EQ(exact[0], 255);
    EXPECT_EQ(exact[1], 0);
    EXPECT_EQ(exact[2], 255);
}

TEST(ImageView, RelativeStandardErrorIsTheMedianOverLitPixels) {
    auto img = flat(2.0f, 0.04f, 10); // se 0.2 per channel, equal channels: √(Σw²)·0.2 / 2
    double w2 = 0, w = 0;
    for (double c : core::kRec709Luminance) {
        w2 += c * c;
        w += c;
    }
    EXPECT_NEAR(app::relativeStandardError(img), std::sqrt(w2) * 0.2 / (2.0 * w), 1e-6);
    for (int c = 0; c < 3; ++c) // one dark pixel does not count
        img.mean[size_t(c)] = 0;
    EXPECT_NEAR(app::relativeStandardError(img), std::sqrt(w2) * 0.2 / (2.0 * w), 1e-6);
    EXPECT_TRUE(std::isnan(app::relativeStandardError(flat(0, 0, 1))));
}
