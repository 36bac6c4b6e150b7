// The .bssrdf file format (thesis Appendix A.2): attribute line, named sections, checks that the
// GLSL sections define the functions the consumers call.
#include "bssrdf/bssrdf.h"
#include "bssrdf/loop_sites.h"
#include "bssrdf/table_model.h"

#include "bssrdf/detail/param_parser.h"
#include "bssrdf/detail/text_lines.h"
#include "core/core.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <regex>

namespace bssrdf {

namespace {

using detail::tokenize;
using detail::trim;

constexpr const char* kKnownSections =
    "parameters, initializer, diffuseReflectance, shader, table, sample";

bool isComment(std::string_view trimmed) {
    return !trimmed.empty() && trimmed.front() == '#';
}

// GLSL code with // and /* */ comments blanked out (newlines kept), so that a commented-out
// definition does not count.
std::string stripGlslComments(std::string_view code) {
    std::string out(code);
    for (size_t i = 0; i + 1 < out.size(); ++i) {
        if (out[i] == '/' && out[i + 1] == '/') {
            while (i < out.size() && out[i] != '\n')
                out[i++] = ' ';
        } else if (out[i] == '/' && out[i + 1] == '*') {
            size_t j = i;
            out[j++] = ' ';
            out[j++] = ' ';
            while (j < out.size() && !(out[j] == '*' && j + 1 < out.size() && out[j + 1] == '/')) {
                if (out[j] != '\n') out[j] = ' ';
                ++j;
            }
            for (size_t k = j; k < out.size() && k < j + 2; ++k)
                out[k] = ' ';
            i = j + 1;
        }
    }
    return out;
}

class Parser {
  public:
    Parser(std::string_view text, const std::string& path) : m_text(text), m_path(path) {}

    Model run();

  private:
    [[noreturn]] void fail(int line, std::string message) const {
        throw core::Error(m_path, line, std::move(message));
    }
    void parseAttributes(std::string_view line, int lineNo, Attributes& attrs) const;
    void parseDirectiveOutside(const std::vector<std::string_view>& tok, int lineNo);
    void closeSection(const std::vector<std::string_view>& tok, int lineNo);
    void assign(Model& m);
    void requireDefinition(const Section& s, const char* pattern, const char* what) const;
    // The file line of the first match of `pattern` in the section (comments ignored), or 0.
    int definitionLine(const Section& s, const char* pattern) const;
    void findLobes(Model& m) const;

