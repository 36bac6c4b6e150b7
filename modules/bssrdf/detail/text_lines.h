// bssrdf/detail: small text helpers shared by the parser and the GLSL assembler.
#pragma once

#include "shader/assembly.h"

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

} // namespace bssrdf::detail
