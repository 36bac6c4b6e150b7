// shader diagnostics: maps a GLSL compiler/linker info log back to the user's files.
// Each driver prints "source-string:line" in its own format; with the SourceMap built by
// assemble() (#line L S directives) the source-string number names the file, so an error in a
// bssrdf model reads "materials/foo.bssrdf:LINE: error: ...". Formats understood:
//   Mesa            0:12(5): error: message
//   NVIDIA          0(12) : error C1008: message
//   glslang / AMD   ERROR: 0:12: 'x' : message      WARNING: 0:3: message
//   Intel (Windows) ERROR: 0:12: message
// Reported lines are decoded with decodeLine() (assembly.h), which also recovers the file when
// Mesa reports source string 0 for a line of another source.
#pragma once

#include "shader/assembly.h"

#include <string>
#include <string_view>
#include <vector>

namespace shader {

struct Diagnostic {
    std::string file; // map.files[source], or "<source n>" for an unknown number
    int line = 0;
    int column = 0;       // 0 when the driver gives none
    std::string severity; // "error" or "warning"
    std::string message;
};

// One Diagnostic per recognised log line; lines that match none of the formats are skipped.
std::vector<Diagnostic> parseDriverLog(std::string_view log, const SourceMap& map);

// One "file:LINE: error: message" line per diagnostic; when nothing could be parsed,
// "could not parse driver log; raw log:\n" followed by the raw log.
std::string formatDiagnostics(std::string_view rawLog, const SourceMap& map);

} // namespace shader
