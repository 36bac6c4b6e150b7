// `bssrdf-workbench probe-model FILE …` (hidden; model_probe_process.h runs it): the check of a
// new or changed model. Makes its own headless GL context, builds the model's pencil (and
// inversion) program, prints `probe-model: key KEY`, generates the code, prints
// `probe-model: evaluating`, evaluates the pencil profile at the given radii with the given
// parameters (bssrdf::evaluateProbe), and exits 0 when it ended, kProbeLoopCut when a loop in
// the model was cut short by the driver's iteration limit, kProbeUnavailable without a GL
// context, 1 for any other error. Killed by its parent when the evaluation takes too long.
//
// `bssrdf-workbench probe-server` (hidden): the same check, kept warm. It makes its GL context
// once, prints `probe-model: ready`, then reads requests from stdin, each the fields
// ROOT, FILE, options… of one check separated by kProbeFieldSeparator and ended by
// kProbeRequestEnd, runs the check as `--root ROOT probe-model FILE options…` would (same
// output), and ends it with `probe-model: done CODE` (CODE: that command's exit status). It
// exits 0 at the end of its input, kProbeUnavailable without a GL context. A check that hangs
// hangs the server: its parent kills it and starts another.
#pragma once

#include "probe/protocol.h"

#include <filesystem>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace app {

struct ProbeModelArgs {
    std::string file;
    std::string sigmaA = "0.0021,0.0041,0.0071", sigmaS = "2.19,2.62,3"; // R,G,B in 1/mm
    double g = 0, eta = 1.3, scale = 1, rMax = 20;
    int samples = 512;
    std::vector<std::string> params; // NAME=V or NAME=R,G,B
    // Generate the programs' code and stop, evaluating nothing: for a model that needs no check
    // (bssrdf::probeFrameKey), so that its code reaches the workbench through the driver's
    // shader cache instead of being generated on its GUI thread (probe/model_probe_process.h).
    bool codeOnly = false;
    // After the programs' code (codeOnly) or a check that passed, the renderer's traversal
    // program's code for a frame of this size (render::warmTraversal); 0: none.
    int renderWidth = 0, renderHeight = 0;
};

void addProbeModelOptions(CLI::App* cmd, ProbeModelArgs& a);
int runProbeModel(const std::filesystem::path& root, const ProbeModelArgs& a);
// The check with a GL context already current; throws core::Error for a model that cannot be
// loaded or built.
int probeModel(const std::filesystem::path& root, const ProbeModelArgs& a);
int runProbeServer();

} // namespace app
