// Ctrl-C (SIGINT) for long command-line runs: the first one asks the run to stop and keep what
// it has (the tracers' cancel flag: the completed prefix of chunks, still unbiased), so the
// command writes a partial result marked as such and exits with kInterrupted; a second Ctrl-C
// ends the process at once.
#pragma once

#include <atomic>

namespace app {

constexpr int kInterrupted = 130; // 128 + SIGINT, as shells report an interrupted program

// Installs the handler (once) and returns the flag it sets.
const std::atomic<bool>* interruptFlag();
bool interrupted();

} // namespace app