    std::string_view m_text;
    const std::string& m_path;
    std::optional<Section> m_open;
    std::vector<Section> m_sections;                // closed sections, file order
    std::map<std::string, int, std::less<>> m_seen; // name -> ::begin line
};

void Parser::parseAttributes(std::string_view line, int lineNo, Attributes& attrs) const {
    const auto tok = tokenize(line);
    if (tok.front().starts_with("::"))
        fail(lineNo, "missing mandatory attribute 'analytic': the first line must list the "
                     "model's attributes (e.g. 'analytic radial no_wi no_wo'), found " +
                         detail::inQuotes(line));
    std::map<std::string_view, bool*> known = {{"analytic", &attrs.analytic},
                                               {"radial", &attrs.radial},
                                               {"no_wi", &attrs.noWi},
                                               {"no_wo", &attrs.noWo}};
    for (std::string_view t : tok) {
        auto it = known.find(t);
        if (it == known.end())
            fail(lineNo, "unknown attribute " + detail::inQuotes(t) +
                             " (expected analytic, radial, no_wi or no_wo)");
        if (*it->second) fail(lineNo, "duplicate attribute " + detail::inQuotes(t));
        *it->second = true;
    }
    if (!attrs.analytic) fail(lineNo, "missing mandatory attribute 'analytic'");
}

void Parser::parseDirectiveOutside(const std::vector<std::string_view>& tok, int lineNo) {
    if (tok[0] == "::end") {
        std::string name = tok.size() > 1 ? " " + std::string(tok[1]) : "";
        fail(lineNo, "'::end" + name + "' without a matching '::begin'");
    }
    if (tok[0] != "::begin")
        fail(lineNo, "unknown directive " + detail::inQuotes(tok[0]) +
                         " (expected '::begin NAME' or '::end NAME')");
    if (tok.size() < 2) fail(lineNo, "'::begin' without a section name");
    if (tok.size() > 2)
        fail(lineNo, "'::begin " + std::string(tok[1]) + "' followed by extra text " +
                         detail::inQuotes(tok[2]) + " (a section has one name)");
    const std::string name(tok[1]);
    if (auto it = m_seen.find(name); it != m_seen.end())
        fail(lineNo, "duplicate section " + detail::inQuotes(name) + " (first opened at line " +
                         std::to_string(it->second) + ")");
    m_seen.emplace(name, lineNo);
    Section s;
    s.name = name;
    s.beginLine = lineNo;
    s.firstLine = lineNo + 1;
    m_open = std::move(s);
}

void Parser::closeSection(const std::vector<std::string_view>& tok, int lineNo) {
    const std::string& name = m_open->name;
    const std::string opened = " (opened at line " + std::to_string(m_open->beginLine) + ")";
    if (tok.size() < 2)
        fail(lineNo, "'::end' without a section name: expected '::end " + name + "'" + opened);
    if (tok[1] != name)
        fail(lineNo,
             "'::end " + std::string(tok[1]) + "' does not match '::begin " + name + "'" + opened);
    if (tok.size() > 2)
        fail(lineNo, "'::end " + name + "' followed by extra text " + detail::inQuotes(tok[2]));
    m_sections.push_back(std::move(*m_open));
    m_open.reset();
}

void Parser::requireDefinition(const Section& s, const char* pattern, const char* what) const {
    const std::regex re(pattern);
    if (!std::regex_search(stripGlslComments(s.code), re))
        fail(s.beginLine, "section " + detail::inQuotes(s.name) + " does not define " + what);
}

int Parser::definitionLine(const Section& s, const char* pattern) const {
    const std::string code = stripGlslComments(s.code);
    std::smatch match;
    if (!std::regex_search(code, match, std::regex(pattern))) return 0;
    const auto before = code.begin() + match.position(0);
    return s.firstLine + static_cast<int>(std::count(code.begin(), before, '\n'));
}

// The lobe interface (materials/README.md): QdLobeCount and QdLobe, both or neither.
void Parser::findLobes(Model& m) const {
    if (!m.shader) return;
    const int count = definitionLine(*m.shader, R"(\bint\s+QdLobeCount\s*\()");
    const int lobe = definitionLine(*m.shader, R"(\bvec2\s+QdLobe\s*\()");
    if (count && !lobe)
        fail(count, "the lobe interface needs both functions: 'int QdLobeCount()' is defined "
                    "but 'vec2 QdLobe(int k, int channel)' is not");
    if (lobe && !count)
        fail(lobe, "the lobe interface needs both functions: 'vec2 QdLobe(int k, int channel)' "
                   "is defined but 'int QdLobeCount()' is not");
    m.lobesLine = lobe;
}

void Parser::assign(Model& m) {
    for (Section& s : m_sections) {
        if (s.name == "parameters") {
            m.params = detail::parseParameters(s, m_path);
        } else if (s.name == "initializer") {
            requireDefinition(s, R"(\bvoid\s+init\s*\()", "void init()");
            m.initializer = std::move(s);
        } else if (s.name == "diffuseReflectance") {
            requireDefinition(s, R"(\bvec3\s+DiffuseReflectance\s*\()",
                              "vec3 DiffuseReflectance(vec3 AlphaPrime)");
            m.diffuseReflectance = std::move(s);
        } else if (s.name == "shader") {
            requireDefinition(s, R"(\bvec3\s+Bssrdf\s*\()",
                              "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo)");
            m.shader = std::move(s);
        } else if (s.name == "table") {
            m.table = std::move(s);
        } else if (s.name == "sample") {
            requireDefinition(s, R"(\bfloat\s+SampleRadius\s*\()",
                              "float SampleRadius(float xi, int channel)");
            requireDefinition(s, R"(\bfloat\s+PdfRadius\s*\()",
                              "float PdfRadius(float r, int channel)");
            requireDefinition(s, R"(\bfloat\s+MaxRadius\s*\()", "float MaxRadius(int channel)");
            m.sample = std::move(s);
        } else {
            std::string note =
                core::formatLocation(m_path, s.beginLine,
                                     "unknown section " + detail::inQuotes(s.name) +
                                         " ignored (known sections: " + kKnownSections + ")");
            core::logInfo(note);
            m.notes.push_back(std::move(note));
        }
    }
}

Model Parser::run() {
    Model m;
    m.path = m_path;
    m.name = std::filesystem::path(m_path).stem().string();
    m.source = std::string(m_text);
    m.hash = core::hashHex(m_text);

    if (auto bad = core::firstInvalidUtf8(m_text))
        fail(core::lineOfOffset(m_text, *bad),
             "not a UTF-8 text file (invalid byte at offset " + std::to_string(*bad) + ")");

    const auto lines = detail::splitLines(m_text);
    const int lastLine = std::max<int>(1, static_cast<int>(lines.size()));
    size_t i = 0;
    while (i < lines.size() && (trim(lines[i]).empty() || isComment(trim(lines[i]))))
        ++i;
    if (i == lines.size())
        fail(lastLine, "empty file: expected an attribute line starting with 'analytic'");
    parseAttributes(trim(lines[i]), static_cast<int>(i) + 1, m.attrs);

    for (++i; i < lines.size(); ++i) {
        const int lineNo = static_cast<int>(i) + 1;
        const std::string_view t = trim(lines[i]);
        if (m_open) {
            if (t.starts_with("::")) {
                const auto tok = tokenize(t);
                if (tok[0] == "::end") {
                    closeSection(tok, lineNo);
                    continue;
                }
                if (tok[0] == "::begin")
                    fail(lineNo, "nested '::begin' inside section " +
                                     detail::inQuotes(m_open->name) + " (opened at line " +
                                     std::to_string(m_open->beginLine) +
                                     "): close it with '::end " + m_open->name + "' first");
                fail(lineNo, "unknown directive " + detail::inQuotes(tok[0]) +
                                 " (expected '::begin NAME' or '::end NAME')");
            }
            m_open->code.append(lines[i]);
            m_open->code += '\n';
            continue;
        }
        if (t.empty() || isComment(t)) continue;
        if (t.starts_with("::")) {
            parseDirectiveOutside(tokenize(t), lineNo);
            continue;
        }
        fail(lineNo, "unexpected text outside a section: " + detail::inQuotes(t) +
                         " (expected '::begin NAME', a '#' comment or a blank line)");
    }
    if (m_open)
        fail(m_open->beginLine, "section " + detail::inQuotes(m_open->name) +
                                    " is not terminated (missing '::end " + m_open->name + "')");

    assign(m);
    // every loop must be a statement the loop budget can guard (loop_budget.h), not a macro's
    for (const std::optional<Section>* sec :
         {&m.initializer, &m.diffuseReflectance, &m.shader, &m.sample})
        if (*sec)
            if (const int at = loopInMacro((*sec)->code, (*sec)->firstLine))
                fail(at, "a macro that loops (for, while or do) or pastes tokens (##): write the "
                         "loop out as a statement, where the loop budget guards it");
    findLobes(m);
    if (m.table && m.shader)
        fail(m.table->beginLine, "a model has either a 'table' or a 'shader' section, not both");
    if (!m.shader && !m.table) fail(lastLine, "missing ::begin shader section");
    return m;
}

} // namespace

const Param* Model::findParam(std::string_view n) const {
    for (const Param& p : params)
        if (p.name == n) return &p;
    return nullptr;
}

Model parseModel(std::string_view text, const std::string& displayPath) {
    return Parser(text, displayPath).run();
}

Model loadModel(const std::filesystem::path& file, const std::string& displayPath) {
    // Checked before reading, so a huge file costs nothing (a model is a page of GLSL).
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(file, ec);
    if (!ec && bytes > kMaxModelBytes) {
        char size[32];
        std::snprintf(size, sizeof size, "%.1f MiB", double(bytes) / (1 << 20));
        throw core::Error(displayPath, 0,
                          std::string("the file is ") + size + "; a model file may be at most " +
                              std::to_string(kMaxModelBytes >> 20) + " MiB");
    }
    std::string text;
    try {
        text = core::readFile(file);
    } catch (const core::Error& e) {
        throw core::Error(displayPath, 0, e.message());
    }
    Model m = parseModel(text, displayPath);
    expandTable(m, file.parent_path());
    return m;
}

} // namespace bssrdf
