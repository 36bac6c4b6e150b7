// gl/detail/hazards.h: what the barrier checks (hazards.cpp) need from the rest of the GL layer.
#pragma once

#include "gl/gl.h"

#include <string>
#include <vector>

namespace gl::detail {

// Called by buildProgram after linking: which storage blocks the sources declare `readonly`.
void noteProgramSources(GLuint program, const std::vector<ShaderStage>& stages);

// Hands a message to the debug output's path (log, debugProblems, the observer) as if the driver
// had sent it; works without a debug context.
void reportDebugMessage(GLenum source, GLenum type, GLenum severity, const std::string& message);

} // namespace gl::detail
