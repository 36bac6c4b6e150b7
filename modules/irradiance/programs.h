// irradiance/programs: loading the module's shaders (shaders/irradiance_*.{comp,vert,frag} and
// their shaders/common/irradiance_*.glsl includes) through the project's one assembler
// (bssrdf::assemble, `#line` source maps), with driver errors reported as core::Error naming
// the file and line; and an RAII sampler object.
#pragma once

#include "gl/gl.h"

#include <filesystem>
#include <string>

namespace irradiance::detail {

// shaderDir: the shaders/ folder; file: e.g. "irradiance_direct.comp".
gl::Program loadComputeProgram(const std::filesystem::path& shaderDir, const std::string& file);
gl::Program loadRenderProgram(const std::filesystem::path& shaderDir, const std::string& vertex,
                              const std::string& fragment);

void deleteSampler(GLuint id);
using Sampler = gl::Handle<deleteSampler>;

} // namespace irradiance::detail
