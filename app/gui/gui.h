// The ImGui frame loop: windowed (GLFW backend, real window) or headless (EGL context, the
// whole UI rendered into an FBO, io.DisplaySize set by hand) — same panels, same pixels.
#pragma once

#include "gl/gl.h"
#include "gui/ui_state.h"
#include "pipeline/workbench.h"

#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace app {

// The windowed frame loop sleeps up to this long before each frame unless an event ends the
// sleep (input, a save, a child's output); the reload bench paces one of its passes by it.
inline constexpr double kFrameWaitSeconds = 0.03;

struct GuiOptions {
    int width = 1600, height = 1000;
    // headless: frames to run before the screenshot; the layout has settled by the fourth (a
    // window is laid out once before ImGui knows whether it needs a scrollbar)
    int frames = 5;
    std::string screenshotPath; // headless: PNG of what a user would see
    bool persistLayout = true;  // load/save window layout and panel visibility
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

// The window size the last session saved (Window=W,H in the layout file, imgui.ini under
// $XDG_CONFIG_HOME or ~/.config/bssrdf-workbench), when it holds two sizes in [320, 16384].
std::optional<std::pair<int, int>> rememberedWindowSize();

// The whole UI rendered into an FBO on the current (headless) context, one frame per call.
class HeadlessGui {
  public:
    HeadlessGui(Workbench& wb, int width, int height);
    ~HeadlessGui();
    HeadlessGui(const HeadlessGui&) = delete;
    HeadlessGui& operator=(const HeadlessGui&) = delete;
    // Updates the workbench, draws every open panel, renders; returns whether stages re-ran.
    bool frame();
    std::vector<unsigned char> pixels() const; // RGBA8, top row first, opaque
    UiState& ui();                             // panel toggles and pending requests
    // Input for the next frames (tests): the mouse at (x, y) in pixels from the top left,
    // the left button held or not; noMouse() takes it away again.
    void mouse(float x, float y, bool down);
    void noMouse() { m_hasMouse = false; }
    void resize(int width, int height); // the window resized: the next frames draw at this size
    int width() const { return m_width; }
    int height() const { return m_height; }

  private:
    Workbench& m_wb;
    int m_width, m_height;
    gl::RenderTarget m_target;
    bool m_ownsContext = false; // created its own ImGui context (used outside runGui)
    bool m_hasMouse = false, m_mouseDown = false;
    float m_mouseX = 0, m_mouseY = 0;
};

// Runs until the window closes (windowed) or for `frames` frames (headless). Returns 0 on
// success, 1 when the screenshot could not be written.
int runGui(Workbench& wb, gl::Context& ctx, const GuiOptions& options);

} // namespace app
