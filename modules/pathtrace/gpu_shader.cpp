// Compute shader loading with #include expansion and driver-log mapping (see gpu_shader.h).
#include "pathtrace/gpu_shader.h"

#include "core/core.h"

#include <regex>
#include <sstream>

namespace pathtrace {

namespace {

namespace fs = std::filesystem;

struct Loader {
    fs::path baseDir;               // includes are relative to the main file's folder
    std::string displayDir;         // e.g. "shaders"
    std::vector<fs::path> resolved; // per source-string number
    GpuShaderSource out;

    // Appends file number `index` (already registered) to out.text.
    void append(size_t index, int depth) {
        const std::string name = out.files[index]; // a copy: out.files grows below
        const std::string text = core::readFile(resolved[index]);
        static const std::regex includeRe(R"(^\s*#\s*include\b(.*)$)");
        static const std::regex quotedRe(R"re(^\s*"([^"]+)"\s*(//.*)?$)re");
        std::istringstream in(text);
        std::string line;
        int lineNo = 0;
        while (std::getline(in, line)) {
            ++lineNo;
            if (!line.empty() && line.back() == '\r') line.pop_back();
            std::smatch m;
            if (!std::regex_match(line, m, includeRe)) {
                out.text += line;
                out.text += '\n';
                continue;
            }
            const std::string rest = m[1];
            std::smatch q;
            if (!std::regex_match(rest, q, quotedRe))
                throw core::Error(name, lineNo, "malformed #include, expected #include \"file\"");
            const std::string rel = q[1];
            const fs::path target = (baseDir / rel).lexically_normal();
            if (depth > 16) throw core::Error(name, lineNo, "includes nested too deeply");
            bool seen = false;
            for (const auto& r : resolved)
                seen = seen || r == target;
            if (!seen) {
                if (!fs::is_regular_file(target))
                    throw core::Error(name, lineNo, "cannot open include \"" + rel + "\"");
                resolved.push_back(target);
                out.files.push_back(displayDir.empty() ? rel : displayDir + "/" + rel);
                const size_t child = out.files.size() - 1;
                out.text += "#line 1 " + std::to_string(child) + "\n";
                append(child, depth + 1);
            }
            // back in this file: the next line is lineNo + 1
            out.text += "#line " + std::to_string(lineNo + 1) + " " + std::to_string(index) + "\n";
        }
    }
};

int toInt(const std::string& digits) {
    try {
        return std::stoi(digits);
    } catch (...) {
        return -1;
    }
}

} // namespace

GpuShaderSource loadGpuShader(const fs::path& file) {
    Loader loader;
    loader.baseDir = file.parent_path();
    loader.displayDir = file.parent_path().filename().string();
    loader.resolved.push_back(file.lexically_normal());
    const std::string name = file.filename().string();
    loader.out.files.push_back(loader.displayDir.empty() ? name : loader.displayDir + "/" + name);
    loader.append(0, 0);
    return std::move(loader.out);
}

gl::Program buildGpuShader(const GpuShaderSource& source) {
    try {
        return gl::buildProgram({{GL_COMPUTE_SHADER, source.text}});
    } catch (const gl::ProgramError& e) {
        // Mesa "0:12(5): error: msg", NVIDIA "0(12) : error C1008: msg", glslang "ERROR: 0:12: msg"
        static const std::regex mesa(R"(^\s*(\d+):(\d+)\(\d+\):\s*(?:\w+\s+)?error\s*:\s*(.*)$)",
                                     std::regex::icase);
        static const std::regex nvidia(R"(^\s*(\d+)\((\d+)\)\s*:\s*error\s*\w*\s*:\s*(.*)$)",
                                       std::regex::icase);
        static const std::regex glslang(R"(^\s*ERROR\s*:\s*(\d+):(\d+)\s*:\s*(.*)$)",
                                        std::regex::icase);
        std::istringstream in(e.log());
        std::string line;
        while (std::getline(in, line)) {
            if (!line.empty() && line.back() == '\r') line.pop_back();
            std::smatch m;
            if (!std::regex_match(line, m, mesa) && !std::regex_match(line, m, nvidia) &&
                !std::regex_match(line, m, glslang))
                continue;
            const int src = toInt(m[1]);
            const int lineNo = toInt(m[2]);
            const std::string file = src >= 0 && static_cast<size_t>(src) < source.files.size()
                                         ? source.files[static_cast<size_t>(src)]
                                         : source.files.front();
            throw core::Error(file, lineNo, m[3].str());
        }
        throw core::Error(source.files.front(), 0, e.log());
    }
}

} // namespace pathtrace
