// Driver info-log parsing (Mesa, NVIDIA, glslang/AMD, Intel) mapped through a SourceMap.
#include "shader/diagnostics.h"

#include <algorithm>
#include <cctype>
#include <regex>
#include <string>
#include <vector>

namespace shader {

namespace {

// Mesa: "0:12(5): error: message"; also "0:3(1): preprocessor error: message".
const std::regex& mesaRegex() {
    static const std::regex re(
        R"(^\s*(\d+):(\d+)\((\d+)\):\s*(?:\w+\s+)?(error|warning)\s*:\s*(.*)$)", std::regex::icase);
    return re;
}
// NVIDIA: "0(12) : error C1008: message".
const std::regex& nvidiaRegex() {
    static const std::regex re(R"(^\s*(\d+)\((\d+)\)\s*:\s*(error|warning)\s*(\w*)\s*:\s*(.*)$)",
                               std::regex::icase);
    return re;
}
// glslang / AMD / Intel: "ERROR: 0:12: message", "WARNING: 0:3: message".
const std::regex& glslangRegex() {
    static const std::regex re(R"(^\s*(ERROR|WARNING)\s*:\s*(\d+):(\d+)\s*:\s*(.*)$)",
                               std::regex::icase);
    return re;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

int toInt(const std::string& digits) {
    try {
        return std::stoi(digits);
    } catch (...) {
        return 0;
    }
}

// Fills file and line from the driver's (source, line), undoing the kLineStride encoding.
void locate(Diagnostic& d, const std::string& sourceDigits, const std::string& lineDigits,
            const SourceMap& map) {
    const SourceLine sl = decodeLine(toInt(sourceDigits), toInt(lineDigits));
    d.line = sl.line;
    if (sl.source >= 0 && static_cast<size_t>(sl.source) < map.files.size())
        d.file = map.files[static_cast<size_t>(sl.source)];
    else
        d.file = "<source " + std::to_string(sl.source) + ">";
}

} // namespace

std::vector<Diagnostic> parseDriverLog(std::string_view log, const SourceMap& map) {
    std::vector<Diagnostic> out;
    for (std::string_view view : splitLines(log)) {
        const std::string line(view);
        std::smatch m;
        Diagnostic d;
        if (std::regex_match(line, m, mesaRegex())) {
            locate(d, m[1], m[2], map);
            d.column = toInt(m[3]);
            d.severity = lower(m[4]);
            d.message = m[5];
        } else if (std::regex_match(line, m, nvidiaRegex())) {
            locate(d, m[1], m[2], map);
            d.severity = lower(m[3]);
            d.message = m[4].length() ? m[4].str() + ": " + m[5].str() : m[5].str();
        } else if (std::regex_match(line, m, glslangRegex())) {
            locate(d, m[2], m[3], map);
            d.severity = lower(m[1]);
            d.message = m[4];
        } else {
            continue;
        }
        const size_t first = d.message.find_first_not_of(" \t\r\f\v");
        const size_t last = d.message.find_last_not_of(" \t\r\f\v");
        d.message = first == std::string::npos ? "" : d.message.substr(first, last - first + 1);
        out.push_back(std::move(d));
    }
    return out;
}

std::string formatDiagnostics(std::string_view rawLog, const SourceMap& map) {
    const auto diags = parseDriverLog(rawLog, map);
    if (diags.empty()) return "could not parse driver log; raw log:\n" + std::string(rawLog);
    std::string out;
    for (const Diagnostic& d : diags)
        out += d.file + ":" + std::to_string(d.line) + ": " + d.severity + ": " + d.message + "\n";
    return out;
}

std::string undeclaredName(std::string_view message) {
    static const std::regex patterns[] = {
        std::regex(R"re(^[`'"](\w+)['`"]\s+undeclared)re"),                  // Mesa
        std::regex(R"re(no function with name [`'"](\w+)['`"])re"),          // Mesa
        std::regex(R"re(undefined variable\s+"(\w+)")re"),                   // NVIDIA
        std::regex(R"re(^'(\w+)'\s*:\s*undeclared identifier)re"),           // glslang
        std::regex(R"re(^'(\w+)'\s*:\s*no matching overloaded function)re"), // glslang
    };
    const std::string text(message);
    std::smatch m;
    for (const std::regex& re : patterns)
        if (std::regex_search(text, m, re)) return m[1];
    return {};
}

namespace {

// Optimal string alignment distance, stopping early above `limit` (returns limit + 1).
size_t editDistance(const std::string& a, const std::string& b, size_t limit) {
    const size_t n = a.size(), m = b.size();
    if ((n > m ? n - m : m - n) > limit) return limit + 1;
    std::vector<std::vector<size_t>> d(n + 1, std::vector<size_t>(m + 1));
    for (size_t i = 0; i <= n; ++i)
        d[i][0] = i;
    for (size_t j = 0; j <= m; ++j)
        d[0][j] = j;
    for (size_t i = 1; i <= n; ++i) {
        size_t rowMin = d[i][0];
        for (size_t j = 1; j <= m; ++j) {
            const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
            rowMin = std::min(rowMin, d[i][j]);
        }
        if (rowMin > limit) return limit + 1;
    }
    return d[n][m];
}

// GLSL 4.50 built-in functions a model is likely to call (GLSL 4.50 specification, chapter 8)
// and the constructors: candidates that need not appear in the source.
constexpr const char* kBuiltins[] = {
    "radians", "degrees",  "sin",       "cos",   "tan",         "asin",        "acos",    "atan",
    "sinh",    "cosh",     "tanh",      "asinh", "acosh",       "atanh",       "pow",     "exp",
    "log",     "exp2",     "log2",      "sqrt",  "inversesqrt", "abs",         "sign",    "floor",
    "trunc",   "round",    "roundEven", "ceil",  "fract",       "mod",         "modf",    "min",
    "max",     "clamp",    "mix",       "step",  "smoothstep",  "isnan",       "isinf",   "fma",
    "length",  "distance", "dot",       "cross", "normalize",   "faceforward", "reflect", "refract",
    "float",   "double",   "int",       "uint",  "bool",        "vec2",        "vec3",    "vec4",
    "dvec2",   "dvec3",    "dvec4",     "ivec2", "ivec3",       "ivec4",       "mat2",    "mat3",
    "mat4",    "return"};

} // namespace

std::string nearestIdentifier(const std::string& name, std::string_view source) {
    if (name.size() < 3) return {};
    const size_t limit = name.size() <= 7 ? 1 : 2;
    std::string best;
    size_t bestDistance = limit + 1;
    auto consider = [&](const std::string& candidate) {
        if (candidate == name) return;
        const size_t d = editDistance(name, candidate, limit);
        if (d < bestDistance) {
            bestDistance = d;
            best = candidate;
        }
    };
    for (size_t i = 0; i < source.size();) {
        const unsigned char c = static_cast<unsigned char>(source[i]);
        if (std::isalpha(c) || c == '_') {
            size_t j = i + 1;
            while (j < source.size() &&
                   (std::isalnum(static_cast<unsigned char>(source[j])) || source[j] == '_'))
                ++j;
            consider(std::string(source.substr(i, j - i)));
            i = j;
        } else if (std::isdigit(c)) { // a number, with its suffix ("1.0e-3f"): no identifier
            while (i < source.size() &&
                   (std::isalnum(static_cast<unsigned char>(source[i])) || source[i] == '.'))
                ++i;
        } else {
            ++i;
        }
    }
    for (const char* b : kBuiltins)
        consider(b);
    return best;
}

} // namespace shader
