// Shared helpers for the bssrdf unit tests.
#pragma once

#include "bssrdf/bssrdf.h"
#include "core/core.h"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <string_view>

namespace bssrdf_test {

inline const std::string kPath = "materials/t.bssrdf";
inline const std::string kShader =
    "::begin shader\n"
    "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { return vec3(0.0); }\n"
    "::end shader\n";

inline std::string sourceRoot() {
    return BW_SOURCE_ROOT;
}

// The error parseModel throws for `text`, or nullopt (with a test failure) when it parses.
inline std::optional<core::Error> parseError(std::string_view text) {
    try {
        bssrdf::parseModel(text, kPath);
    } catch (const core::Error& e) {
        return e;
    }
    ADD_FAILURE() << "expected a parse error for:\n" << text;
    return std::nullopt;
}

// Asserts that parsing fails at `line` with a message containing `fragment`.
inline void expectParseError(std::string_view text, int line, std::string_view fragment) {
    SCOPED_TRACE(std::string(text));
    auto e = parseError(text);
    if (!e) return;
    EXPECT_EQ(e->file(), kPath);
    EXPECT_EQ(e->line(), line) << e->what();
    EXPECT_NE(e->message().find(fragment), std::string::npos)
        << "message: " << e->message() << "\nexpected fragment: " << fragment;
}

// 1-based number of the first line of `text` that contains `needle` (0 when none).
inline int lineContaining(std::string_view text, std::string_view needle) {
    int line = 1;
    size_t start = 0;
    while (start <= text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        if (text.substr(start, end - start).find(needle) != std::string_view::npos) return line;
        ++line;
        start = end + 1;
    }
    return 0;
}

} // namespace bssrdf_test
