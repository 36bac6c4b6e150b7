// The ImGui frame loop: windowed (GLFW backend, real window) or headless (EGL context, the
// whole UI rendered into an FBO, io.DisplaySize set by hand) — same panels, same pixels.
#pragma once

#include "gl/gl.h"
#include "workbench.h"

#include <string>

namespace app {

struct GuiOptions {
    int width = 1280, height = 860;
    int frames = 3;             // headless: frames to run before the screenshot
    std::string screenshotPath; // headless: PNG of what a user would see
    bool persistLayout = true;  // load/save window layout and panel visibility
};

// Runs until the window closes (windowed) or for `frames` frames (headless). Returns 0 on
// success, 1 when the screenshot could not be written.
int runGui(Workbench& wb, gl::Context& ctx, const GuiOptions& options);

} // namespace app
