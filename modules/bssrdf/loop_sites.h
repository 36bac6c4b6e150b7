// bssrdf/loop_sites.h: where a model's code loops. A model that does not finish (its check
// timed out, the driver cut a loop at its iteration limit, or the compiler dropped the code after
// a loop that never ends) is reported at its loops' lines, which a scan of the model's GLSL
// sections can tell: `for`, `while` and `do` statements outside comments (the `while` that
// closes a `do` block is the `do`'s). Written by hand: no packaged library lexes GLSL.
#pragma once

#include "bssrdf/bssrdf.h"

#include <string>
#include <vector>

namespace bssrdf {

struct LoopSite {
    int line = 0;        // 1-based line in the model file
    std::string keyword; // "for", "while" or "do"
};

// Every loop statement of the model's code sections, in file order.
std::vector<LoopSite> loopSites(const Model& m);

// "the loop at line 12 (for)" or "loops at lines 12 (for), 20 (while)"; "" for none.
std::string describeLoops(const std::vector<LoopSite>& loops);

} // namespace bssrdf
