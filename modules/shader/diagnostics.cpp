// Driver info-log parsing (Mesa, NVIDIA, glslang/AMD, Intel) mapped through a SourceMap.
#include "shader/diagnostics.h"

#include <algorithm>
#include <cctype>
#include <regex>

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

} // namespace shader
