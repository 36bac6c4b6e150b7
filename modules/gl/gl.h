// gl: the OpenGL layer. One Context interface with two implementations — a GLFW window
// (OpenGL 4.5 core) and an EGL headless context (Mesa surfaceless or device platform, no X
// server) — plus RAII GL objects, program compilation with logs, stage timing (GL timer
// queries + CPU clocks) and framebuffer readback. Every stage renders into FBOs, so the
// window only presents them and headless runs produce the same pixels.
#pragma once

#include <epoxy/gl.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

struct GLFWwindow;

namespace gl {

// ---- context ----------------------------------------------------------------------------------
class Context {
  public:
    virtual ~Context() = default;
    virtual void makeCurrent() = 0;
    virtual GLFWwindow* window() const { return nullptr; } // null when headless
    bool headless() const { return window() == nullptr; }
    std::string renderer() const;
    std::string version() const;
};

// EGL headless context (surfaceless, then device platform, then default display).
// Throws core::Error with the reason when no OpenGL 4.5 core context can be created.
std::unique_ptr<Context> createHeadlessContext(bool debug = true);
// GLFW window with an OpenGL 4.5 core context, width x height UI units of `uiScale` screen
// pixels each (0: the window's content scale, which the desktop sets: 2 on a screen at 200 %),
// shrunk to fit the primary monitor's work area (fitWindowSize). Throws core::Error when it
// cannot open one.
std::unique_ptr<Context> createWindowContext(int width, int height, const std::string& title,
                                             bool debug = true, float uiScale = 0);
// The window's content scale (GLFW: the desktop's scaling of that monitor; X11: Xft.dpi / 96).
float contentScale(GLFWwindow* window);
// True when a display server is reachable (DISPLAY / WAYLAND_DISPLAY set and GLFW starts).
bool displayAvailable();

// The size a window opens at: `want` shrunk, keeping its aspect, until it and its decorations
// (`frameW` × `frameH` in all) fit the monitor's work area (`areaW` × `areaH`: the screen less
// panels and docks); never below 640 × 400 unless the work area itself is smaller. The window
// context opens at this size on the primary monitor.
struct WindowSize {
    int width = 0, height = 0;
};
WindowSize fitWindowSize(int wantW, int wantH, int areaW, int areaH, int frameW = 0,
                         int frameH = 0);

// What the workbench needs of a driver beyond "OpenGL 4.5 core" (limits.cpp): each limit, the
// least value it needs and what needs it. Both contexts call requireLimits() when created, which
// throws core::Error("<renderer>: the OpenGL driver falls short …: NAME is V, needs N (use); …").
struct RequiredLimit {
    const char* name;
    GLenum pname;
    int index; // indexed query (glGetInteger64i_v) when >= 0
    int64_t needed;
    const char* use;
};
const std::vector<RequiredLimit>& requiredLimits();
// "" when every limit is met by `query`, else the message naming every shortfall.
std::string limitsProblem(const std::function<int64_t(const RequiredLimit&)>& query);
void requireLimits(); // with the current context; throws core::Error
// The driver's GL_MAX_SHADER_STORAGE_BLOCK_SIZE: the most bytes one storage block binding may
// hold (at least 2^27, requiredLimits()). requireStorageBlock throws core::Error(what, 0, …)
// naming the bytes `what` needs in one block and that limit when they exceed it, before a
// buffer that a dispatch could not address is made (the barrier checks report a binding over it).
int64_t maxStorageBlockBytes();
void requireStorageBlock(uint64_t bytes, const std::string& what, const std::string& unit,
                         uint64_t bytesPerUnit);

// Whether the environment turns the driver's on-disk shader cache off (shader_cache.cpp: Mesa's
// MESA_SHADER_CACHE_DISABLE, NVIDIA's __GL_SHADER_DISK_CACHE=0). With the cache on, code a
// driver generated for a program in another process (the model check's) is reused at this
// process's first dispatch of the same program text.
bool driverShaderCacheOff();

// Waits until the GPU has finished every command issued so far: a fence polled every 50 ms,
// and core::Error("<what>: the GPU did not finish within S s …") once `seconds` have passed,
// instead of a readback that blocks without end (fence.cpp). `poll` replaces glClientWaitSync
// (tests of the deadline on drivers that finish everything at once).
using FencePoll = std::function<GLenum(GLsync, GLbitfield, GLuint64)>;
void finishWithin(const std::string& what, double seconds, const FencePoll& poll = {});

// The driver's graphics-reset status (reset.cpp): None while the context is usable; after a
// GPU hang or driver reset the context is lost (where reset notification was granted:
// resetNotificationRequested()) and every GL call does nothing. finishWithin() throws naming it;
// the GUI restarts on a new context with its state. $BSSRDF_WORKBENCH_SIMULATE_GL_RESET=N
// reports a reset (Guilty) from the N-th query on (tests).
enum class ResetStatus { None, Guilty, Innocent, Unknown };
ResetStatus graphicsResetStatus();
// "the GPU driver reset the OpenGL context, after GPU work of this program hung or faulted" …
std::string describe(ResetStatus s);
// Whether graphicsResetStatus() has seen a reset in this process. No GL object survives one, so
// the objects' deleters (objects.cpp, the irradiance samplers, the waiting fence) then call
// nothing: after resets on an NVIDIA H200 the processes aborted in their teardown, in libepoxy
// ("Couldn't find current GLX or EGL context"), instead of ending with the reset's message.
bool contextLost();
// Whether the current context was created with reset notification (lose context on reset).
bool resetNotificationRequested();
// Clears $BSSRDF_WORKBENCH_SIMULATE_GL_RESET for processes started from here on (a restart after
// a simulated reset must not simulate another).
void stopSimulatedResetsInChildren();

// Routes KHR_debug messages to the core log (called by both context constructors).
void installDebugOutput();
// Also hands every debug message to `observer` (the tests fail on errors and undefined
// behaviour: tests/support/gl_debug_guard.cpp); nullptr removes it.
using DebugObserver = void (*)(GLenum source, GLenum type, GLenum severity, const char* message);
void setDebugObserver(DebugObserver observer);

// Barrier checks (hazards.cpp): every dispatch, draw, buffer or texture read is checked against
// the memory barriers OpenGL 4.5 §7.13.2 requires after a shader wrote what it reads; a missing
// one is a debug message of type UNDEFINED_BEHAVIOR ("barrier missing: glGetNamedBufferSubData
// reads buffer 7, which the glDispatchCompute of shaders/x.comp wrote, with no
// glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT) in between"). Off unless requested (every test
// does) or $BSSRDF_WORKBENCH_GL_BARRIERS is set; the contexts install them when created.
void requestBarrierChecks();
// By the context constructors, with the context current; `resolve` gives the driver's functions.
using ProcResolver = void (*(*)(const char*))();
void installBarrierChecks(ProcResolver resolve);
// Every host wait has a deadline (waits.cpp): glFinish and the readbacks (glGetNamedBufferSubData,
// glGetBufferSubData, glGetTextureImage, glGetTextureSubImage, glReadPixels) first wait with
// finishWithin(call name, hostWaitSeconds()), so a GPU that never finishes is a core::Error
// naming the call instead of a frozen program. Installed by both contexts, once per process,
// after the barrier checks. hostWaitSeconds(): 60, or $BSSRDF_WORKBENCH_GPU_WAIT_SECONDS (a
// bad value is a core::Error naming the variable). setWaitPollForTesting replaces the fence
// poll of these waits (tests of the deadline on drivers that finish everything at once).
void installWaitDeadlines(ProcResolver resolve);
double hostWaitSeconds();
void setWaitPollForTesting(FencePoll poll);
bool barrierChecksActive();
// For reads the checks cannot see (ImGui's backend has its own GL loader): `reader` is about to
// sample `texture`, which needs GL_TEXTURE_FETCH_BARRIER_BIT after an image store to it.
void checkTextureFetch(GLuint texture, const char* reader);
void forgetBarrierState(); // of the current context (a new context may reuse an old one's key)

// GL debug messages of medium or high severity (and every GL_DEBUG_TYPE_ERROR), grouped by
// their text with numbers masked: the first message of each group, how often it came and when
// it last came (core::secondsSinceStart). The workbench lists them under Errors while they keep
// coming (expireDebugProblems); clearDebugProblems() forgets them all.
struct DebugProblem {
    std::string first;
    long long count = 0;
    double lastSeconds = 0;
};
std::vector<DebugProblem> debugProblems();
void clearDebugProblems();
// Forgets the groups whose message has not come for `seconds`: a message is an event, and once
// the call that raised it stops (the program was fixed), its entry leaves.
void expireDebugProblems(double seconds);

// ---- RAII objects -------------------------------------------------------------------------------
template <void (*Deleter)(GLuint)> class Handle {
  public:
    Handle() = default;
    explicit Handle(GLuint id) : m_id(id) {}
    ~Handle() { reset(); }
    Handle(Handle&& o) noexcept : m_id(std::exchange(o.m_id, 0)) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            m_id = std::exchange(o.m_id, 0);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    GLuint id() const { return m_id; }
    explicit operator bool() const { return m_id != 0; }
    void reset() {
        if (m_id) Deleter(m_id);
        m_id = 0;
    }

  private:
    GLuint m_id = 0;
};
void deleteBuffer(GLuint id);
void deleteTexture(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteProgram(GLuint id);
void deleteVertexArray(GLuint id);
using Buffer = Handle<deleteBuffer>;
using Texture = Handle<deleteTexture>;
using FramebufferId = Handle<deleteFramebuffer>;
using Program = Handle<deleteProgram>;
using VertexArray = Handle<deleteVertexArray>;

Buffer createBuffer(size_t bytes, const void* data, GLbitfield flags = GL_DYNAMIC_STORAGE_BIT);
// A 2D texture of one level with immutable storage, `filter` for minification and
// magnification, edges clamped.
Texture createTexture2D(GLenum internalFormat, int width, int height, GLenum filter = GL_NEAREST);

// RGBA colour target (RGBA8 or RGBA32F) with an FBO around it.
class RenderTarget {
  public:
    void resize(int width, int height, GLenum internalFormat = GL_RGBA8);
    void bind() const;
    int width() const { return m_width; }
    int height() const { return m_height; }
    GLuint texture() const { return m_color.id(); }
    GLuint framebuffer() const { return m_fbo.id(); }

  private:
    Texture m_color;
    FramebufferId m_fbo;
    int m_width = 0, m_height = 0;
    GLenum m_format = 0;
};

// Creates (or re-creates on a size change) an RGBA8 texture and uploads `rgba` (top row
// first, as images are stored here; the caller flips UVs when drawing).
void uploadRGBA8(Texture& texture, int width, int height, const unsigned char* rgba);

// ---- programs -----------------------------------------------------------------------------------
struct ShaderStage {
    GLenum type; // GL_COMPUTE_SHADER, GL_VERTEX_SHADER, ...
    std::string source;
};
// Compile or link failure; `log` is the raw driver log, `stage` the failing stage (0: link).
class ProgramError : public std::runtime_error {
  public:
    ProgramError(GLenum stage, std::string log)
        : std::runtime_error(log), m_stage(stage), m_log(std::move(log)) {}
    GLenum stage() const { return m_stage; }
    const std::string& log() const { return m_log; }

  private:
    GLenum m_stage;
    std::string m_log;
};
Program buildProgram(const std::vector<ShaderStage>& stages); // throws ProgramError
GLint uniformLocation(const Program& p, const char* name);    // -1 when unused/absent

// ---- timing -------------------------------------------------------------------------------------
// Per-stage timings: CPU wall clock and GPU time (GL_TIME_ELAPSED). GPU results are collected
// without stalling on a later call to collectTimings().
struct StageTiming {
    std::string stage;
    double cpuMs = 0;
    double gpuMs = -1; // -1: no GPU time (nested in another timer, or not arrived yet)
    long long runs = 0;
    bool gpuUnmeasurable = false; // the driver's timer reported 0 ns (llvmpipe defers work)
};
class ScopedStageTimer {
  public:
    explicit ScopedStageTimer(std::string stage);
    ~ScopedStageTimer();
    ScopedStageTimer(const ScopedStageTimer&) = delete;
    ScopedStageTimer& operator=(const ScopedStageTimer&) = delete;

  private:
    std::string m_stage;
    GLuint m_query = 0;
    double m_startMs;
};
void collectTimings(bool wait = false);
std::vector<StageTiming> timings();
// A named measurement that is not a GL stage (e.g. save-to-pixels latency).
void recordTiming(const std::string& stage, double cpuMs);

// ---- offscreen draws
// ----------------------------------------------------------------------------- The state of an
// opaque, depth-tested draw into an offscreen target (shadow maps, G-buffers): binds `framebuffer`
// for drawing with a width × height viewport, depth test GL_LESS with depth writes, no face
// culling, blending or scissor test; on leaving (also by an exception) restores the draw
// framebuffer, the viewport and each of those settings as they were (the GUI's own passes rely on
// theirs).
class ScopedDrawTarget {
  public:
    ScopedDrawTarget(GLuint framebuffer, int width, int height);
    ~ScopedDrawTarget();
    ScopedDrawTarget(const ScopedDrawTarget&) = delete;
    ScopedDrawTarget& operator=(const ScopedDrawTarget&) = delete;

  private:
    GLint m_framebuffer = 0, m_viewport[4] = {}, m_depthFunc = GL_LESS;
    GLboolean m_depthMask = GL_TRUE, m_depthTest = GL_FALSE, m_cull = GL_FALSE, m_blend = GL_FALSE,
              m_scissor = GL_FALSE;
};

// ---- readback -----------------------------------------------------------------------------------
// Reads an RGBA8 rectangle of the bound read framebuffer, rows top-to-bottom.
std::vector<unsigned char> readPixelsRGBA8(GLuint fbo, int x, int y, int width, int height);
// RGBA8 pixels (top row first) encoded as PNG bytes; empty when they cannot be encoded.
std::string encodePng(int width, int height, const std::vector<unsigned char>& rgba);
// Writes RGBA8 pixels (top row first) as PNG; throws core::Error naming the path.
void writePng(const std::filesystem::path& path, int width, int height,
              const std::vector<unsigned char>& rgba);

} // namespace gl
