// pathtrace GPU half: the slab tracer of pathtrace.h (thesis 3.2, Algorithm 1 with the
// termination of pathtrace.h) as an OpenGL 4.5 compute shader, shaders/pathtrace_slab.comp.
//   Same physics, conventions, estimators (Implicit / Analog) and tally as the CPU tracer,
//   traced in float with a Philox4x32-10 stream per path index
//   (shaders/common/pathtrace_rng.glsl): statistically, not bitwise, equal to the CPU result.
//   No radial splitting (SlabSettings::splitting is the CPU walk's; same expectation).
//   Work: step() cuts its paths into rounds of ≤ kMaxPathsPerRound new paths; each dispatch
//   of a round gives every invocation an event budget (paths one after another, one event per
//   loop iteration); a path still running when the budget is spent is saved whole and resumed
//   by the next dispatch, until the round has no path left. So dispatches stay short, and
//   Mesa llvmpipe's limit of 65535 loop iterations per invocation cannot drop long paths.
//   Tallies (shaders/common/pathtrace_tally.glsl): per slot Σw and Σw² as exact 64-bit
//   fixed-point sums (unit 2^-32) made of 32-bit integer atomics with carries; values
//   rounded to 2^-32 stochastically (unbiased); values above 16 (possible only when
//   rouletteWeight / rouletteSurvival > 16) go through a side list of floats. The dispatches of
//   a round hand over on the GPU (common/pathtrace_queue.glsl): the host issues them by
//   glDispatchComputeIndirect in batches and reads the queue once per batch; it reads the
//   integers once per round (≤ 2^16 paths, one value per slot each: no 64-bit sum can wrap),
//   adds them exactly into 128-bit integers and converts to the double SlabTally. On one
//   device and driver the tally is a function of (medium, settings, seed, paths done), bitwise: not
//   of step sizes, budgets, dispatches or scheduling.
//   Needs the same current OpenGL 4.5 context on the calling thread for every call.
#pragma once

#include "gl/gl.h"
#include "pathtrace/detail/gpu_work_queue.h"
#include "pathtrace/pathtrace.h"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace pathtrace {

class GpuSlabTracer {
  public:
    // New paths per round; a round dispatches until all of them have ended.
    static constexpr uint64_t kMaxPathsPerRound = uint64_t(1) << 16;
    static constexpr uint32_t kDefaultEventBudget = 4096;
    static constexpr uint32_t kMaxEventBudget = 32768; // llvmpipe ends loops at 65535

    // Compiles `shaderFile` (e.g. <root>/shaders/pathtrace_slab.comp; its #includes are
    // relative to its folder) and resets to Medium{} and SlabSettings{}. Throws core::Error
    // like reload().
    explicit GpuSlabTracer(std::filesystem::path shaderFile);
    ~GpuSlabTracer();
    GpuSlabTracer(const GpuSlabTracer&) = delete;
    GpuSlabTracer& operator=(const GpuSlabTracer&) = delete;

    // Validates (core::Error naming the field) and starts over at path 0 with an empty tally.
    // SlabSettings::threads is ignored.
    void reset(const Medium& m, const SlabSettings& s);
    // Traces up to `maxPaths` more paths, never beyond settings().paths, and returns
    // pathsDone(). Blocks until they are tallied.
    // Throws core::Error only for an impossible tally (a non-finite or negative weight from
    // an edited shader, or a weight beyond 2^45); the tally then starts over.
    uint64_t step(uint64_t maxPaths);
    const SlabTally& tally() const { return m_tally; }
    uint64_t pathsDone() const { return m_tally.paths; }
    bool finished() const { return m_tally.paths >= m_settings.paths; }
    double seconds() const { return m_seconds; } // wall time spent in step() since reset

    // Events one invocation traces per dispatch before it suspends its path to the next
    // dispatch (clamped to [1, kMaxEventBudget]). Smaller keeps dispatches short on slow
    // devices; the result does not depend on it.
    void setEventBudget(uint32_t events);
    uint32_t eventBudget() const { return m_eventBudget; }
    // Workgroup-shared tallies (common/pathtrace_tally.glsl; compiled in only when on). They
    // apply when bins + 6 ≤ 512, else every exit adds to the global tally. The result is
    // bitwise the same (integer sums). On by default where the first tracer of the process
    // measured MCML's case faster with them (a GPU with parallel workgroups, whose global
    // atomics on the hot bins contend); off where not (Mesa llvmpipe runs a workgroup's
    // invocations as coroutines around every barrier() and traces a third slower with them).
    // A change rebuilds the program (throws like reload()) and starts the tally over: call it
    // before reset().
    void setSharedTallies(bool on);
    bool sharedTallies() const; // whether the next dispatch sums in shared memory
    bool sharedTalliesCompiled() const { return m_sharedTallies; } // the switch itself
    // Path values tallied through the heavy-weight list (above 16) since reset (diagnostics).
    uint64_t heavyTallies() const { return m_work.heavyTallies(); }
    // Dispatches and host reads since construction (the dispatches hand over on the GPU).
    const detail::GpuWorkQueue& workQueue() const { return m_work; }

    // Recompiles the shader from disk. On failure throws core::Error
    // ("shaders/pathtrace_slab.comp:LINE: message", or the shaders/common/… file that has the
    // error) and keeps the previous program and tally. On success the tally starts over (the
    // paths so far were traced by the old code).
    void reload();

    const std::filesystem::path& shaderFile() const { return m_shaderFile; }
    // The files the program was built from (hot reload) and its successful builds.
    const shader::Record& shaderRecord() const { return m_shader; }
    const Medium& medium() const { return m_medium; }
    const SlabSettings& settings() const { return m_settings; }

  private:
    void clearSums();
    void setMediumUniforms();
    void runPaths(uint64_t first, uint64_t count);
    void measureSharedTallies(); // the default of setSharedTallies, once per process
    void publish();

    std::filesystem::path m_shaderFile;
    bool m_sharedTallies;
    shader::Record m_shader;
    gl::Program m_program;
    std::vector<int> m_loc; // uniform locations, indexed by the Uniform enum in gpu_slab.cpp
    // Buffers, dispatch loop and exact sums in units of 2^-32 per slot (bins, beyond rMax,
    // absorbed, loss+, loss−).
    detail::GpuWorkQueue m_work;
    uint32_t m_eventBudget = kDefaultEventBudget;
    Medium m_medium;
    SlabSettings m_settings;
    SlabTally m_tally;
    double m_seconds = 0;
};

} // namespace pathtrace
