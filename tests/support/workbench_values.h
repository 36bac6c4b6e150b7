// Shared by the hot-reload tests: what a Workbench shows of a model, read without side effects,
// and the loop that updates it until something holds.
#pragma once

#include "pipeline/workbench.h"

#include "core/core.h"

#include <chrono>
#include <string>
#include <thread>

namespace testsupport {

// R of the model's pencil profile at its first radius, channel R; −1 when the model is not
// loaded or has no profile.
inline double valueAt0(app::Workbench& wb, const std::string& path) {
    if (!wb.library().find(path)) return -1.0;
    auto& v = wb.view(path);
    return v.profile.value.empty() ? -1.0 : v.profile.value[0].x;
}

// The text of the first Errors entry containing `what`, "" when there is none.
inline std::string errorNaming(app::Workbench& wb, const std::string& what) {
    for (const auto& e : wb.errors())
        if (e.text.find(what) != std::string::npos) return e.text;
    return "";
}

// Runs wb.update() until `done` holds or `ms` milliseconds have passed (the debounce is 40 ms, a
// rebuild about 100 ms: the limit only bounds a failing test); false when it never held.
template <class F> bool waitFor(app::Workbench& wb, F done, double ms = 8000) {
    core::Stopwatch sw;
    while (sw.ms() < ms) {
        wb.update();
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}

} // namespace testsupport
