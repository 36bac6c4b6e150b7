// pathtrace GPU lit sphere: the path-traced lit-sphere image of sphere_tracer.h (setup and
// pixel definition: lit_sphere.h) as an OpenGL 4.5 compute shader,
// shaders/pathtrace_sphere.comp, run like the GPU slab tracer (gpu_slab.h): flat event loop
// with a per-dispatch event budget and suspended paths (safe under llvmpipe's 65535-iteration
// loop limit; dispatches planned on the GPU), Philox4x32-10 streams, 64-bit fixed-point integer
// tallies read back once per round (one value per pixel per path) into 128-bit host sums.
//   Estimator: that of traceLitSphere (entry uniform on the light's projected disk, each path
//   power πR²/N, Fresnel at entry dropped as specular, refraction with weight 1 − F, implicit
//   absorption with weight roulette, truncation at the event limit, Fresnel roulette at boundary
//   hits, exit tallied into the pixel its point projects to when n·z > 0); pixel value = power /
//   footprint (sphereFootprints), N = pathsDone(), variance of the mean from per-path second
//   moments. Float state: statistically, not bitwise, equal to the CPU image.
//   RGB: channel c of path i uses media[c] and the Philox stream (key seed, counter (i, block,
//   'SPH0' + c)): one stream per channel and path, a function of (seed, path, channel) only.
//   Determinism: on one device and driver the image is a function of (media, setup, options,
//   paths done), bitwise: not of step sizes, event budgets, dispatches or scheduling.
//   Needs the same current OpenGL 4.5 context on the calling thread for every call.
#pragma once

#include "gl/gl.h"
#include "pathtrace/camera.h"
#include "pathtrace/detail/gpu_work_queue.h"
#include "pathtrace/lit_sphere.h"
#include "pathtrace/pathtrace.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace pathtrace {

class GpuSphereTracer {
  public:
    // New paths (per channel) per round; a round dispatches until all of them have ended.
    static constexpr uint64_t kMaxPathsPerRound = uint64_t(1) << 15;
    static constexpr uint32_t kDefaultEventBudget = 4096;
    static constexpr uint32_t kMaxEventBudget = 32768; // llvmpipe ends loops at 65535

    // Compiles `shaderFile` (e.g. <root>/shaders/pathtrace_sphere.comp) and resets to default
    // media and LitSphereSetup{}. Throws core::Error like reload().
    explicit GpuSphereTracer(std::filesystem::path shaderFile);
    ~GpuSphereTracer();
    GpuSphereTracer(const GpuSphereTracer&) = delete;
    GpuSphereTracer& operator=(const GpuSphereTracer&) = delete;

    // Validates (core::Error naming the field) and starts over at path 0 with an empty tally.
    // The target is litSpherePaths(setup) paths per channel; setup.threads is ignored.
    void reset(const std::array<Medium, 3>& media, const LitSphereSetup& setup,
               const TraceOptions& options = {});
    // Traces up to `maxPathsPerChannel` more paths (each in all three channels), never beyond
    // the target, and returns pathsDone(). Blocks until they are tallied. Throws core::Error
    // only for an impossible tally (from an edited shader); the tally then starts over.
    uint64_t step(uint64_t maxPathsPerChannel);
    // The image of the paths so far (traceLitSphere's definition with N = pathsDone()).
    Image image() const;
    // Exited power per channel (W at 1 W/mm², visible or not) and its standard error.
    std::array<double, 3> exitedPower(std::array<double, 3>* stderrOut = nullptr) const;
    // Power (W) of paths truncated at the event limit per channel: a bound on what the image
    // misses (0 unless the albedo is within ~1e-5 of 1).
    std::array<double, 3> truncatedPower(std::array<double, 3>* stderrOut = nullptr) const;
    uint64_t pathsDone() const { return m_paths; }
    uint64_t targetPaths() const { return m_target; }
    bool finished() const { return m_paths >= m_target; }
    uint64_t events() const { return m_work.events(); } // collisions, all channels (diagnostics)
    double seconds() const { return m_seconds; }        // wall time in step() since reset

    void setEventBudget(uint32_t events); // clamped to [1, kMaxEventBudget]
    uint32_t eventBudget() const { return m_eventBudget; }

    // Recompiles the shader from disk. On failure throws core::Error
    // ("shaders/pathtrace_sphere.comp:LINE: message", or the shaders/common/… file with the
    // error) and keeps the previous program and tally. On success the tally starts over.
    void reload();

    const std::filesystem::path& shaderFile() const { return m_shaderFile; }
    // The files the program was built from (hot reload) and its successful builds.
    const shader::Record& shaderRecord() const { return m_shader; }
    const LitSphereSetup& setup() const { return m_setup; }

  private:
    void clearSums();
    std::array<double, 3> slotPower(size_t offset, std::array<double, 3>* stderrOut) const;
    void setUniforms();
    void runPaths(uint64_t first, uint64_t paths);

    std::filesystem::path m_shaderFile;
    shader::Record m_shader;
    gl::Program m_program;
    std::vector<int> m_loc;
    // Buffers, dispatch loop and exact sums in units of 2^-32: slot c·(P + 2) + p (pixel p),
    // c·(P + 2) + P (exited), c·(P + 2) + P + 1 (truncated).
    detail::GpuWorkQueue m_work;
    uint32_t m_eventBudget = kDefaultEventBudget;
    std::array<Medium, 3> m_media{};
    LitSphereSetup m_setup;
    TraceOptions m_options;
    PixelGeometry m_pixels;
    uint64_t m_target = 0, m_paths = 0;
    double m_seconds = 0;
};

} // namespace pathtrace
