// bssrdf/detail: the 'parameters' section of a .bssrdf file (thesis Appendix A.2):
//   float NAME MIN MAX DEFAULT | bool NAME DEFAULT | color NAME R G B
#pragma once

#include "bssrdf/bssrdf.h"

#include <string>
#include <vector>

namespace bssrdf::detail {

// Parses every declaration of the section; throws core::Error(path, line, ...) on the first
// bad line. Checks types, field counts, numbers, ranges, identifiers, duplicates and
// clashes with builtinNames().
std::vector<Param> parseParameters(const Section& section, const std::string& path);

} // namespace bssrdf::detail
