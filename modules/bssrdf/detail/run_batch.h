// bssrdf/detail: one dispatch of a consumer program over a batch of vec4 inputs, shared by the
// consumers (program.cpp), the check of a new model (model_probe.cpp) and the conditioning
// (conditioning.cpp).
#pragma once

#include "bssrdf/bssrdf.h"
#include "bssrdf/program.h"
#include "gl/gl.h"

#include <cstddef>
#include <vector>

namespace bssrdf::detail {

// Uploads `in` (`inVec4` vec4 per entry), dispatches, reads back one vec4 per entry. `queries`
// and `sentinel` set pencil_profile.comp's Queries and Sentinel uniforms where the program has
// them. `outInit` (one vec4 per entry) fills the output buffer before the dispatch, so an
// invocation that never writes its value is seen. A loop of `m` that ran past its budget
// (loop_budget.h) throws core::Error naming the loop's line.
std::vector<float> runBatch(const Model& m, GLuint program, const std::vector<float>& in,
                            size_t count, size_t inVec4 = 1, GLuint queries = 0,
                            GLuint sentinel = 0, const std::vector<float>* outInit = nullptr);

// The input of the query mode (Queries = 1): three vec4 per query, Xo, Wi and Wo in .xyz.
std::vector<float> queryInputs(const std::vector<Query>& queries);

} // namespace bssrdf::detail
