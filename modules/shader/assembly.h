// shader assembly: pieces a GLSL template and its #include files together into one shader
// source. Every piece is preceded by a `#line L S` directive so that a driver error maps back to
// the file and line it came from (see diagnostics.h); SourceMap says which file each
// source-string number S is, and is also the list of files the shader was built from (its
// hot-reload dependencies, see program.h). An Extension lets a caller splice its own text in
// (the bssrdf module puts a model's sections where `#pragma bssrdf_model` stands).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace shader {

struct SourceMap {
    std::vector<std::string> files; // index = GLSL source-string number used in #line N S
};

// Line numbers in the assembled text. Mesa (seen with 22.3 / llvmpipe) reports source string 0
// for every semantic error, whatever `#line L S` said, and only keeps the line number right.
// So a line L of source S >= 1 is emitted as `#line S*kLineStride+L S`: the line number alone
// names the file on every driver, and the source number stays right for those that keep it.
// Source 0 (the template) is not offset. decodeLine() undoes this.
constexpr int kLineStride = 100000;
inline int encodeLine(int source, int line) {
    return source == 0 ? line : source * kLineStride + line;
}
struct SourceLine {
    int source = 0;
    int line = 0;
};
// (source, line) as reported by a driver -> the source string and line in that file.
inline SourceLine decodeLine(int reportedSource, int reportedLine) {
    if (reportedLine >= kLineStride)
        return {reportedLine / kLineStride, reportedLine % kLineStride};
    return {reportedSource, reportedLine};
}

// Splits text into lines (index 0 = file line 1), numbered as the #line directives number
// them. A trailing '\r' is stripped from each line (CRLF files); a final '\n' does not start an
// extra line.
std::vector<std::string_view> splitLines(std::string_view text);

struct AssembledShader {
    std::string glsl;
    SourceMap map;
};

// Returns the text of an included file (e.g. "common/bssrdf_prelude.glsl") and sets
// displayPathOut (e.g. "shaders/common/bssrdf_prelude.glsl"); throws core::Error if missing.
using IncludeResolver =
    std::function<std::string(const std::string& includeName, std::string& displayPathOut)>;

// Where an Extension writes: plain text, `#line` directives and new source numbers.
class Emitter {
  public:
    virtual ~Emitter() = default;
    virtual void text(std::string_view glsl) = 0;
    // `#line` making the NEXT line line `line` of source `source` (encoded per kLineStride).
    virtual void line(int line, int source) = 0;
    // The source number of `displayPath`, added to the SourceMap on first use.
    virtual int source(const std::string& displayPath) = 0;
};

struct Extension {
    // Called right after the template's `#version` line (defines, say).
    std::function<void(Emitter&)> afterVersion;
    // `#pragma <pragma>` lines are replaced by whatever onPragma writes; `file`/`line`/`source`
    // say where the pragma stood; a second such pragma is an error. Empty: no pragma is handled.
    std::string pragma;
    std::function<void(Emitter&, const std::string& file, int line, int source)> onPragma;
};

// Assembles `templateText` (source 0, must start with `#version`): `#include "NAME"` lines are
// replaced by the resolved file, recursively, each file under its own source number and each
// piece preceded by `#line encodeLine(S, L) S`; include cycles are errors. Throws
// core::Error(file, line, message) naming the template or include line at fault.
AssembledShader assemble(std::string_view templateText, const std::string& templateDisplayPath,
                         const IncludeResolver& resolveInclude, const Extension& extension = {});

} // namespace shader
