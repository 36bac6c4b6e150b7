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

// The name an error message says is not declared, as each compiler words it: Mesa "`x'
// undeclared" and "no function with name 'x'", NVIDIA 'undefined variable "x"', glslang "'x' :
// undeclared identifier" and "'x' : no matching overloaded function found"; empty for any other
// message.
std::string undeclaredName(std::string_view message);

// The identifier of `source` (the assembled GLSL, so the model's own names and the builtins the
// workbench declares) or GLSL built-in function nearest to `name` by optimal string alignment
// distance (an insertion, deletion, substitution or swap of neighbours costs 1): within 1 for a
// name of up to 7 characters, 2 beyond; the first such in source order among the nearest; empty
// when none is that near or the name is shorter than 3 characters. Written here: no Debian
// package offers an edit distance for C++.
std::string nearestIdentifier(const std::string& name, std::string_view source);

} // namespace shader
