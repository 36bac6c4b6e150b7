// Compute shader loading and compilation for the GPU tracer (see gpu_shader.h).
#include "pathtrace/gpu_shader.h"

#include "bssrdf/diagnostics.h"
#include "core/core.h"

namespace pathtrace {

namespace fs = std::filesystem;

GpuShaderSource loadGpuShader(const fs::path& file) {
    const fs::path dir = file.parent_path();
    const std::string displayDir = dir.filename().string();
    auto display = [&](const std::string& name) {
        return displayDir.empty() ? name : displayDir + "/" + name;
    };
    const std::string mainName = display(file.filename().string());
    std::string text;
    try {
        text = core::readFile(file);
    } catch (const core::Error& e) {
        throw core::Error(mainName, 0, e.message());
    }
    auto resolve = [&](const std::string& include, std::string& displayPath) {
        displayPath = display(include);
        return core::readFile(dir / include);
    };
    return bssrdf::assemble(text, mainName, nullptr, resolve);
}

gl::Program buildGpuShader(const GpuShaderSource& source) {
    try {
        return gl::buildProgram({{GL_COMPUTE_SHADER, source.glsl}});
    } catch (const gl::ProgramError& e) {
        const std::string all = bssrdf::formatDiagnostics(e.log(), source.map);
        for (const auto& d : bssrdf::parseDriverLog(e.log(), source.map))
            if (d.severity == "error") throw core::Error(d.file, d.line, d.message + "\n" + all);
        throw core::Error(source.map.files.front(), 0, all);
    }
}

} // namespace pathtrace
