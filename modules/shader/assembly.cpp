// GLSL assembly with #line source maps: template + #include files + an extension's text.
#include "shader/assembly.h"

#include "core/core.h"

#include <algorithm>
#include <regex>

namespace shader {

std::vector<std::string_view> splitLines(std::string_view text) {
    std::vector<std::string_view> lines;
    size_t start = 0;
    while (start < text.size()) {
        size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(start, end - start);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        lines.push_back(line);
        start = end + 1;
    }
    return lines;
}

namespace {

const std::regex& includeRegex() {
    static const std::regex re(R"(^\s*#\s*include\s+\"([^\"]+)\"\s*$)");
    return re;
}
const std::regex& pragmaRegex() {
    static const std::regex re(R"(^\s*#\s*pragma\s+(\w+)\s*$)");
    return re;
}
const std::regex& versionRegex() {
    static const std::regex re(R"(^\s*#\s*version\b.*)");
    return re;
}

class Assembler final : public Emitter {
  public:
    Assembler(const IncludeResolver& resolve, const Extension& ext)
        : m_resolve(resolve), m_ext(ext) {}

    AssembledShader run(std::string_view templateText, const std::string& templatePath) {
        source(templatePath); // source 0
        m_stack.push_back(templatePath);
        processFile(templateText, templatePath, 0, true);
        return std::move(m_result);
    }

    void text(std::string_view glsl) override { m_result.glsl += glsl; }
    void line(int line, int source) override {
        m_result.glsl += "#line " + std::to_string(encodeLine(source, line)) + " " +
                         std::to_string(source) + "\n";
    }
    int source(const std::string& path) override {
        auto& files = m_result.map.files;
        auto it = std::find(files.begin(), files.end(), path);
        if (it != files.end()) return static_cast<int>(it - files.begin());
        files.push_back(path);
        return static_cast<int>(files.size()) - 1;
    }

  private:
    void processFile(std::string_view text, const std::string& path, int source, bool isTemplate);
    void include(const std::string& name, const std::string& path, int lineNo, int source);

    const IncludeResolver& m_resolve;
    const Extension& m_ext;
    AssembledShader m_result;
    std::vector<std::string> m_stack; // include chain, template first
    std::string m_pragmaAt;           // "file:line" of the extension's pragma
};

void Assembler::processFile(std::string_view text, const std::string& path, int source,
                            bool isTemplate) {
    const auto lines = splitLines(text);
    if (lines.size() >= static_cast<size_t>(kLineStride))
        throw core::Error(path, 0,
                          "too long for the #line source map (" + std::to_string(lines.size()) +
                              " lines, at most " + std::to_string(kLineStride - 1) + ")");
    std::string& out = m_result.glsl;
    std::smatch match;
    for (size_t i = 0; i < lines.size(); ++i) {
        const int lineNo = static_cast<int>(i) + 1;
        const std::string line(lines[i]);
        const bool isVersion = std::regex_match(line, versionRegex());
        if (isTemplate && i == 0) {
            if (!isVersion)
                throw core::Error(path, 1, "a shader template must start with '#version'");
            out += line + "\n";
            if (m_ext.afterVersion) m_ext.afterVersion(*this);
            continue;
        }
        if (isVersion)
            throw core::Error(path, lineNo,
                              "'#version' is only allowed on the first line of the template");
        if (std::regex_match(line, match, includeRegex())) {
            include(match[1].str(), path, lineNo, source);
        } else if (!m_ext.pragma.empty() && std::regex_match(line, match, pragmaRegex()) &&
                   match[1].str() == m_ext.pragma) {
            const std::string here = path + ":" + std::to_string(lineNo);
            if (!m_pragmaAt.empty())
                throw core::Error(path, lineNo,
                                  "'#pragma " + m_ext.pragma + "' used twice (first at " +
                                      m_pragmaAt + ")");
            m_pragmaAt = here;
            m_ext.onPragma(*this, path, lineNo, source);
        } else {
            out += line;
            out += '\n';
        }
    }
    if (isTemplate && lines.empty())
        throw core::Error(path, 1, "a shader template must start with '#version'");
}

void Assembler::include(const std::string& name, const std::string& path, int lineNo, int source) {
    std::string displayPath;
    std::string text;
    try {
        text = m_resolve(name, displayPath);
    } catch (const core::Error& e) {
        throw core::Error(path, lineNo, "cannot include \"" + name + "\": " + e.what());
    }
    if (displayPath.empty()) displayPath = name;
    if (std::find(m_stack.begin(), m_stack.end(), displayPath) != m_stack.end()) {
        std::string chain;
        for (const auto& f : m_stack)
            chain += f + " -> ";
        throw core::Error(path, lineNo, "include cycle: " + chain + displayPath);
    }
    const int n = this->source(displayPath);
    line(1, n);
    m_stack.push_back(displayPath);
    processFile(text, displayPath, n, false);
    m_stack.pop_back();
    line(lineNo + 1, source);
}

} // namespace

AssembledShader assemble(std::string_view templateText, const std::string& templateDisplayPath,
                         const IncludeResolver& resolveInclude, const Extension& extension) {
    return Assembler(resolveInclude, extension).run(templateText, templateDisplayPath);
}

} // namespace shader
