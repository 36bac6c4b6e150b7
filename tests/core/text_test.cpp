#include "core/core.h"

#include <gtest/gtest.h>

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
