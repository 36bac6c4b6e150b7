// SIGINT (and for the window SIGTERM, SIGHUP) → a cancel flag (interrupt.h). The handler only
// stores to lock-free atomics and, the second time, restores the default action and re-raises:
// all async-signal-safe.
#include "cli/interrupt.h"

#include <csignal>
#include <string>

namespace app {
namespace {

std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

void onSignal(int sig) {
    g_signal.store(sig);
    if (g_interrupted.exchange(true)) {
        std::signal(sig, SIG_DFL);
        std::raise(sig);
    }
}

void install(int sig) {
    struct sigaction sa {};
    sa.sa_handler = onSignal;
    sigemptyset(&sa.sa_mask);
    sigaction(sig, &sa, nullptr);
}

} // namespace

const std::atomic<bool>* interruptFlag() {
    static const bool installed = [] {
        install(SIGINT);
        return true;
    }();
    (void)installed;
    return &g_interrupted;
}

const std::atomic<bool>* closeRequestFlag() {
    static const bool installed = [] {
        for (int sig : {SIGINT, SIGTERM, SIGHUP})
            install(sig);
        return true;
    }();
    (void)installed;
    return &g_interrupted;
}

std::string interruptingSignal() {
    switch (g_signal.load()) {
    case SIGINT:
        return "SIGINT (Ctrl-C)";
    case SIGTERM:
        return "SIGTERM";
    case SIGHUP:
        return "SIGHUP (the terminal closed)";
    default:
        return "no signal";
    }
}

bool interrupted() {
    return g_interrupted.load();
}

} // namespace app
