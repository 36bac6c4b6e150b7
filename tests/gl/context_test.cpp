// Headless GL context: OpenGL 4.5 core through EGL, compute shaders, FBO readback.
#include "../support/gl_debug_guard.h"
#include "core/core.h"
#include "gl/gl.h"

#include <epoxy/egl.h>
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <vector>

TEST(HeadlessContext, GivesGl45CoreWithCompute) {
    auto ctx = gl::createHeadlessContext();
    ASSERT_TRUE(ctx);
    EXPECT_TRUE(ctx->headless());
    EXPECT_GE(epoxy_gl_version(), 45);
    EXPECT_FALSE(ctx->renderer().empty());

    const char* src = R"(#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Out { float v[]; };
void main() { v[gl_GlobalInvocationID.x] = float(gl_GlobalInvocationID.x) * 0.5; })";
    gl::Program p = gl::buildProgram({{GL_COMPUTE_SHADER, src}});
    gl::Buffer buf = gl::createBuffer(256 * sizeof(float), nullptr);
    glUseProgram(p.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf.id());
    {
        gl::ScopedStageTimer t("test_compute");
        glDispatchCompute(4, 1, 1);
    }
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> out(256);
    glGetNamedBufferSubData(buf.id(), 0, 256 * sizeof(float), out.data());
    for (int i = 0; i < 256; ++i)
        EXPECT_EQ(out[i], i * 0.5f);
    gl::collectTimings(true);
    auto t = gl::timings();
    ASSERT_EQ(t.size(), 1u);
    // the query's result arrived: a time, or a driver that reports 0 ns (shown as n/a)
    EXPECT_TRUE(t[0].gpuMs >= 0.0 || t[0].gpuUnmeasurable);
}

