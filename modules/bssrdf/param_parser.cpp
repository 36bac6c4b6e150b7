// The 'parameters' section of a .bssrdf file (thesis Appendix A.2), plus identifier rules.
#include "bssrdf/detail/param_parser.h"

#include "bssrdf/detail/text_lines.h"
#include "core/core.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <string_view>

namespace bssrdf {

namespace {

// GLSL 4.50 keywords and reserved words (spec section 3.6); a parameter becomes a uniform,
// so none of these can be a parameter name.
constexpr std::string_view kGlslKeywords[] = {
    "const",         "uniform",    "buffer",    "shared",    "attribute",     "varying",
    "coherent",      "volatile",   "restrict",  "readonly",  "writeonly",     "atomic_uint",
    "layout",        "centroid",   "flat",      "smooth",    "noperspective", "patch",
    "sample",        "invariant",  "precise",   "break",     "continue",      "do",
    "for",           "while",      "switch",    "case",      "default",       "if",
    "else",          "subroutine", "in",        "out",       "inout",         "int",
    "void",          "bool",       "true",      "false",     "float",         "double",
    "discard",       "return",     "vec2",      "vec3",      "vec4",          "ivec2",
    "ivec3",         "ivec4",      "bvec2",     "bvec3",     "bvec4",         "uint",
    "uvec2",         "uvec3",      "uvec4",     "dvec2",     "dvec3",         "dvec4",
    "mat2",          "mat3",       "mat4",      "mat2x2",    "mat2x3",        "mat2x4",
    "mat3x2",        "mat3x3",     "mat3x4",    "mat4x2",    "mat4x3",        "mat4x4",
    "dmat2",         "dmat3",      "dmat4",     "lowp",      "mediump",       "highp",
    "precision",     "sampler1D",  "sampler2D", "sampler3D", "samplerCube",   "image1D",
    "image2D",       "image3D",    "struct",    "common",    "partition",     "active",
    "asm",           "class",      "union",     "enum",      "typedef",       "template",
    "this",          "resource",   "goto",      "inline",    "noinline",      "public",
    "static",        "extern",     "external",  "interface", "long",          "short",
    "half",          "fixed",      "unsigned",  "superp",    "input",         "output",
    "hvec2",         "hvec3",      "hvec4",     "fvec2",     "fvec3",         "fvec4",
    "sampler3DRect", "filter",     "sizeof",    "cast",      "namespace",     "using"};

[[noreturn]] void fail(const std::string& path, int line, std::string message) {
    throw core::Error(path, line, std::move(message));
}

// Parses a whole token as a finite float (locale independent); throws otherwise.
float parseNumber(std::string_view tok, std::string_view what, const std::string& path, int line) {
    std::string_view digits = tok;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    float v = 0;
    auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (ec == std::errc::result_out_of_range)
        fail(path, line,
             std::string(what) + " " + detail::inQuotes(tok) + " is not a finite number");
    if (ec != std::errc() || ptr != digits.data() + digits.size() || digits.empty())
        fail(path, line, std::string(what) + " " + detail::inQuotes(tok) + " is not a number");
    if (!std::isfinite(v))
        fail(path, line,
             std::string(what) + " " + detail::inQuotes(tok) + " is not a finite number");
    return v;
}

void checkFieldCount(const std::vector<std::string_view>& tok, size_t expected,
                     std::string_view form, const std::string& path, int line) {
    if (tok.size() == expected) return;
    const bool few = tok.size() < expected;
    fail(path, line,
         std::string(few ? "too few" : "too many") + " fields for a " + std::string(tok[0]) +
             " parameter: expected '" + std::string(form) + "' (" + std::to_string(expected) +
             " fields), found " + std::to_string(tok.size()));
}

void checkName(std::string_view name, const std::string& path, int line) {
    if (!isValidIdentifier(name)) {
        std::string why = "must match [A-Za-z_][A-Za-z0-9_]*, not start with 'gl_', not "
                          "contain '__' and not be a GLSL keyword";
        fail(path, line, "invalid parameter name " + detail::inQuotes(name) + ": " + why);
    }
    const auto& builtins = builtinNames();
    if (std::find(builtins.begin(), builtins.end(), name) != builtins.end()) {
        std::string list;
        for (const auto& b : builtins)
            list += (list.empty() ? "" : ", ") + b;
        fail(path, line,
             "parameter name " + detail::inQuotes(name) + " clashes with a built-in name (" + list +
                 ")");
    }
}

Param parseLine(const std::vector<std::string_view>& tok, const std::string& path, int line) {
    Param p;
    p.line = line;
    const std::string_view type = tok[0];
    if (type == "float") {
        p.type = ParamType::Float;
        checkFieldCount(tok, 5, "float NAME MIN MAX DEFAULT", path, line);
    } else if (type == "bool") {
        p.type = ParamType::Bool;
        checkFieldCount(tok, 3, "bool NAME DEFAULT", path, line);
    } else if (type == "color") {
        p.type = ParamType::Color;
        checkFieldCount(tok, 5, "color NAME R G B", path, line);
    } else {
        fail(path, line,
             "unknown parameter type " + detail::inQuotes(type) +
                 " (expected float, bool or color)");
    }
    checkName(tok[1], path, line);
    p.name = std::string(tok[1]);

    if (p.type == ParamType::Float) {
        p.min = parseNumber(tok[2], "minimum", path, line);
        p.max = parseNumber(tok[3], "maximum", path, line);
        float def = parseNumber(tok[4], "default", path, line);
        if (p.min > p.max)
            fail(path, line,
                 "minimum " + detail::inQuotes(tok[2]) + " is greater than maximum " +
                     detail::inQuotes(tok[3]));
        if (def < p.min || def > p.max)
            fail(path, line,
                 "default " + detail::inQuotes(tok[4]) + " is outside [" + std::string(tok[2]) +
                     ", " + std::string(tok[3]) + "]");
        p.value = {def, 0, 0};
    } else if (p.type == ParamType::Bool) {
        const std::string_view d = tok[2];
        if (d == "true" || d == "1")
            p.value = {1, 0, 0};
        else if (d == "false" || d == "0")
            p.value = {0, 0, 0};
        else
            fail(path, line,
                 "invalid bool default " + detail::inQuotes(d) + " (expected true, false, 1 or 0)");
    } else {
        const char* names[3] = {"red", "green", "blue"};
        float hi = 1;
        for (int c = 0; c < 3; ++c) {
            p.value[c] = parseNumber(tok[2 + c], names[c], path, line);
            hi = std::max(hi, p.value[c]);
        }
        p.min = 0;
        p.max = hi; // UI range; colours are not clamped to [0,1]
    }
    return p;
}

} // namespace

const std::vector<std::string>& builtinNames() {
    // clang-format off
    static const std::vector<std::string> names = {
        "SigmaA", "SigmaS", "G", "IOR", "Scale", "PI",
        "Bssrdf", "DiffuseReflectance", "init", "main",
        "SampleRadius", "PdfRadius", "MaxRadius", "QdLobeCount", "QdLobe"};
    // clang-format on
    return names;
}

bool isValidIdentifier(std::string_view name) {
    if (name.empty()) return false;
    auto alpha = [](char c) {
        return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
    };
    auto digit = [](char c) { return c >= '0' && c <= '9'; };
    if (!alpha(name[0])) return false;
    for (char c : name)
        if (!alpha(c) && !digit(c)) return false;
    if (name.starts_with("gl_")) return false;
    if (name.find("__") != std::string_view::npos) return false;
    for (std::string_view k : kGlslKeywords)
        if (k == name) return false;
    return true;
}

namespace detail {

std::vector<Param> parseParameters(const Section& section, const std::string& path) {
    std::vector<Param> params;
    std::map<std::string, int, std::less<>> seen; // name -> line
    const auto lines = splitLines(section.code);
    for (size_t i = 0; i < lines.size(); ++i) {
        const int line = section.firstLine + static_cast<int>(i);
        std::string_view text = lines[i];
        if (size_t hash = text.find('#'); hash != std::string_view::npos)
            text = text.substr(0, hash); // '#' starts a comment
        const auto tok = tokenize(text);
        if (tok.empty()) continue;
        Param p = parseLine(tok, path, line);
        if (auto it = seen.find(p.name); it != seen.end())
            fail(path, line,
                 "duplicate parameter " + detail::inQuotes(p.name) + " (first declared at line " +
                     std::to_string(it->second) + ")");
        seen.emplace(p.name, line);
        params.push_back(std::move(p));
    }
    return params;
}

} // namespace detail
} // namespace bssrdf
