#include "core/color.h"
#include "core/core.h"
#include "core/text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

TEST(CoreText, Utf8Validation) {
    EXPECT_FALSE(core::firstInvalidUtf8("plain ascii\n").has_value());
    EXPECT_FALSE(core::firstInvalidUtf8("σ′ and ü").has_value());
    EXPECT_EQ(core::firstInvalidUtf8(std::string_view("ab\xff", 3)), 2u);
    EXPECT_EQ(core::firstInvalidUtf8(std::string_view("a\0b", 3)), 1u);      // NUL → binary
    EXPECT_EQ(core::firstInvalidUtf8(std::string_view("\xc0\xaf", 2)), 0u);  // overlong
    EXPECT_EQ(core::firstInvalidUtf8(std::string_view("x\xe2\x82", 3)), 1u); // truncated
}

TEST(CoreText, LineOfOffset) {
    EXPECT_EQ(core::lineOfOffset("a\nb\nc", 0), 1);
    EXPECT_EQ(core::lineOfOffset("a\nb\nc", 2), 2);
    EXPECT_EQ(core::lineOfOffset("a\nb\nc", 4), 3);
}

TEST(CoreText, HashIsStableFnv1a) {
    // FNV-1a 64 reference values (Fowler/Noll/Vo test vectors).
    EXPECT_EQ(core::fnv1a64(""), 0xcbf29ce484222325ull);
    EXPECT_EQ(core::fnv1a64("a"), 0xaf63dc4c8601ec8cull);
    EXPECT_EQ(core::hashHex("a"), "fnv1a64:af63dc4c8601ec8c");
}

TEST(CoreText, ErrorsNameFileAndLine) {
    core::Error e("materials/x.bssrdf", 7, "bad thing");
    EXPECT_STREQ(e.what(), "materials/x.bssrdf:7: bad thing");
    EXPECT_THROW(core::readFile("/nonexistent/file.txt"), core::Error);
    try {
        core::writeFile("/proc/definitely/not/here.csv", "x");
        FAIL();
    } catch (const core::Error& err) {
        EXPECT_NE(std::string(err.what()).find("/proc/definitely/not/here.csv"), std::string::npos);
    }
}

TEST(CoreText, FormatNumberIsPrintfG) {
    EXPECT_EQ(core::formatNumber(0.1f), "0.100000001"); // 9 digits show a float exactly
    EXPECT_EQ(core::formatNumber(1.0 / 3.0, 6), "0.333333");
    EXPECT_EQ(core::formatNumber(1e-5, 3), "1e-05");
    EXPECT_EQ(core::formatNumber(123456789.0, 4), "1.235e+08");
    EXPECT_EQ(core::formatNumber(0.1, 17), "0.10000000000000001");
    EXPECT_EQ(core::formatNumber(-2.5), "-2.5");
}

TEST(CoreText, FormatShortestRoundTrips) {
    EXPECT_EQ(core::formatShortest(0.1), "0.1");
    EXPECT_EQ(core::formatShortest(1e-300), "1e-300");
    EXPECT_EQ(core::formatShortest(-0.0), "-0");
    EXPECT_EQ(core::formatShortest(std::nan("")), "nan");
    EXPECT_EQ(core::formatShortest(-std::nan("")), "nan");
    EXPECT_EQ(core::formatShortest(INFINITY), "inf");
    EXPECT_EQ(core::formatShortest(-INFINITY), "-inf");
    for (double v : {1.0 / 3.0, 2.0 / 7.0 * 1e17, 5e-324, 1.7976931348623157e308}) {
        const std::string s = core::formatShortest(v);
        EXPECT_EQ(std::strtod(s.c_str(), nullptr), v) << s;
    }
    std::string out = "x=";
    core::appendShortest(out, 0.25);
    EXPECT_EQ(out, "x=0.25");
}

TEST(CoreColor, Rec709Luminance) {
    EXPECT_DOUBLE_EQ(core::luminance(glm::dvec3(1.0)), 1.0);
    EXPECT_DOUBLE_EQ(core::luminance(glm::dvec3(0, 1, 0)), 0.7152);
    EXPECT_EQ(core::luminance(glm::vec3(1, 0, 0)), 0.2126f);
    EXPECT_EQ(core::luminance(glm::vec3(0, 0, 2)), 2 * 0.0722f);
}
