// The check of a new or changed model in a child process (bssrdf/model_probe.h): the workbench
// executable re-run as `bssrdf-workbench --root ROOT probe-model FILE …` (cli/probe_commands.h)
// makes its own headless GL context, builds the model's pencil (and inversion) program and
// evaluates it once with the current parameters at the pencil plot's radii. The model is adopted
// only when the child finishes that evaluation within the limit; otherwise the child is killed and
// the model's Errors entry says why. The GUI polls the child once per frame; the CLI waits for it.
//
// Kept warm: the first check of a process starts `bssrdf-workbench probe-server`
// (cli/probe_commands.h), which keeps its GL context and takes one check after another, so a saved
// model is checked without a process start and a context creation. A check that runs out of time
// kills that server (its GL call cannot be interrupted) and a new one starts at once, warming up
// for the next; so does a check given up before its verdict (a newer save replaced it). While the
// server is busy with a check of another model, a check runs in its own `probe-model` process, as
// before.
//
// Needed only for loops: a model whose code has none, in a frame (templates, includes,
// parameters) in which a check passed, is not checked (bssrdf::probeFrameKey). Its code is still
// new to the driver, and generating it at the first dispatch holds the GUI thread (llvmpipe:
// about 100 ms for the pencil program), so while the server is free it generates that code
// instead (`probe-model --code-only`: the programs the check would evaluate, built and
// dispatched with no work) and the model is adopted when it is done, however that ends; the
// driver's on-disk shader cache hands the code to the workbench. When the scene shows the model,
// the server then generates the renderer's traversal program's code too (on llvmpipe about 1 s)
// while the plot already shows the new model, and the scene takes the model once that is done
// (rendererCodePending); so it does after a check that passed in the server. With the server
// busy, or the cache off, the model is adopted at once as before.
#pragma once

#include "bssrdf/model_probe.h"
#include "probe/child_process.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace app {

// Seconds a model's first evaluation may take in the child (after its GL context and programs
// are ready); $BSSRDF_WORKBENCH_PROBE_SECONDS overrides it (tests).
inline constexpr double kModelProbeSeconds = 5.0;
// Seconds the child may take to start and build the programs (oblique tables take several
// seconds per program on llvmpipe; the main process builds them too).
inline constexpr double kModelProbeStartSeconds = 120.0;
double modelProbeSeconds();

// The executable that runs the checks; empty (the default) turns them off. main() sets itself;
// test programs set the workbench executable.
void setModelProbeExecutable(const std::filesystem::path& exe);
const std::filesystem::path& modelProbeExecutable();

// What the check evaluates besides the model file: the parameters the model starts with; and
// the frame size of the scene when it shows this model (0: it does not), for the code of the
// renderer's traversal program.
struct ProbeInputs {
    bssrdf::Builtins builtins;
    double rMaxMm = 20.0;
    int samples = 512;
    int renderWidth = 0, renderHeight = 0;
};

// Seconds the server may take over the traversal program's code after the model's adoption (its
// code generated, or its check passed); past them the scene generates it itself.
inline constexpr double kRendererCodeSeconds = 30.0;
// Whether the server is still generating the traversal program's code of the model adopted
// last from `display` (its display path): the scene keeps its last frame until it is done.
bool rendererCodePending(const std::string& display);

// Starts checks of models under `root` with the inputs `inputsFor(file)` gives; a model text
// whose key passed in this process before is adopted without a check.
bssrdf::ProbeStarter
makeProbeStarter(std::filesystem::path root,
                 std::function<ProbeInputs(const std::filesystem::path&)> inputsFor);

// The verdict on a check that ended with exit status `code` (the server's `done CODE`) and
// printed `output`.
bssrdf::ProbeVerdict probeVerdict(int code, const std::string& output, const std::string& display,
                                  const std::string& key);

// The process id of the warm server, -1 when none runs, and counts since the process started:
// checks the server took, checks run in their own process, servers started, and checks (of
// either kind) seen evaluating, their model file read and built (tests, bench).
int probeServerPid();
struct ProbeCounts {
    long served = 0, ownProcess = 0, serverStarts = 0, evaluating = 0;
    long unneeded = 0; // loop-free models adopted in a frame that passed (bssrdf::probeFrameKey)
    long codeOnly = 0; // of those, the ones whose code the server generated before adoption
    long traversalCode = 0; // answers of the server with the traversal program's code
};
ProbeCounts probeCounts();
// Forgets every verdict of this process and ends the warm server (the next check starts one,
// with the environment of then): tests that each want a process's first state.
void resetModelProbes();

// One check under way in its own process.
class ModelProbeProcess : public bssrdf::PendingProbe {
  public:
    // args: the command line; display: the model's display path; key: bssrdf::probeKey.
    ModelProbeProcess(const std::vector<std::string>& args, std::string display, std::string key,
                      int evaluations);
    bssrdf::ProbeVerdict poll() override;
    bssrdf::ProbeVerdict wait() override;

  private:
    ChildProcess m_child;
    std::string m_display, m_key;
    int m_evaluations;
    double m_limit;
    double m_startMs;
    double m_evalStartMs = -1;
};

} // namespace app
