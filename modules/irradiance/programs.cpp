// irradiance/programs: shader assembly and compilation with mapped errors (see programs.h).
#include "irradiance/programs.h"

#include "bssrdf/assembly.h"
#include "bssrdf/diagnostics.h"
#include "core/core.h"

#include <vector>

namespace irradiance::detail {
namespace {
namespace fs = std::filesystem;

bssrdf::AssembledShader assembleFile(const fs::path& dir, const std::string& file) {
    const std::string displayDir = dir.filename().string();
    auto display = [&](const std::string& name) {
        return displayDir.empty() ? name : displayDir + "/" + name;
    };
    const std::string mainName = display(file);
    std::string text;
    try {
        text = core::readFile(dir / file);
    } catch (const core::Error& e) {
        throw core::Error(mainName, 0, e.message());
    }
    auto resolve = [&](const std::string& include, std::string& displayPath) {
        displayPath = display(include);
        return core::readFile(dir / include);
    };
    return bssrdf::assemble(text, mainName, nullptr, resolve);
}

[[noreturn]] void rethrow(const gl::ProgramError& e, const bssrdf::SourceMap& map) {
    const std::string all = bssrdf::formatDiagnostics(e.log(), map);
    for (const auto& d : bssrdf::parseDriverLog(e.log(), map))
        if (d.severity == "error") throw core::Error(d.file, d.line, d.message + "\n" + all);
    throw core::Error(map.files.front(), 0, all);
}
} // namespace

gl::Program loadComputeProgram(const fs::path& shaderDir, const std::string& file) {
    const auto src = assembleFile(shaderDir, file);
    try {
        return gl::buildProgram({{GL_COMPUTE_SHADER, src.glsl}});
    } catch (const gl::ProgramError& e) {
        rethrow(e, src.map);
    }
}

gl::Program loadRenderProgram(const fs::path& shaderDir, const std::string& vertex,
                              const std::string& fragment) {
    const auto vs = assembleFile(shaderDir, vertex);
    const auto fs = assembleFile(shaderDir, fragment);
    try {
        return gl::buildProgram({{GL_VERTEX_SHADER, vs.glsl}, {GL_FRAGMENT_SHADER, fs.glsl}});
    } catch (const gl::ProgramError& e) {
        rethrow(e, e.stage() == GL_FRAGMENT_SHADER ? fs.map : vs.map);
    }
}

void deleteSampler(GLuint id) {
    glDeleteSamplers(1, &id);
}

} // namespace irradiance::detail
