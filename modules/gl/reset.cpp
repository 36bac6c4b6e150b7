// gl reset: the driver's graphics-reset status (OpenGL 4.5 §2.3.2, glGetGraphicsResetStatus).
// Both contexts ask for reset notification (EGL_EXT_create_context_robustness, GLFW's
// GLFW_LOSE_CONTEXT_ON_RESET) where the driver offers it: after a GPU hang or a driver reset
// such a context is lost, every GL call does nothing, and this status says so instead of the
// program drawing black frames or waiting for work that never ends. The GUI restarts on a new
// context with its state (gui.cpp); GPU waits name the reset (fence.cpp).
// BSSRDF_WORKBENCH_SIMULATE_GL_RESET=N makes the N-th query and every later one report a reset
// this program caused: how the tests exercise the recovery on drivers that never reset.
#include "gl.h"

#include "core/core.h"

#include <atomic>
#include <cstdlib>
#include <string>

namespace gl {
namespace {

constexpr const char* kSimulateVar = "BSSRDF_WORKBENCH_SIMULATE_GL_RESET";

// The query from which a reset is simulated (0: none), read once.
long simulatedFrom() {
    static const long from = [] {
        const char* v = std::getenv(kSimulateVar);
        if (!v || !*v) return 0L;
        char* end = nullptr;
        const long n = std::strtol(v, &end, 10);
        if (*end != '\0' || n < 1)
            throw core::Error(kSimulateVar, 0,
                              std::string("expected a query count >= 1, got '") + v + "'");
        return n;
    }();
    return from;
}

std::atomic<long> g_queries{0};
std::atomic<bool> g_lost{false};

ResetStatus queryResetStatus() {
    const long from = simulatedFrom();
    if (from > 0 && ++g_queries >= from) return ResetStatus::Guilty;
    switch (glGetGraphicsResetStatus()) {
    case GL_NO_ERROR:
        return ResetStatus::None;
    case GL_GUILTY_CONTEXT_RESET:
        return ResetStatus::Guilty;
    case GL_INNOCENT_CONTEXT_RESET:
        return ResetStatus::Innocent;
    default:
        return ResetStatus::Unknown;
    }
}

} // namespace

ResetStatus graphicsResetStatus() {
    const ResetStatus s = queryResetStatus();
    if (s != ResetStatus::None) g_lost = true;
    return s;
}

bool contextLost() {
    return g_lost;
}

std::string describe(ResetStatus s) {
    switch (s) {
    case ResetStatus::None:
        return "no reset";
    case ResetStatus::Guilty:
        return "the GPU driver reset the OpenGL context, after GPU work of this program hung or "
               "faulted";
    case ResetStatus::Innocent:
        return "the GPU driver reset the OpenGL context, after GPU work of another program hung "
               "or faulted";
    default:
        return "the GPU driver reset the OpenGL context (cause unknown)";
    }
}

bool resetNotificationRequested() {
    GLint strategy = 0;
    glGetIntegerv(GL_RESET_NOTIFICATION_STRATEGY, &strategy);
    return strategy == GL_LOSE_CONTEXT_ON_RESET;
}

void stopSimulatedResetsInChildren() {
    unsetenv(kSimulateVar);
}

} // namespace gl
