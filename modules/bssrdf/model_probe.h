// bssrdf model probe: the check a new or changed model passes before the library adopts it. A
// model's Bssrdf() may loop for ever or for very long, and a GL call that waits for such a
// dispatch cannot be interrupted by the thread that made it, so the model's first evaluation
// runs elsewhere (the workbench: in a child process with a time limit,
// app/model_probe_process.h) and ModelLibrary adopts the model only once it finished in time.
//   probeKey      what the check evaluates: the assembled pencil (and inversion) programs, i.e.
//                 the model's text, the templates and every include; a key that passed once is
//                 not checked again, so an unchanged model reloads at its usual cost.
//   probeFrameKey what surrounds a loop-free model's code: once a check passed in that frame,
//                 a loop-free model needs none (its straight-line code cannot run away).
//   warmUp        makes the driver generate the program's code without evaluating the model.
//   evaluateProbe the check itself: pencil_profile.comp (and invert_rdr.comp) with a sentinel
//                 loop after the model, which tells a loop the driver cut short (Mesa llvmpipe
//                 stops a shader invocation's loops after 65 535 iterations in total), and an
//                 output the invocation never wrote (the GLSL compiler may drop the code after
//                 a loop that provably never ends, so the invocation ends without a value).
#pragma once

#include "bssrdf/program.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace bssrdf {

// Where a check stands. done && problem.empty(): adopt; done && !problem.empty(): the Errors
// entry's message (the last good version stays).
struct ProbeVerdict {
    bool done = false;
    std::string problem;
};

// One check under way; the destructor stops it.
class PendingProbe {
  public:
    virtual ~PendingProbe() = default;
    virtual ProbeVerdict poll() = 0; // never blocks
    virtual ProbeVerdict wait() = 0; // blocks, at most for the check's own time limit
    // False for a model that needs no check, whose code is only generated elsewhere first.
    virtual bool evaluates() const { return true; }
};

// Starts the check of `candidate` (read from `file`, to be adopted with `values`); nullptr when
// none is needed (its key passed before).
using ProbeStarter = std::function<std::unique_ptr<PendingProbe>(
    const std::filesystem::path& file, const Model& candidate, const ParamValues& values,
    const std::string& key)>;

// A hash of the GLSL the check evaluates (the same text on every run of the same files).
std::string probeKey(const Model& m, const shader::Sources& src);
// For a model whose code sections have no loop (no `for`, `while` or `do`: loop_sites.h) and no
// `#define` (a macro may hide a loop from that scan), a hash
// of the GLSL around its code (probeKey with the sections' code, their lines and the source left
// out: templates, includes, parameters, attributes); "" for any other model. Straight-line
// code ends, and every loop of the GLSL around it is bounded by a count the host sets, so once a
// check passed with that frame a loop-free model in it needs none: only its loops can run away.
std::string probeFrameKey(const Model& m, const shader::Sources& src);

// Whether the inversion program (invert_rdr.comp: init() and DiffuseReflectance()) can reach a
// loop of the model, so that the check must evaluate it too: a loop in the initializer or
// diffuseReflectance section, or a function declared there without its body (a prototype, whose
// body a later section may give, with a loop). Sections are assembled in that order and GLSL
// calls only what is declared before, so otherwise those two functions reach only loop-free
// model code and the templates' own bounded loops. False for a model without the section.
bool inversionMayLoop(const Model& m);

// The programs whose code the workbench generates itself (warmUp) while a new version of `m`
// is checked, of those the first frame after adoption dispatches: pencil_profile.comp, and
// invert_rdr.comp where `inversionInUse` (the material inverts R_dr) and the model has the
// section. The check's process generates the code of what it evaluates (the pencil program, the
// inversion where inversionMayLoop) from the same text, and a driver's on-disk shader cache
// hands that code to the workbench at its first dispatch; so only the rest, or everything where
// `driverCacheOff` (gl::driverShaderCacheOff).
std::vector<std::string> programsToWarmDuringCheck(const Model& m, bool inversionInUse,
                                                   bool driverCacheOff);

// Runs a dispatch of `program` in which every invocation returns before the model is called, so
// the driver's code generation (slow for big table models on llvmpipe) is not timed as
// evaluation. `program` is pencil_profile.comp or invert_rdr.comp.
void warmUp(GLuint program);

struct ProbeResult {
    Profile profile;       // the pencil profile at the given radii
    size_t loopsCut = 0;   // radii (and α′) whose sentinel loop was cut short
    size_t notWritten = 0; // radii (and α′) whose value was never written
    size_t evaluated = 0;  // radii + α′ evaluated
};
// Loop length of the sentinel after the model.
inline constexpr unsigned kProbeSentinel = 4;
// The pencil profile at `radii` and, for a model with a diffuseReflectance section, R_dr at a
// few α′ (`inversionProgram` 0 otherwise), each followed by the sentinel loop.
ProbeResult evaluateProbe(GLuint pencilProgram, GLuint inversionProgram, const Model& m,
                          const ParamValues& values, const Builtins& b,
                          const std::vector<double>& radii);

} // namespace bssrdf