// A program deleted while current is unbound first: restoring GL_CURRENT_PROGRAM afterwards (as
// ImGui's renderer does each frame) is then no GL_INVALID_VALUE.
TEST(HeadlessContext, DeletingTheCurrentProgramUnbindsIt) {
    auto ctx = gl::createHeadlessContext();
    const char* src = "#version 450\nlayout(local_size_x = 1) in;\nvoid main() {}\n";
    {
        gl::Program p = gl::buildProgram({{GL_COMPUTE_SHADER, src}});
        glUseProgram(p.id());
    }
    GLint current = -1;
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    EXPECT_EQ(current, 0);
    while (glGetError() != GL_NO_ERROR) {
    }
    glUseProgram(GLuint(current)); // what a save-and-restore does
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST(HeadlessContext, CompileErrorsCarryTheDriverLog) {
    auto ctx = gl::createHeadlessContext();
    try {
        gl::buildProgram({{GL_COMPUTE_SHADER, "#version 450\nlayout(local_size_x=1) in;\n"
                                              "void main() { undefined_thing = 1; }\n"}});
        FAIL() << "expected a compile error";
    } catch (const gl::ProgramError& e) {
        EXPECT_EQ(e.stage(), static_cast<GLenum>(GL_COMPUTE_SHADER));
        EXPECT_NE(e.log().find("undefined_thing"), std::string::npos) << e.log();
    }
}

TEST(HeadlessContext, RenderTargetClearAndReadback) {
    auto ctx = gl::createHeadlessContext();
    gl::RenderTarget rt;
    rt.resize(8, 4);
    rt.bind();
    glClearColor(1.0f, 0.5f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    auto px = gl::readPixelsRGBA8(rt.framebuffer(), 0, 0, 8, 4);
    ASSERT_EQ(px.size(), 8u * 4u * 4u);
    EXPECT_EQ(px[0], 255);
    EXPECT_NEAR(px[1], 128, 1);
    EXPECT_EQ(px[2], 0);
    EXPECT_EQ(px[3], 255);
}

// An offscreen pass (shadow maps, G-buffers) sets what an opaque depth-tested draw needs and
// leaves the state as it found it, also when the pass throws.
TEST(HeadlessContext, AnOffscreenDrawRestoresTheStateItChanges) {
    auto ctx = gl::createHeadlessContext();
    gl::RenderTarget before, target;
    before.resize(64, 64);
    target.resize(16, 8);
    before.bind();
    glViewport(3, 4, 50, 60);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_FALSE);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glEnable(GL_SCISSOR_TEST);
    struct State {
        GLint framebuffer = 0, viewport[4] = {}, depthFunc = 0;
        GLboolean depthMask = 0, depthTest = 0, cull = 0, blend = 0, scissor = 0;
    };
    const auto now = [] {
        State s;
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s.framebuffer);
        glGetIntegerv(GL_VIEWPORT, s.viewport);
        glGetIntegerv(GL_DEPTH_FUNC, &s.depthFunc);
        glGetBooleanv(GL_DEPTH_WRITEMASK, &s.depthMask);
        s.depthTest = glIsEnabled(GL_DEPTH_TEST);
        s.cull = glIsEnabled(GL_CULL_FACE);
        s.blend = glIsEnabled(GL_BLEND);
        s.scissor = glIsEnabled(GL_SCISSOR_TEST);
        return s;
    };
    const auto expectState = [](const State& s, const State& want) {
        EXPECT_EQ(s.framebuffer, want.framebuffer);
        EXPECT_EQ(std::vector<GLint>(s.viewport, s.viewport + 4),
                  std::vector<GLint>(want.viewport, want.viewport + 4));
        EXPECT_EQ(s.depthFunc, want.depthFunc);
        EXPECT_EQ(s.depthMask, want.depthMask);
        EXPECT_EQ(s.depthTest, want.depthTest);
        EXPECT_EQ(s.cull, want.cull);
        EXPECT_EQ(s.blend, want.blend);
        EXPECT_EQ(s.scissor, want.scissor);
    };
    const State asBefore{GLint(before.framebuffer()),
                         {3, 4, 50, 60},
                         GL_GREATER,
                         GL_FALSE,
                         GL_FALSE,
                         GL_TRUE,
                         GL_TRUE,
                         GL_TRUE};
    const State inPass{GLint(target.framebuffer()),
                       {0, 0, 16, 8},
                       GL_LESS,
                       GL_TRUE,
                       GL_TRUE,
                       GL_FALSE,
                       GL_FALSE,
                       GL_FALSE};
    {
        const gl::ScopedDrawTarget draw(target.framebuffer(), 16, 8);
        expectState(now(), inPass);
    }
    expectState(now(), asBefore);
    try {
        const gl::ScopedDrawTarget draw(target.framebuffer(), 16, 8);
        throw core::Error("pass", 0, "failed in the middle");
    } catch (const core::Error&) {
    }
    expectState(now(), asBefore);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
}

TEST(HeadlessContext, NestedStageTimersDoNotNestGlQueries) {
    auto ctx = gl::createHeadlessContext();
    {
        gl::ScopedStageTimer outer("outer");
        gl::ScopedStageTimer inner("inner"); // CPU time only: queries cannot nest
    }
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    gl::collectTimings(true);
    EXPECT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));
    bool outerHasGpu = false, innerSeen = false;
    for (const auto& t : gl::timings()) {
        if (t.stage == "outer") outerHasGpu = t.gpuMs >= 0 || t.gpuUnmeasurable;
        if (t.stage == "inner") innerSeen = t.runs == 1 && t.gpuMs < 0 && !t.gpuUnmeasurable;
    }
    EXPECT_TRUE(outerHasGpu);
    EXPECT_TRUE(innerSeen);
}

