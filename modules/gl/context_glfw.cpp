// gl windowed context: GLFW window with an OpenGL 4.5 core profile context.
#include "gl.h"

#include "core/core.h"

#include <GLFW/glfw3.h>

#include <cstdlib>

namespace gl {
namespace {

void glfwErrorCallback(int code, const char* text) {
    core::logDebug("GLFW error " + std::to_string(code) + ": " + text);
}

class GlfwContext final : public Context {
  public:
    GlfwContext(int width, int height, const std::string& title, bool debug) {
        glfwSetErrorCallback(glfwErrorCallback);
        if (!glfwInit()) throw core::Error("GLFW: cannot initialise (no display?)");
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, debug ? GLFW_TRUE : GLFW_FALSE);
        m_window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
        if (!m_window) {
            glfwTerminate();
            throw core::Error("GLFW: cannot open an OpenGL 4.5 core window");
        }
        makeCurrent();
        glfwSwapInterval(1);
        if (debug) installDebugOutput();
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

std::unique_ptr<Context> createWindowContext(int width, int height, const std::string& title,
                                             bool debug) {
    return std::make_unique<GlfwContext>(width, height, title, debug);
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
