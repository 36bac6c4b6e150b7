// gl headless context: EGL with the surfaceless platform (Mesa), then the device platform,
// then the default display; OpenGL 4.5 core, no surface (everything renders into FBOs).
#include "gl.h"

#include "core/core.h"

#include <epoxy/egl.h>

namespace gl {
namespace {

class EglContext final : public Context {
  public:
    explicit EglContext(bool debug) {
        m_display = openDisplay();
        EGLint major = 0, minor = 0;
        if (!eglInitialize(m_display, &major, &minor))
            throw core::Error("EGL: eglInitialize failed (no usable EGL driver)");
        if (!eglBindAPI(EGL_OPENGL_API)) throw core::Error("EGL: OpenGL API not supported");
        const EGLint cfgAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        eglChooseConfig(m_display, cfgAttribs, &config, 1, &count);
        // Reset notification where the driver offers it (reset.cpp): a context lost after a GPU
        // hang says so instead of doing nothing in silence. EGL 1.5's attribute, else
        // EGL_EXT_create_context_robustness's (Mesa refuses the latter for desktop OpenGL), else
        // a context without it.
        const bool egl15 = major > 1 || (major == 1 && minor >= 5);
        const bool ext = epoxy_has_egl_extension(m_display, "EGL_EXT_create_context_robustness");
        const EGLint strategies[][2] = {
            {egl15 ? EGL_CONTEXT_OPENGL_RESET_NOTIFICATION_STRATEGY : EGL_NONE,
             EGL_LOSE_CONTEXT_ON_RESET},
            {ext ? EGL_CONTEXT_OPENGL_RESET_NOTIFICATION_STRATEGY_EXT : EGL_NONE,
             EGL_LOSE_CONTEXT_ON_RESET_EXT},
            {EGL_NONE, EGL_NONE}};
        for (const auto& strategy : strategies) {
            if (strategy[0] == EGL_NONE && &strategy != &strategies[2]) continue;
            const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                         4,
                                         EGL_CONTEXT_MINOR_VERSION,
                                         5,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_CONTEXT_OPENGL_DEBUG,
                                         debug ? EGL_TRUE : EGL_FALSE,
                                         strategy[0],
                                         strategy[1],
                                         EGL_NONE};
            m_context = eglCreateContext(m_display, count > 0 ? config : EGL_NO_CONFIG_KHR,
                                         EGL_NO_CONTEXT, ctxAttribs);
            if (m_context != EGL_NO_CONTEXT) break;
        }
        if (m_context == EGL_NO_CONTEXT)
            throw core::Error("EGL: cannot create an OpenGL 4.5 core context (error 0x" +
                              hex(eglGetError()) + ")");
        try {
            makeCurrent();
            if (epoxy_gl_version() < 45)
                throw core::Error("EGL: OpenGL 4.5 required, driver gives " +
                                  std::to_string(epoxy_gl_version() / 10) + "." +
                                  std::to_string(epoxy_gl_version() % 10));
            requireLimits();
        } catch (...) {
            release(); // no destructor runs for a constructor that throws
            throw;
        }
        if (debug) installDebugOutput();
        forgetBarrierState();
        installBarrierChecks(eglGetProcAddress);
        installWaitDeadlines(eglGetProcAddress);
    }
    ~EglContext() override { release(); }
    void release() {
        if (m_display != EGL_NO_DISPLAY) {
            eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            if (m_context != EGL_NO_CONTEXT) eglDestroyContext(m_display, m_context);
            eglTerminate(m_display);
        }
        m_display = EGL_NO_DISPLAY;
        m_context = EGL_NO_CONTEXT;
    }
    void makeCurrent() override {
        if (!eglMakeCurrent(m_display, EGL_NO_SURFACE, EGL_NO_SURFACE, m_context))
            throw core::Error("EGL: eglMakeCurrent failed (error 0x" + hex(eglGetError()) + ")");
    }

  private:
    static std::string hex(EGLint v) {
        char b[16];
        std::snprintf(b, sizeof b, "%x", static_cast<unsigned>(v));
        return b;
    }
    static EGLDisplay openDisplay() {
        if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
            EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA,
                                                    EGL_DEFAULT_DISPLAY, nullptr);
            if (d != EGL_NO_DISPLAY) return d;
        }
        if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device")) {
            EGLDeviceEXT devices[8];
            EGLint n = 0;
            if (eglQueryDevicesEXT(8, devices, &n) && n > 0) {
                EGLDisplay d =
                    eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr);
                if (d != EGL_NO_DISPLAY) return d;
            }
        }
        EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        if (d == EGL_NO_DISPLAY) throw core::Error("EGL: no display available");
        return d;
    }

    EGLDisplay m_display = EGL_NO_DISPLAY;
    EGLContext m_context = EGL_NO_CONTEXT;
};

} // namespace

std::unique_ptr<Context> createHeadlessContext(bool debug) {
    return std::make_unique<EglContext>(debug);
}

std::string Context::renderer() const {
    const GLubyte* s = glGetString(GL_RENDERER);
    return s ? reinterpret_cast<const char*>(s) : "unknown";
}
std::string Context::version() const {
    const GLubyte* s = glGetString(GL_VERSION);
    return s ? reinterpret_cast<const char*>(s) : "unknown";
}

} // namespace gl
