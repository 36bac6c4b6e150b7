// bssrdf/loop_sites.h: where a model's code loops. A model that does not finish (its check
// timed out, the driver cut a loop at its iteration limit, or the compiler dropped the code after
// a loop that never ends) is reported at its loops' lines, which a scan of the model's GLSL
// sections can tell: `for`, `while` and `do` statements outside comments (the `while` that
// closes a `do` block is the `do`'s). Written by hand: no packaged library lexes GLSL.
#pragma once

#include "bssrdf/bssrdf.h"

#include <functional>
#include <string>
#include <vector>

namespace bssrdf {

struct LoopSite {
    int line = 0;        // 1-based line in the model file
    std::string keyword; // "for", "while" or "do"
};

// Calls onWord(word, at, line, lastCode) for every identifier or keyword of `code` outside
// comments (a /* */ comment may span lines) and preprocessor lines: `at` is its index in `code`,
// `line` its file line (`firstLine` is the code's first), `lastCode` the last character of
// code before it (0 at the start). The one scan of a model's GLSL that loopSites and the loop
// budget's rewrite (loop_budget.h) share.
void forEachWord(
    const std::string& code, int firstLine,
    const std::function<void(const std::string& word, size_t at, int line, char lastCode)>& onWord);

// Every loop statement of the model's code sections, in file order.
std::vector<LoopSite> loopSites(const Model& m);

// Calls onDefine(text, line) for every `#define` of `code`: its logical line (a trailing
// backslash continues it), `line` the file line it starts on. The one scan of macros that
// loopInMacro and the model check's frame key (model_probe.h) share.
void forEachDefine(const std::string& code, int firstLine,
                   const std::function<void(const std::string& text, int line)>& onDefine);

// The file line of the first `#define` of `code` (with its continued lines) that could make a
// loop the scan above does not see (it leaves preprocessor lines alone, and so does the loop
// budget's rewrite): one naming `for`, `while` or `do` outside a `//` comment, or one pasting
// tokens (`##`, which can make a keyword). 0 for none.
int loopInMacro(const std::string& code, int firstLine);

// "the loop at line 12 (for)" or "loops at lines 12 (for), 20 (while)"; "" for none.
std::string describeLoops(const std::vector<LoopSite>& loops);

} // namespace bssrdf
