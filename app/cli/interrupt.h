// Ctrl-C (SIGINT) for long command-line runs: the first one asks the run to stop and keep what
// it has (the tracers' cancel flag: the completed prefix of chunks, still unbiased), so the
// command writes a partial result marked as such and exits with kInterrupted; a second Ctrl-C
// ends the process at once.
#pragma once

#include <atomic>
#include <string>

namespace app {

constexpr int kInterrupted = 130; // 128 + SIGINT, as shells report an interrupted program

// Installs the handler (once) and returns the flag it sets.
const std::atomic<bool>* interruptFlag();
bool interrupted();

// The window's close request: the same flag, set by SIGINT and also by SIGTERM (`kill`, a
// logout) and SIGHUP (the terminal closed), so the GUI leaves as its Quit does (layout saved,
// child processes stopped) instead of dying where it stands; a second signal ends it at once.
const std::atomic<bool>* closeRequestFlag();
// The last of those signals received, for the message ("SIGTERM", …; "no signal" before any).
std::string interruptingSignal();

} // namespace app
