// bssrdf/loop_budget.h: no loop of a model's code runs for ever, on any driver. Mesa llvmpipe
// stops a shader invocation's loops after 65 535 iterations; a GPU driver has no such limit, so a
// `Bssrdf()` that loops for ever (or 10^9 times) for some inputs would hang the dispatch, the GL
// call that waits for it and the program. So the assembly (assembly.cpp) rewrites every `for` and
// `while` condition of the model's sections into `(condition) && bw_loop(site)`, keeping the
// file's line numbers:
//   - bw_loop counts the invocation's iterations since its last `Bssrdf()` call began (init(),
//     DiffuseReflectance() and the sampler count from the invocation's start) and returns false
//     past the host's budget (uniform BwLoopBudget, kLoopBudget), which ends the loop;
//   - the invocation then stays stopped: every later loop of the model in it ends at once, and
//     it counts itself in an atomic counter (binding 0), with the site that ran out;
//   - every 256 iterations a loop also reads that counter, so once one invocation ran out the
//     others of the dispatch stop within 256 iterations: a dispatch costs at most about one
//     budget per invocation in flight, whatever its size.
// The host (LoopFaults) zeroes and binds the counters before its dispatches and reads them with
// its results: a loop that ran out is core::Error(model file, the loop's line, ...), which each
// consumer reports as it reports any other model error (an Errors entry, a CLI error).
// Loops inside a `#define` are not rewritten. Written by hand: no packaged library rewrites GLSL.
#pragma once

#include "bssrdf/bssrdf.h"
#include "gl/gl.h"

#include <string>
#include <vector>

namespace bssrdf {

// Loop iterations one call of Bssrdf() may run (and init(), DiffuseReflectance() and the sampler
// together, per invocation). The models shipped need at most 1000 (multipole's sum); it is below
// llvmpipe's 65 535, so there too a runaway loop is reported rather than cut silently.
constexpr unsigned kLoopBudget = 16384;
// kLoopBudget, or $BSSRDF_WORKBENCH_LOOP_BUDGET (1 to 2^31) for a model that needs more; a
// malformed value is an error naming the variable.
unsigned loopBudget();

// `code` with every loop condition guarded: `for (a; b; c)` -> `for (a; (b) && bw_loop(N); c)`
// (an empty b -> `bw_loop(N)`), `while (b)` -> `while ((b) && bw_loop(N))`, N counting on from
// `site`; `lines` gets each guarded loop's file line (`firstLine` is the code's first line).
std::string guardLoops(const std::string& code, int firstLine, unsigned& site,
                       std::vector<int>& lines);

// The file lines of the model's guarded loops, by site (the assembly's order of sections).
std::vector<int> guardedLoopLines(const Model& m);

// The GLSL declared before the model's code when it has loops (bw_loop, the counters, the
// budget uniform), and after it (the Bssrdf() wrapper that restarts the count per call).
std::string loopGuardPrelude();
std::string loopGuardEpilogue(const Model& m);

// The counters of one consumer: arm() before its dispatches (program current), check() after
// reading their results.
class LoopFaults {
  public:
    void arm(GLuint program);
    // Throws core::Error(m.path, line, "... ran past the loop budget ...") when a loop ran out.
    void check(const Model& m);

  private:
    gl::Buffer m_counters;
};

} // namespace bssrdf
