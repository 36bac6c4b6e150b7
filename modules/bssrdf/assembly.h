// bssrdf assembly: pieces a GLSL template, its #include files and a model's sections together
// into one shader source (thesis Appendix A.2: "segments of GLSL code, which are pieced together
// with code from our system to produce various shaders"). Every piece is preceded by a
// `#line L S` directive so that a driver error maps back to the user's file and line
// (see diagnostics.h); SourceMap says which file each source-string number S is.
#pragma once

#include "bssrdf/bssrdf.h"

#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace bssrdf {

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

struct AssembledShader {
    std::string glsl;
    SourceMap map;
};

// Returns the text of an included file (e.g. "common/bssrdf_prelude.glsl") and sets
// displayPathOut (e.g. "shaders/common/bssrdf_prelude.glsl"); throws core::Error if missing.
using IncludeResolver =
    std::function<std::string(const std::string& includeName, std::string& displayPathOut)>;

// Assembles `templateText` (source 0, must start with `#version`). Each piece is preceded by
// `#line encodeLine(S, L) S` (see kLineStride):
//   - `#include "NAME"` lines are replaced by the resolved file, recursively, each file with
//     its own source number; include cycles are errors.
//   - `#pragma bssrdf_model` is replaced by the model's parameter uniforms, its initializer
//     (or `void init() {}`), its diffuseReflectance section and its shader section, each under
//     `#line` directives pointing into the model file. Error if model == nullptr.
//   - With a model, right after `#version`: `#define BSSRDF_RADIAL 1`, `BSSRDF_NO_WI`,
//     `BSSRDF_NO_WO` for the attributes set, and `BSSRDF_NO_DIFFUSE_REFLECTANCE` when the
//     model has no diffuseReflectance section.
// Throws core::Error(file, line, message) naming the template or include line at fault.
AssembledShader assemble(std::string_view templateText, const std::string& templateDisplayPath,
                         const Model* model, const IncludeResolver& resolveInclude);

// "uniform float Multiplier;\n" / "uniform bool X;\n" / "uniform vec3 C;\n", one per parameter.
std::string uniformDeclarations(const Model& m);

// The GLSL type of a parameter's uniform: "float", "bool" or "vec3".
const char* glslType(ParamType t);

} // namespace bssrdf
