// gl windowed context: GLFW window with an OpenGL 4.5 core profile context, sized in UI units
// of the UI scale's screen pixels.
#include "gl.h"

#include "core/core.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace gl {
namespace {

void glfwErrorCallback(int code, const char* text) {
    core::logDebug("GLFW error " + std::to_string(code) + ": " + text);
}

class GlfwContext final : public Context {
  public:
    GlfwContext(int width, int height, const std::string& title, bool debug, float uiScale) {
        glfwSetErrorCallback(glfwErrorCallback);
        if (!glfwInit()) throw core::Error("GLFW: cannot initialise (no display?)");
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
        // fit the primary monitor's work area (decorations are known once the window exists)
        int ax = 0, ay = 0, aw = 0, ah = 0;
        GLFWmonitor* monitor = glfwGetPrimaryMonitor();
        if (monitor) glfwGetMonitorWorkarea(monitor, &ax, &ay, &aw, &ah);
        WindowSize size =
            aw > 0 && ah > 0 ? fitWindowSize(width, height, aw, ah) : WindowSize{width, height};
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        // Reset notification (reset.cpp) where the driver grants it; else a context without.
        glfwWindowHint(GLFW_CONTEXT_ROBUSTNESS, GLFW_LOSE_CONTEXT_ON_RESET);
        m_window = glfwCreateWindow(size.width, size.height, title.c_str(), nullptr, nullptr);
        if (!m_window) {
            glfwWindowHint(GLFW_CONTEXT_ROBUSTNESS, GLFW_NO_ROBUSTNESS);
            m_window = glfwCreateWindow(size.width, size.height, title.c_str(), nullptr, nullptr);
        }
        if (!m_window) {
            glfwTerminate();
            throw core::Error("GLFW: cannot open an OpenGL 4.5 core window");
        }
        // UI units to the window's screen coordinates: the UI scale over the framebuffer's
        // pixels per screen coordinate (1 on X11, where the window is sized in pixels; the
        // content scale where the platform scales windows itself: Wayland, macOS)
        int ww = 0, wh = 0, fw = 0, fh = 0;
        glfwGetWindowSize(m_window, &ww, &wh);
        glfwGetFramebufferSize(m_window, &fw, &fh);
        const float scale = uiScale > 0 ? uiScale : contentScale(m_window);
        const double perUnit = ww > 0 && fw > 0 ? scale / (double(fw) / ww) : 1.0;
        const int wantW = int(std::lround(width * perUnit)),
                  wantH = int(std::lround(height * perUnit));
        if (aw > 0 && ah > 0) {
            int left = 0, top = 0, right = 0, bottom = 0;
            glfwGetWindowFrameSize(m_window, &left, &top, &right, &bottom);
            size = fitWindowSize(wantW, wantH, aw, ah, left + right, top + bottom);
            glfwSetWindowSize(m_window, size.width, size.height);
            glfwSetWindowPos(m_window, ax + left, ay + top);
        } else {
            glfwSetWindowSize(m_window, wantW, wantH);
        }
        glfwShowWindow(m_window);
        makeCurrent();
        glfwSwapInterval(1);
        try {
            requireLimits();
        } catch (...) {
            glfwDestroyWindow(m_window);
            glfwTerminate();
            throw;
        }
        if (debug) installDebugOutput();
        forgetBarrierState();
        installBarrierChecks(glfwGetProcAddress);
        installWaitDeadlines(glfwGetProcAddress);
    }
    ~GlfwContext() override {
        glfwDestroyWindow(m_window);
        glfwTerminate();
    }
    void makeCurrent() override { glfwMakeContextCurrent(m_window); }
    GLFWwindow* window() const override { return m_window; }

  private:
    GLFWwindow* m_window = nullptr;
};

} // namespace

WindowSize fitWindowSize(int wantW, int wantH, int areaW, int areaH, int frameW, int frameH) {
    const double availW = std::max(1, areaW - frameW), availH = std::max(1, areaH - frameH);
    double scale = std::min({1.0, availW / std::max(1, wantW), availH / std::max(1, wantH)});
    WindowSize s{int(std::lround(wantW * scale)), int(std::lround(wantH * scale))};
    // a floor for usability, unless the screen is smaller still
    s.width = std::min(std::max(s.width, 640), int(availW));
    s.height = std::min(std::max(s.height, 400), int(availH));
    return s;
}

std::unique_ptr<Context> createWindowContext(int width, int height, const std::string& title,
                                             bool debug, float uiScale) {
    return std::make_unique<GlfwContext>(width, height, title, debug, uiScale);
}

float contentScale(GLFWwindow* window) {
    float x = 1, y = 1;
    glfwGetWindowContentScale(window, &x, &y);
    return std::isfinite(x) && x >= 0.25f && x <= 8.0f ? x : 1.0f;
}

bool displayAvailable() {
    const char* x = std::getenv("DISPLAY");
    const char* w = std::getenv("WAYLAND_DISPLAY");
    if ((!x || !*x) && (!w || !*w)) return false;
    glfwSetErrorCallback(glfwErrorCallback);
    if (!glfwInit()) return false;
    glfwTerminate();
    return true;
}

} // namespace gl
