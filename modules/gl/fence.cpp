// gl fence: waits for the GPU with a deadline (gl.h, finishWithin). A readback such as
// glGetNamedBufferSubData blocks until the GPU is done, however long that takes; a hung driver
// or a shader that never ends then freezes the program without a word. Waiting on a fence
// (glFenceSync / glClientWaitSync) in short polls instead lets the caller give up after a
// deadline with a message naming the work, and notice a driver reset (reset.cpp) while it waits.
#include "gl.h"

#include "core/core.h"
#include "core/text.h"

namespace gl {

void finishWithin(const std::string& what, double seconds, const FencePoll& poll) {
    GLsync fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    if (!fence) throw core::Error(what + ": glFenceSync failed (lost context?)");
    core::Stopwatch clock;
    GLbitfield flags = GL_SYNC_FLUSH_COMMANDS_BIT; // the first poll flushes the commands
    for (;;) {
        constexpr GLuint64 kPollNs = 50'000'000; // 50 ms
        const GLenum r =
            poll ? poll(fence, flags, kPollNs) : glClientWaitSync(fence, flags, kPollNs);
        flags = 0;
        if (r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED) break;
        // still waiting: a reset is named at once rather than waited out
        if (r == GL_TIMEOUT_EXPIRED)
            if (const ResetStatus reset = graphicsResetStatus(); reset != ResetStatus::None)
                throw core::Error(what + ": " + describe(reset)); // the fence went with it
        if (r != GL_TIMEOUT_EXPIRED) {
            glDeleteSync(fence);
            throw core::Error(what + ": waiting for the GPU failed (lost context?)");
        }
        if (clock.ms() >= seconds * 1e3) {
            glDeleteSync(fence);
            throw core::Error(what + ": the GPU did not finish within " +
                              core::formatNumber(seconds, 3) +
                              " s (a hung driver, or GPU work far slower than this device "
                              "should take)");
        }
    }
    glDeleteSync(fence);
}

} // namespace gl