// The environment variables with which Mesa and NVIDIA's driver turn their on-disk shader cache
// off, read as those drivers read them (the model check then leaves no code for the workbench).
TEST(DriverShaderCache, OffOnlyWhereTheEnvironmentTurnsItOff) {
    const char* const vars[] = {"MESA_SHADER_CACHE_DISABLE", "MESA_GLSL_CACHE_DISABLE",
                                "__GL_SHADER_DISK_CACHE"};
    std::vector<std::pair<std::string, std::optional<std::string>>> saved;
    for (const char* v : vars) {
        const char* was = std::getenv(v);
        saved.emplace_back(v, was ? std::optional<std::string>(was) : std::nullopt);
        unsetenv(v);
    }
    EXPECT_FALSE(gl::driverShaderCacheOff());
    for (const char* value : {"true", "1", "YES", "y"}) {
        setenv("MESA_SHADER_CACHE_DISABLE", value, 1);
        EXPECT_TRUE(gl::driverShaderCacheOff()) << value;
    }
    for (const char* value : {"false", "0", "no", ""}) {
        setenv("MESA_SHADER_CACHE_DISABLE", value, 1);
        EXPECT_FALSE(gl::driverShaderCacheOff()) << value;
    }
    unsetenv("MESA_SHADER_CACHE_DISABLE");
    setenv("MESA_GLSL_CACHE_DISABLE", "true", 1);
    EXPECT_TRUE(gl::driverShaderCacheOff());
    unsetenv("MESA_GLSL_CACHE_DISABLE");
    setenv("__GL_SHADER_DISK_CACHE", "0", 1);
    EXPECT_TRUE(gl::driverShaderCacheOff());
    setenv("__GL_SHADER_DISK_CACHE", "1", 1);
    EXPECT_FALSE(gl::driverShaderCacheOff());
    for (const auto& [name, value] : saved)
        if (value)
            setenv(name.c_str(), value->c_str(), 1);
        else
            unsetenv(name.c_str());
}

// The window opens fitting the monitor's work area (it opened at 1600 × 1000 whatever the screen,
// so at 1280 × 720 the inspector and the bottom strip were off-screen), keeping its aspect.
TEST(WindowSize, FitsTheWorkAreaWithItsDecorations) {
    const auto fit = [](int w, int h, int aw, int ah, int fw = 0, int fh = 0) {
        const gl::WindowSize s = gl::fitWindowSize(w, h, aw, ah, fw, fh);
        return std::make_pair(s.width, s.height);
    };
    EXPECT_EQ(fit(1600, 1000, 1920, 1050), std::make_pair(1600, 1000));      // fits as asked
    EXPECT_EQ(fit(1600, 1000, 1280, 720), std::make_pair(1152, 720));        // height decides
    EXPECT_EQ(fit(1600, 1000, 1280, 720, 0, 30), std::make_pair(1104, 690)); // title bar
    EXPECT_EQ(fit(1600, 1000, 800, 600), std::make_pair(800, 500));          // width decides
    EXPECT_EQ(fit(1600, 1000, 1366, 768, 2, 32), std::make_pair(1178, 736));
    EXPECT_EQ(fit(1600, 1000, 600, 380), std::make_pair(600, 380)); // smaller than the floor
}

// The tests' guard (tests/support/gl_debug_guard.cpp): a GL error the test did not expect fails
// it, naming the message; one it expects is counted instead.
TEST(HeadlessContext, AnUnexpectedGlErrorFailsTheTest) {
    static auto ctx = gl::createHeadlessContext();
    ctx->makeCurrent();
    // never generated: GL_INVALID_OPERATION, one message on Mesa and on NVIDIA
    EXPECT_NONFATAL_FAILURE(glBindTexture(GL_TEXTURE_2D, 987654u),
                            "GL debug message of type ERROR");
    bwtest::expectGlProblem([] { glBindTexture(GL_TEXTURE_2D, 987655u); }, "GL_INVALID_OPERATION");
    bwtest::ExpectedGlErrors expected;
    glBindTexture(GL_TEXTURE_2D, 987656u);
    EXPECT_EQ(expected.count(), 1);
    glBindTexture(GL_TEXTURE_2D, 0);
}

