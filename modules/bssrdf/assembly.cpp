// GLSL assembly with #line source maps: template + #include files + model sections.
#include "bssrdf/assembly.h"

#include "bssrdf/detail/text_lines.h"
#include "core/core.h"

#include <algorithm>
#include <regex>

namespace bssrdf {

namespace {

const std::regex& includeRegex() {
    static const std::regex re(R"(^\s*#\s*include\s+\"([^\"]+)\"\s*$)");
    return re;
}
const std::regex& pragmaRegex() {
    static const std::regex re(R"(^\s*#\s*pragma\s+bssrdf_model\s*$)");
    return re;
}
const std::regex& versionRegex() {
    static const std::regex re(R"(^\s*#\s*version\b.*)");
    return re;
}

// `#line` making the NEXT line line `line` of source string `source` (offset per kLineStride).
std::string lineDirective(int line, int source) {
    return "#line " + std::to_string(encodeLine(source, line)) + " " + std::to_string(source) +
           "\n";
}

class Assembler {
  public:
    Assembler(const Model* model, const IncludeResolver& resolve)
        : m_model(model), m_resolve(resolve) {}

    AssembledShader run(std::string_view templateText, const std::string& templatePath) {
        sourceNumber(templatePath); // source 0
        m_stack.push_back(templatePath);
        processFile(templateText, templatePath, 0, true);
        return std::move(m_result);
    }

  private:
    void processFile(std::string_view text, const std::string& path, int source, bool isTemplate);
    void include(const std::string& name, const std::string& path, int lineNo, int source);
    void emitModel(const std::string& path, int lineNo, int source);
    void emitDefines();
    int sourceNumber(const std::string& path);

    const Model* m_model;
    const IncludeResolver& m_resolve;
    AssembledShader m_result;
    std::vector<std::string> m_stack; // include chain, template first
    std::string m_pragmaAt;           // "file:line" of the first #pragma bssrdf_model
};

int Assembler::sourceNumber(const std::string& path) {
    auto& files = m_result.map.files;
    auto it = std::find(files.begin(), files.end(), path);
    if (it != files.end()) return static_cast<int>(it - files.begin());
    files.push_back(path);
    return static_cast<int>(files.size()) - 1;
}

void Assembler::emitDefines() {
    if (!m_model) return;
    std::string& out = m_result.glsl;
    if (m_model->attrs.radial) out += "#define BSSRDF_RADIAL 1\n";
    if (m_model->attrs.noWi) out += "#define BSSRDF_NO_WI 1\n";
    if (m_model->attrs.noWo) out += "#define BSSRDF_NO_WO 1\n";
    if (!m_model->diffuseReflectance) out += "#define BSSRDF_NO_DIFFUSE_REFLECTANCE 1\n";
    out += lineDirective(2, 0);
}

void Assembler::processFile(std::string_view text, const std::string& path, int source,
                            bool isTemplate) {
    const auto lines = detail::splitLines(text);
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
            emitDefines();
            continue;
        }
        if (isVersion)
            throw core::Error(path, lineNo,
                              "'#version' is only allowed on the first line of the template");
        if (std::regex_match(line, match, includeRegex())) {
            include(match[1].str(), path, lineNo, source);
        } else if (std::regex_match(line, pragmaRegex())) {
            emitModel(path, lineNo, source);
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
    const int n = sourceNumber(displayPath);
    m_result.glsl += lineDirective(1, n);
    m_stack.push_back(displayPath);
    processFile(text, displayPath, n, false);
    m_stack.pop_back();
    m_result.glsl += lineDirective(lineNo + 1, source);
}

void Assembler::emitModel(const std::string& path, int lineNo, int source) {
    const std::string here = path + ":" + std::to_string(lineNo);
    if (!m_model)
        throw core::Error(path, lineNo,
                          "'#pragma bssrdf_model' in a shader assembled without a model");
    if (!m_pragmaAt.empty())
        throw core::Error(path, lineNo,
                          "'#pragma bssrdf_model' used twice (first at " + m_pragmaAt + ")");
    m_pragmaAt = here;
    const Model& m = *m_model;
    if (std::count(m.source.begin(), m.source.end(), '\n') >= kLineStride - 1)
        throw core::Error(m.path, 0, "too long for the #line source map");
    const int ms = sourceNumber(m.path);
    std::string& out = m_result.glsl;
    for (const Param& p : m.params) {
        out += lineDirective(p.line, ms);
        out += std::string("uniform ") + glslType(p.type) + " " + p.name + ";\n";
    }
    auto emitSection = [&](const std::optional<Section>& s) {
        if (!s) return;
        out += lineDirective(s->firstLine, ms);
        out += s->code;
    };
    if (m.initializer) {
        emitSection(m.initializer);
    } else {
        out += lineDirective(lineNo, source);
        out += "void init() {}\n";
    }
    emitSection(m.diffuseReflectance);
    emitSection(m.shader);
    out += lineDirective(lineNo + 1, source);
}

} // namespace

const char* glslType(ParamType t) {
    switch (t) {
    case ParamType::Float:
        return "float";
    case ParamType::Bool:
        return "bool";
    case ParamType::Color:
        return "vec3";
    }
    return "float";
}

std::string uniformDeclarations(const Model& m) {
    std::string out;
    for (const Param& p : m.params)
        out += std::string("uniform ") + glslType(p.type) + " " + p.name + ";\n";
    return out;
}

AssembledShader assemble(std::string_view templateText, const std::string& templateDisplayPath,
                         const Model* model, const IncludeResolver& resolveInclude) {
    return Assembler(model, resolveInclude).run(templateText, templateDisplayPath);
}

} // namespace bssrdf
