// SIGINT → a cancel flag (interrupt.h). The handler only stores to a lock-free atomic and,
// the second time, restores the default action and re-raises: both async-signal-safe.
#include "cli/interrupt.h"

#include <csignal>

namespace app {
namespace {

std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free);

void onSigint(int sig) {
    if (g_interrupted.exchange(true)) {
        std::signal(sig, SIG_DFL);
        std::raise(sig);
    }
}

} // namespace

const std::atomic<bool>* interruptFlag() {
    static const bool installed = [] {
        struct sigaction sa {};
        sa.sa_handler = onSigint;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, nullptr);
        return true;
    }();
    (void)installed;
    return &g_interrupted;
}

bool interrupted() {
    return g_interrupted.load();
}

} // namespace app
