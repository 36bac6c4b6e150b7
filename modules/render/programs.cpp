// render: plain program building (see detail.h).
#include "render/detail.h"

#include "bssrdf/assembly.h"
#include "bssrdf/diagnostics.h"
#include "core/core.h"

namespace render::detail {

gl::Program buildPlainProgram(const bssrdf::ShaderSources& src,
                              const std::vector<std::pair<GLenum, std::string>>& stages) {
    std::vector<gl::ShaderStage> glStages;
    std::vector<bssrdf::AssembledShader> assembled;
    for (const auto& [type, name] : stages) {
        std::string display;
        const std::string text = src.readTemplate(name, display);
        assembled.push_back(bssrdf::assemble(text, display, nullptr, src.includeResolver()));
        glStages.push_back({type, assembled.back().glsl});
    }
    try {
        return gl::buildProgram(glStages);
    } catch (const gl::ProgramError& e) {
        size_t which = 0;
        for (size_t i = 0; i < stages.size(); ++i)
            if (stages[i].first == e.stage()) which = i;
        const bssrdf::SourceMap& map = assembled[which].map;
        const std::string all = bssrdf::formatDiagnostics(e.log(), map);
        for (const auto& d : bssrdf::parseDriverLog(e.log(), map))
            if (d.severity == "error") throw core::Error(d.file, d.line, d.message + "\n" + all);
        throw core::Error(map.files.empty() ? stages[which].second : map.files.front(), 0, all);
    }
}

} // namespace render::detail