// The limits a driver must meet (gl/limits.cpp): this driver meets them all, and one that falls
// short gets one message naming each limit, its value, what is needed and what needs it.
TEST(HeadlessContext, DriverLimitsAreCheckedAndShortfallsNamed) {
    auto ctx = gl::createHeadlessContext(); // requireLimits() passed in the constructor
    EXPECT_NO_THROW(gl::requireLimits());
    ASSERT_FALSE(gl::requiredLimits().empty());
    for (const gl::RequiredLimit& l : gl::requiredLimits()) {
        GLint64 v = 0;
        if (l.index >= 0)
            glGetInteger64i_v(l.pname, GLuint(l.index), &v);
        else
            glGetInteger64v(l.pname, &v);
        EXPECT_GE(v, l.needed) << l.name;
    }
    // a driver with half the shared memory needed and a 2048-pixel texture limit
    const std::string problem = gl::limitsProblem([](const gl::RequiredLimit& l) -> int64_t {
        if (l.pname == GL_MAX_COMPUTE_SHARED_MEMORY_SIZE) return 4096;
        if (l.pname == GL_MAX_TEXTURE_SIZE) return 2048;
        return l.needed;
    });
    EXPECT_NE(problem.find("GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is 4096, needs 8192 (the slab "
                           "tracer's workgroup-shared tallies"),
              std::string::npos)
        << problem;
    EXPECT_NE(problem.find("GL_MAX_TEXTURE_SIZE is 2048, needs 4096"), std::string::npos)
        << problem;
    EXPECT_EQ(problem.find("GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS"), std::string::npos);
    EXPECT_EQ(gl::limitsProblem([](const gl::RequiredLimit& l) { return l.needed; }), "");
}

