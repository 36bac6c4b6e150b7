// bssrdf conditioning: how far a model's pencil-beam profile may lie apart when two OpenGL drivers
// that both keep to the GLSL 4.50 precision rules (section 4.7.1) evaluate it. Each transcendental
// function of the model (exp, exp2, log, log2, pow, sqrt, inversesqrt) is moved by the largest
// error the rules allow it, with a sign drawn per call from its argument and a seed
// (shaders/common/perturbed_builtins.glsl, through shaders/pencil_perturbed.comp); the largest
// change over `patterns` seeds is the spread of each value. Where a model subtracts nearly equal
// terms (the better dipole's φ(r) far from the source, the multipole's alternating dipoles) the
// spread is many times the functions' own error; elsewhere it is about that error.
//
// A real driver's errors are a fixed function of the argument, with magnitudes up to the bound:
// signs drawn per argument at the bound's magnitude are that at its largest. Replaying a capture
// on another driver allows twice the spread (both drivers' errors, in opposite directions) on top
// of the relative floor (app/pipeline/capture_entries.h).
#pragma once

#include "bssrdf/program.h"

#include <glm/vec3.hpp>

#include <vector>

namespace bssrdf {

inline constexpr int kConditioningPatterns = 8;

// Per radius (mm) and channel: max over seeds 1 … patterns of |perturbed − unperturbed|, both from
// the same program. Throws core::Error (file, line) when the perturbed program does not build (a
// model that calls a transcendental function in a constant expression, for one) or a loop runs past
// its budget.
std::vector<glm::dvec3> profileSpread(const Model& m, const shader::Sources& src,
                                      const ParamValues& values, const Builtins& b,
                                      const std::vector<double>& radii,
                                      int patterns = kConditioningPatterns);

// Bssrdf(0, Wi, Xo, Wo) at `queries` (as evaluateQueries), unperturbed ([0]) and under seeds
// 1 … patterns ([1] …), for callers that reduce the values before they compare (the BSSRDF slice
// averages many queries per bin). Throws as profileSpread.
std::vector<std::vector<glm::dvec3>> perturbedQueries(const Model& m, const shader::Sources& src,
                                                      const ParamValues& values, const Builtins& b,
                                                      const std::vector<Query>& queries,
                                                      int patterns = kConditioningPatterns);

} // namespace bssrdf
