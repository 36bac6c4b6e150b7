// The ImGui frame loop: windowed (GLFW backend, real window) or headless (EGL context, the
// whole UI rendered into an FBO, io.DisplaySize set by hand) — same panels, same pixels.
#pragma once

#include "gl/gl.h"
#include "gui/frame_pacing.h" // kFrameWaitSeconds: the reload bench paces a pass by it
#include "gui/layout_file.h"  // configDir(), rememberedWindowSize()
#include "gui/ui_state.h"
#include "pipeline/workbench.h"

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace app {

struct GuiOptions {
    // The window's (or headless screenshot's) size in UI units: uiScale screen pixels each.
    int width = 1600, height = 1000;
    // Screen pixels per UI unit: every panel, font and field uiScale times as large (2 on a 4K
    // screen at 200 %), laid out as at 1, text rasterised at that size. 0: the display's own
    // scale (the window's content scale, which the desktop sets; 1 headless).
    float uiScale = 0;
    // headless: frames to run before the screenshot; the layout has settled by the fourth (a
    // window is laid out once before ImGui knows whether it needs a scrollbar)
    int frames = 5;
    std::string screenshotPath; // headless: PNG of what a user would see
    bool persistLayout = true;  // load/save window layout and panel visibility
    // with persistLayout: save it as well (false: a window on a capture starts from the layout
    // and leaves it to the project's window)
    bool saveLayout = true;
    // called once the layout is loaded, before the first frame (a window on a capture shows
    // what it recorded: showCapturedState)
    std::function<void(UiState&)> prepare;
    // window: set (by a signal: cli/interrupt.h) to close it as File > Quit does
    const std::atomic<bool>* closeRequest = nullptr;
};

// After a GPU driver reset (gl::graphicsResetStatus, checked after every frame) runGui saves the
// workbench's state (models, parameters, settings: a capture's inputs, with the reason) to
// glResetRequest(root) and returns kGlResetRestart; the command then starts the program again
// on a new context (--restore-after-reset), where workbenchAfterReset() rebuilds the workbench
// from it with an Errors entry naming the reset.
constexpr int kGlResetRestart = 75;
std::filesystem::path glResetRequest(const std::filesystem::path& root);
std::unique_ptr<Workbench> workbenchAfterReset(const std::filesystem::path& root, bool watch);

// `units` UI units in pixels at `uiScale` (rounded).
int scaledSize(int units, float uiScale);

// The whole UI rendered into an FBO on the current (headless) context, one frame per call.
class HeadlessGui {
  public:
    // width x height UI units, uiScale pixels each (pixels() is uiScale times as large).
    HeadlessGui(Workbench& wb, int width, int height, float uiScale = 1.0f);
    ~HeadlessGui();
    HeadlessGui(const HeadlessGui&) = delete;
    HeadlessGui& operator=(const HeadlessGui&) = delete;
    // Updates the workbench, draws every open panel, renders; returns whether stages re-ran.
    bool frame();
    // RGBA8, top row first, opaque: pixelWidth() x pixelHeight()
    std::vector<unsigned char> pixels() const;
    UiState& ui(); // panel toggles and pending requests
    // Input for the next frames (tests): the mouse at (x, y) in UI units from the top left,
    // the left button held or not; noMouse() takes it away again.
    void mouse(float x, float y, bool down);
    void noMouse() { m_hasMouse = false; }
    void resize(int width, int height); // the window resized: the next frames draw at this size
    // The window went to a screen that scales differently: the fonts rasterised again and the
    // next frames drawn at `uiScale` pixels per unit (as the windowed loop does).
    void setUiScale(float uiScale);
    int width() const { return m_width; }
    int height() const { return m_height; }
    int pixelWidth() const { return scaledSize(m_width, m_scale); }
    int pixelHeight() const { return scaledSize(m_height, m_scale); }

  private:
    Workbench& m_wb;
    int m_width, m_height;
    float m_scale;
    gl::RenderTarget m_target;
    bool m_ownsContext = false; // created its own ImGui context (used outside runGui)
    bool m_hasMouse = false, m_mouseDown = false;
    float m_mouseX = 0, m_mouseY = 0;
};

// Runs until the window closes (windowed) or for `frames` frames (headless). Returns 0 on
// success, 1 when the screenshot could not be written.
int runGui(Workbench& wb, gl::Context& ctx, const GuiOptions& options);

} // namespace app