// Waiting for the GPU has a deadline (gl/fence.cpp): finished work returns at once; work that
// does not finish in time (a fence that never signals, as a hung driver's would) is an error
// naming the work after the deadline, not a wait without end; a failed wait is an error too.
TEST(HeadlessContext, WaitingForTheGpuHasADeadline) {
    auto ctx = gl::createHeadlessContext();
    gl::Buffer buf = gl::createBuffer(1024, nullptr);
    glClearNamedBufferData(buf.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    EXPECT_NO_THROW(gl::finishWithin("clear", 10.0));
    int polls = 0;
    const auto never = [&](GLsync, GLbitfield, GLuint64) {
        ++polls;
        std::this_thread::sleep_for(std::chrono::milliseconds(5)); // the wait a poll would take
        return GLenum(GL_TIMEOUT_EXPIRED);
    };
    try {
        gl::finishWithin("the tracer", 0.2, never);
        ADD_FAILURE() << "no error after the deadline";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("the tracer: the GPU did not finish within 0.2 s"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_GE(polls, 1);
    const auto failed = [](GLsync, GLbitfield, GLuint64) { return GLenum(GL_WAIT_FAILED); };
    EXPECT_THROW(gl::finishWithin("the tracer", 10.0, failed), core::Error);
}

// A driver reset (gl/reset.cpp) is named, not waited out: a context lost after a GPU hang never
// signals its fences, so a wait that sees the reset stops at once with the reason. Simulated
// ($BSSRDF_WORKBENCH_SIMULATE_GL_RESET: the first query on reports this program's reset), since
// no driver here resets; the contexts ask for reset notification where EGL offers it (EGL 1.5).
TEST(HeadlessContext, ADriverResetIsNamedByTheWaitThatSeesIt) {
    ASSERT_EQ(setenv("BSSRDF_WORKBENCH_SIMULATE_GL_RESET", "1", 1), 0);
    auto ctx = gl::createHeadlessContext();
    if (epoxy_egl_version(eglGetCurrentDisplay()) >= 15) {
        EXPECT_TRUE(gl::resetNotificationRequested());
    }
    EXPECT_EQ(gl::graphicsResetStatus(), gl::ResetStatus::Guilty);
    int polls = 0;
    const auto never = [&](GLsync, GLbitfield, GLuint64) {
        ++polls;
        return GLenum(GL_TIMEOUT_EXPIRED);
    };
    try {
        gl::finishWithin("the tracer", 30.0, never);
        ADD_FAILURE() << "no error after a reset";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("the tracer: the GPU driver reset the OpenGL "
                                             "context, after GPU work of this program hung"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(polls, 1); // not polled on until the 30 s deadline
    unsetenv("BSSRDF_WORKBENCH_SIMULATE_GL_RESET");
}

// No GL object survives a reset: once graphicsResetStatus() has seen one, the objects' deleters
// call nothing (gl::contextLost()). After resets on an NVIDIA H200 the processes aborted in that
// teardown, in libepoxy ("Couldn't find current GLX or EGL context"), instead of ending with
// the reset's message.
TEST(HeadlessContext, AfterAResetTheObjectsAreNotDeleted) {
    ASSERT_EQ(setenv("BSSRDF_WORKBENCH_SIMULATE_GL_RESET", "1", 1), 0);
    auto ctx = gl::createHeadlessContext();
    GLuint before = 0, after = 0;
    {
        gl::Buffer b = gl::createBuffer(16, nullptr);
        before = b.id();
    }
    EXPECT_FALSE(glIsBuffer(before)) << "deleted while the context is good";
    EXPECT_FALSE(gl::contextLost());
    {
        gl::Buffer b = gl::createBuffer(16, nullptr);
        after = b.id();
        EXPECT_EQ(gl::graphicsResetStatus(), gl::ResetStatus::Guilty);
        EXPECT_TRUE(gl::contextLost());
    }
    EXPECT_TRUE(glIsBuffer(after)) << "a deleter called GL after the reset";
    unsetenv("BSSRDF_WORKBENCH_SIMULATE_GL_RESET");
}

// Every host wait has a deadline (gl/waits.cpp): glFinish and the readbacks wait on a fence
// first, so a GPU that never finishes (a fence that never signals, as a hung driver's would) is
// an error naming the call after $BSSRDF_WORKBENCH_GPU_WAIT_SECONDS, not a frozen program. With
// the fences signalling, the same calls read what they read before.
TEST(HeadlessContext, EveryReadbackAndFinishWaitsWithADeadline) {
    ASSERT_EQ(setenv("BSSRDF_WORKBENCH_GPU_WAIT_SECONDS", "0.2", 1), 0);
    auto ctx = gl::createHeadlessContext();
    EXPECT_EQ(gl::hostWaitSeconds(), 0.2);
    const uint32_t seven = 7;
    gl::Buffer buf = gl::createBuffer(sizeof seven, &seven);
    // each poll takes at least 5 ms, so a wait that keeps its 0.2 s deadline polls at most 41
    // times (fewer on a loaded machine): counted, not timed
    int polls = 0;
    gl::setWaitPollForTesting([&polls](GLsync, GLbitfield, GLuint64) {
        ++polls;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        return GLenum(GL_TIMEOUT_EXPIRED);
    });
    uint32_t read = 0;
    unsigned char pixel[4];
    const std::vector<std::pair<const char*, std::function<void()>>> waits = {
        {"glGetNamedBufferSubData",
         [&] { glGetNamedBufferSubData(buf.id(), 0, sizeof read, &read); }},
        {"glReadPixels", [&] { glReadPixels(0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel); }},
        {"glFinish", [] { glFinish(); }}};
    for (const auto& [call, run] : waits) {
        polls = 0;
        try {
            run();
            ADD_FAILURE() << call << ": no error after the deadline";
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(std::string(call) +
                                                 ": the GPU did not finish within 0.2 s"),
                      std::string::npos)
                << e.what();
        }
        EXPECT_GE(polls, 1) << call;
        EXPECT_LE(polls, 41) << call;
    }
    EXPECT_EQ(read, 0u); // the read did not happen
    gl::setWaitPollForTesting({});
    glGetNamedBufferSubData(buf.id(), 0, sizeof read, &read);
    EXPECT_EQ(read, 7u);
    glFinish();
    unsetenv("BSSRDF_WORKBENCH_GPU_WAIT_SECONDS");
}
