// bssrdf/detail: small text helpers shared by the parser and the GLSL assembler.
#pragma once

#include "shader/assembly.h"

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace bssrdf::detail {

// Lines numbered as the shader assembler numbers them (the #line directives point into them).
using shader::splitLines;

inline bool isBlank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

inline std::string_view trim(std::string_view s) {
    while (!s.empty() && isBlank(s.front()))
        s.remove_prefix(1);
    while (!s.empty() && isBlank(s.back()))
        s.remove_suffix(1);
    return s;
}

// Whitespace-separated tokens.
inline std::vector<std::string_view> tokenize(std::string_view s) {
    std::vector<std::string_view> out;
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && isBlank(s[i]))
            ++i;
        size_t j = i;
        while (j < s.size() && !isBlank(s[j]))
            ++j;
        if (j > i) out.push_back(s.substr(i, j - i));
        i = j;
    }
    return out;
}

// 'text' in single quotes, as messages quote what they name.
inline std::string inQuotes(std::string_view s) {
    std::string out;
    out.reserve(s.size() + 2);
    out += '\'';
    out.append(s);
    out += '\'';
    return out;
}

// A GLSL float literal of v: 9 significant digits (every float exactly), always with a '.' or
// an exponent so that GLSL reads it as a float.
inline std::string glslFloat(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.9g", v);
    std::string s = b;
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
}

} // namespace bssrdf::detail
