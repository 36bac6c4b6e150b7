// gl waits: every host wait for the GPU has a deadline (gl.h, installWaitDeadlines). The calls
// that make the host wait — glFinish and the readbacks glGetNamedBufferSubData,
// glGetBufferSubData, glGetTextureImage, glGetTextureSubImage and glReadPixels, which block until
// the GPU has written what they read — first wait on a fence with finishWithin (fence.cpp), so a
// hung driver or a dispatch that never ends is an error naming the call after
// hostWaitSeconds(), never a frozen program; a driver reset is named at once. It replaces
// libepoxy's function pointers of those calls (as hazards.cpp does, after it, so both run), for
// the whole process. glFinish itself becomes the fence wait: the same guarantee, with a limit.
// Barrier checks requested only after the first context would replace these hooks (hazards.cpp
// installs once, at a context's creation); the tests request them before any context.
// Written by hand: no packaged library puts deadlines on GL waits.
#include "gl.h"

#include "core/core.h"

#include <cstdlib>
#include <mutex>
#include <string>

namespace gl {
namespace waits { // named: the unity build puts other files' anonymous namespaces beside this
namespace {

constexpr const char* kSecondsVar = "BSSRDF_WORKBENCH_GPU_WAIT_SECONDS";

FencePoll g_poll; // tests: replaces glClientWaitSync

PFNGLGETNAMEDBUFFERSUBDATAPROC g_glGetNamedBufferSubData = nullptr;
PFNGLGETBUFFERSUBDATAPROC g_glGetBufferSubData = nullptr;
PFNGLGETTEXTUREIMAGEPROC g_glGetTextureImage = nullptr;
PFNGLGETTEXTURESUBIMAGEPROC g_glGetTextureSubImage = nullptr;
PFNGLREADPIXELSPROC g_glReadPixels = nullptr;

void wait(const char* call) {
    finishWithin(call, hostWaitSeconds(), g_poll);
}

void hook_glGetNamedBufferSubData(GLuint b, GLintptr o, GLsizeiptr n, void* d) {
    wait("glGetNamedBufferSubData");
    g_glGetNamedBufferSubData(b, o, n, d);
}
void hook_glGetBufferSubData(GLenum t, GLintptr o, GLsizeiptr n, void* d) {
    wait("glGetBufferSubData");
    g_glGetBufferSubData(t, o, n, d);
}
void hook_glGetTextureImage(GLuint t, GLint l, GLenum f, GLenum ty, GLsizei n, void* d) {
    wait("glGetTextureImage");
    g_glGetTextureImage(t, l, f, ty, n, d);
}
void hook_glGetTextureSubImage(GLuint t, GLint l, GLint x, GLint y, GLint z, GLsizei w, GLsizei h,
                               GLsizei dp, GLenum f, GLenum ty, GLsizei n, void* d) {
    wait("glGetTextureSubImage");
    g_glGetTextureSubImage(t, l, x, y, z, w, h, dp, f, ty, n, d);
}
void hook_glReadPixels(GLint x, GLint y, GLsizei w, GLsizei h, GLenum f, GLenum t, void* d) {
    wait("glReadPixels");
    g_glReadPixels(x, y, w, h, f, t, d);
}
void hook_glFinish() {
    wait("glFinish");
}

// Puts `hook` in libepoxy's pointer, calling on to the barrier checks' hook where those are
// installed (hazards.cpp, which calls the driver), else to the driver's function from `resolve`
// — not to libepoxy's first pointer, a stub that overwrites the pointer with the driver's
// function when first called (which would take the hook out).
template <class Fn>
void chain(Fn& slot, Fn& previous, Fn hook, const char* name, ProcResolver resolve) {
    previous = barrierChecksActive() ? slot : reinterpret_cast<Fn>(resolve(name));
    if (previous) slot = hook;
}

} // namespace
} // namespace waits

double hostWaitSeconds() {
    static const double seconds = [] {
        const char* v = std::getenv(waits::kSecondsVar);
        if (!v || !*v) return 60.0;
        char* end = nullptr;
        const double s = std::strtod(v, &end);
        if (*end != '\0' || !(s > 0 && s <= 86400))
            throw core::Error(waits::kSecondsVar, 0,
                              std::string("expected seconds in (0, 86400], got '") + v + "'");
        return s;
    }();
    return seconds;
}

void installWaitDeadlines(ProcResolver resolve) {
    using namespace waits;
    static std::once_flag once;
    std::call_once(once, [resolve] {
#define BW_CHAIN(name) chain(epoxy_##name, g_##name, &hook_##name, #name, resolve)
        BW_CHAIN(glGetNamedBufferSubData);
        BW_CHAIN(glGetBufferSubData);
        BW_CHAIN(glGetTextureImage);
        BW_CHAIN(glGetTextureSubImage);
        BW_CHAIN(glReadPixels);
#undef BW_CHAIN
        epoxy_glFinish = &hook_glFinish; // the fence wait replaces it
    });
}

void setWaitPollForTesting(FencePoll poll) {
    waits::g_poll = std::move(poll);
}

} // namespace gl
