// pathtrace GPU shaders: a compute shader with its shared files, assembled and mapped back by
// the project's one shader assembler (bssrdf/assembly.h: `#include "common/x.glsl"` expanded
// relative to the main file's folder, every file under its own `#line` source number, line
// numbers encoded so that even Mesa's source-0 reports name the right file), and compiled
// with driver errors reported as "shaders/common/x.glsl:LINE: message".
#pragma once

#include "bssrdf/assembly.h"
#include "gl/gl.h"

#include <filesystem>

namespace pathtrace {

using GpuShaderSource = bssrdf::AssembledShader;

// Reads `file` and its includes. Throws core::Error(file, line, msg) for a missing include, an
// include cycle or an unreadable file (line 0).
GpuShaderSource loadGpuShader(const std::filesystem::path& file);

// Compiles and links a compute program. On failure throws core::Error naming the file and
// line of the first driver error, with every diagnostic in the message (or the raw log when
// the log has no recognisable location).
gl::Program buildGpuShader(const GpuShaderSource& source);

} // namespace pathtrace
