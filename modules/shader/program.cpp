// shader programs: sources, dependency records, build with mapped driver errors.
#include "shader/program.h"

#include "core/core.h"
#include "shader/diagnostics.h"

#include <algorithm>

namespace shader {
namespace fs = std::filesystem;

namespace {
fs::path normal(const fs::path& p) {
    return fs::absolute(p).lexically_normal();
}
} // namespace

void Dependencies::add(const fs::path& file) {
    const fs::path f = normal(file);
    if (!contains(f)) m_files.push_back(f);
}

bool Dependencies::contains(const fs::path& file) const {
    return std::find(m_files.begin(), m_files.end(), normal(file)) != m_files.end();
}

bool Dependencies::containsAny(const std::vector<fs::path>& files) const {
    return std::any_of(files.begin(), files.end(), [&](const fs::path& f) { return contains(f); });
}

Sources::Sources(fs::path root, std::string dir) : m_root(std::move(root)), m_dir(std::move(dir)) {}

Sources Sources::forFolder(const fs::path& folder) {
    fs::path dir = folder.lexically_normal();
    if (dir.filename().empty()) dir = dir.parent_path(); // "shaders/"
    return Sources(dir.parent_path(), dir.filename().string());
}

std::string Sources::displayPath(const std::string& name) const {
    return m_dir.empty() ? name : m_dir + "/" + name;
}

fs::path Sources::fileOf(const std::string& displayPath) const {
    return normal(m_root / displayPath);
}

std::string Sources::read(const std::string& displayPath) const {
    try {
        return core::readFile(fileOf(displayPath));
    } catch (const core::Error& e) {
        throw core::Error(displayPath, 0, e.message());
    }
}

AssembledShader Sources::assemble(const std::string& name, Dependencies& deps,
                                  const Extension& extension) const {
    const std::string display = displayPath(name);
    deps.add(fileOf(display));
    const std::string text = read(display);
    auto resolve = [&](const std::string& include, std::string& includeDisplay) {
        includeDisplay = displayPath(include);
        deps.add(fileOf(includeDisplay));
        return read(includeDisplay);
    };
    return shader::assemble(text, display, resolve, extension);
}

namespace {

// The first error's message, then the compiler's other messages, which mostly follow from it
// (an undeclared name makes every expression using it fail): each distinct line once, with how
// often it came, under a line saying how many there are. The first error's own repeats (the same
// line and message) are counted on it.
std::string firstErrorWithItsCascade(const std::vector<Diagnostic>& all, size_t first) {
    const Diagnostic& f = all[first];
    auto same = [&](const Diagnostic& d) {
        return d.file == f.file && d.line == f.line && d.message == f.message;
    };
    const long repeats = std::count_if(all.begin(), all.end(), same);
    std::string out = f.message + (repeats > 1 ? " (" + std::to_string(repeats) + " times)" : "");
    std::vector<std::pair<std::string, int>> lines; // distinct, in order
    size_t more = 0;
    for (const Diagnostic& d : all) {
        if (same(d)) continue;
        ++more;
        const std::string text =
            core::formatLocation(d.file, d.line, d.severity + ": " + d.message);
        auto it = std::find_if(lines.begin(), lines.end(),
                               [&](const auto& l) { return l.first == text; });
        if (it == lines.end())
            lines.push_back({text, 1});
        else
            ++it->second;
    }
    if (more == 0) return out;
    out += "\n" + std::to_string(more) + " more compiler message" + (more == 1 ? "" : "s") +
           " (most follow from the first):";
    for (const auto& [text, count] : lines)
        out += "\n" + text + (count > 1 ? " (" + std::to_string(count) + " times)" : "");
    return out;
}

} // namespace

gl::Program link(const std::vector<StageSource>& stages, const std::string& blame) {
    std::vector<gl::ShaderStage> glStages;
    for (const auto& s : stages)
        glStages.push_back({s.type, s.source.glsl});
    try {
        gl::Program program = gl::buildProgram(glStages);
        // the program's name in driver messages and in the barrier checks: its template's path
        const SourceMap& first = stages.front().source.map;
        if (!first.files.empty())
            glObjectLabel(GL_PROGRAM, program.id(), -1, first.files.front().c_str());
        return program;
    } catch (const gl::ProgramError& e) {
        size_t which = 0;
        for (size_t i = 0; i < stages.size(); ++i)
            if (stages[i].type == e.stage()) which = i;
        const SourceMap& map = stages.at(which).source.map;
        const std::string all = formatDiagnostics(e.log(), map);
        const std::vector<Diagnostic> diagnostics = parseDriverLog(e.log(), map);
        for (size_t i = 0; i < diagnostics.size(); ++i)
            if (diagnostics[i].severity == "error") {
                std::string text = firstErrorWithItsCascade(diagnostics, i);
                // an undeclared name that is a typo of a declared one: say which
                const std::string name = undeclaredName(diagnostics[i].message);
                const std::string near =
                    name.empty() ? "" : nearestIdentifier(name, stages.at(which).source.glsl);
                if (!near.empty())
                    text.insert(text.find('\n') == std::string::npos ? text.size()
                                                                     : text.find('\n'),
                                "; did you mean `" + near + "'?");
                throw core::Error(diagnostics[i].file, diagnostics[i].line, text);
            }
        const std::string file = !blame.empty()      ? blame
                                 : map.files.empty() ? std::string("<shader>")
                                                     : map.files.front();
        throw core::Error(file, 0, (e.stage() == 0 ? "link failed: " : "compile failed: ") + all);
    }
}

gl::Program build(const Sources& src, const std::vector<std::pair<GLenum, std::string>>& stages,
                  Record& record, const Extension& extension, const std::string& blame) {
    record.dependencies = {};
    std::vector<StageSource> assembled;
    for (const auto& [type, name] : stages)
        assembled.push_back({type, src.assemble(name, record.dependencies, extension)});
    gl::Program program = link(assembled, blame);
    ++record.builds;
    return program;
}

} // namespace shader
