// bssrdf/detail: one dispatch of a model consumer that reads `inVec4` vec4 per entry from
// binding 0 and writes one vec4 per entry to binding 1 (pencil_profile.comp, invert_rdr.comp).
#pragma once

#include "gl/gl.h"

#include <cstddef>
#include <vector>

namespace bssrdf::detail {

// Uploads `in` (`inVec4` vec4 per entry), dispatches `count` invocations, reads back a vec4
// per entry. `queries` sets pencil_profile.comp's Queries uniform where the program has it.
std::vector<float> runBatch(GLuint program, const std::vector<float>& in, size_t count,
                            size_t inVec4 = 1, GLuint queries = 0);

} // namespace bssrdf::detail
