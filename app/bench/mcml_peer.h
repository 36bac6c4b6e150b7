// bench pathtrace --mcml: MCML 1.2.2 timed on this machine as the CPU peer (mcml_peer.cpp).
#pragma once

#include "pathtrace/pathtrace.h"

#include <filesystem>
#include <vector>

namespace app {

struct McmlCase {
    double binMm = 0.15; // MCML's dr (in mm here)
    int bins = 400;      // its nr (the last is MCML's overflow bin)
    long long photonsPerBatch = 100000;
    int batches = 20; // 2·10^6 photons in all
};

struct McmlPeer {
    double seconds = 0, photons = 0, photonsPerSecond = 0;
    std::vector<double> relVar; // per bin: relative variance per photon, from the batches
};

// Runs MCML (`exe`, its `mcml` binary) on the semi-infinite slab of medium `m` under a pencil
// beam, `c.batches` runs in one process. Throws core::Error naming `exe` when it is missing,
// fails or writes no output.
McmlPeer runMcmlPeer(const std::filesystem::path& exe, const pathtrace::Medium& m,
                     const McmlCase& c);

} // namespace app
