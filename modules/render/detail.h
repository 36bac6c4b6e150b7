// render internals: plain (non-model) programs assembled like every shader of the project
// (bssrdf::assemble without a model: #include expansion and #line maps) and built with driver
// errors mapped back to "shaders/NAME:LINE".
#pragma once

#include "bssrdf/program.h"
#include "gl/gl.h"

#include <string>
#include <utility>
#include <vector>

namespace render::detail {

// stages: (GL_VERTEX_SHADER | GL_FRAGMENT_SHADER | GL_COMPUTE_SHADER, template name).
gl::Program buildPlainProgram(const bssrdf::ShaderSources& src,
                              const std::vector<std::pair<GLenum, std::string>>& stages);

} // namespace render::detail
