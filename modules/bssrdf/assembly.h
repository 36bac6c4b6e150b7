// bssrdf assembly: pieces a GLSL template, its #include files and a model's sections together
// into one shader source (thesis Appendix A.2: "segments of GLSL code, which are pieced together
// with code from our system to produce various shaders"). The template and includes go through
// the project's one assembler (shader/assembly.h: `#line` source maps whose line numbers carry
// the file); this adds the model: its sections each under `#line` directives pointing into the
// model file, so that a driver error maps back to `materials/NAME.bssrdf:LINE`.
#pragma once

#include "bssrdf/bssrdf.h"
#include "shader/assembly.h"

#include <string>
#include <string_view>

namespace bssrdf {

// The model's part of the assembly, for shader::assemble / shader::build:
//   - `#pragma bssrdf_model` is replaced by the model's parameter uniforms, its initializer
//     (or `void init() {}`), its diffuseReflectance section and its shader section, each under
//     `#line` directives pointing into the model file, then its sample section inside
//     `#if defined(BSSRDF_WANT_SAMPLE)` (a template that evaluates the analytic sampler defines
//     it before the pragma; no other consumer compiles the sampler). Error if model == nullptr,
//     or when the pragma appears twice.
//   - With a model, right after `#version`: `#define BSSRDF_RADIAL 1`, `BSSRDF_NO_WI`,
//     `BSSRDF_NO_WO` for the attributes set, and `BSSRDF_NO_DIFFUSE_REFLECTANCE` when the
//     model has no diffuseReflectance section, `BSSRDF_HAS_SAMPLE` with a sample section and
//     `BSSRDF_HAS_LOBES` when the shader section defines the lobe interface.
// The returned extension refers to `model`, which must outlive its use.
shader::Extension modelExtension(const Model* model);

// shader::assemble with modelExtension(model). Throws core::Error(file, line, message).
shader::AssembledShader assemble(std::string_view templateText,
                                 const std::string& templateDisplayPath, const Model* model,
                                 const shader::IncludeResolver& resolveInclude);

// "uniform float Multiplier;\n" / "uniform bool X;\n" / "uniform vec3 C;\n", one per parameter.
std::string uniformDeclarations(const Model& m);

// The GLSL type of a parameter's uniform: "float", "bool" or "vec3".
const char* glslType(ParamType t);

} // namespace bssrdf
