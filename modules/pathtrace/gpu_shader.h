// pathtrace GPU shaders: loading a compute shader with its shared files and mapping the
// driver's compile log back to them.
//   `#include "common/x.glsl"` lines are expanded (paths relative to the main file's folder,
//   each file at most once). Every file gets its own GLSL source-string number through
//   `#line L N` directives (0: the main file, then includes in order of first use), so a
//   driver message "N:L(C): error: msg" (Mesa; NVIDIA and glslang forms too) names the file
//   and line the author edited: "shaders/common/x.glsl:L: msg".
#pragma once

#include "gl/gl.h"

#include <filesystem>
#include <string>
#include <vector>

namespace pathtrace {

struct GpuShaderSource {
    std::string text;               // what the driver compiles
    std::vector<std::string> files; // display name per source-string number, e.g. "shaders/a.comp"
};

// Reads `file` and its includes. Throws core::Error(file, line, msg) for a missing include, a
// malformed #include line or an unreadable file (line 0).
GpuShaderSource loadGpuShader(const std::filesystem::path& file);

// Compiles and links a compute program. On failure throws core::Error naming the file and
// line of the first driver error ("shaders/pathtrace_slab.comp:42: message"), or the main
// file with line 0 and the raw log when the log has no recognisable location.
gl::Program buildGpuShader(const GpuShaderSource& source);

} // namespace pathtrace
