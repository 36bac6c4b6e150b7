// Pencil-plot reference: the volumetric path tracer (modules/pathtrace) run progressively in
// a background thread for the three colour channels (each its own medium, its own seed), so
// the UI never waits. The plot reads snapshots; any change of inputs restarts the run.
#pragma once

#include "core/limits.h"
#include "pipeline/capture_entries.h"
#include "pipeline/stage.h"
#include "pipeline/tracer_device.h"

#include "material/material.h"
#include "pathtrace/gpu_slab.h"
#include "pathtrace/pathtrace.h"

#include <array>
#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace app {

struct ReferenceSettings {
    bool enabled = false;
    uint64_t paths = 2000000; // per channel
    int bins = 200;
    uint64_t seed = 1;
    // auto: the GL compute tracer (sliced per frame on the GL thread) where it measured faster
    // than the CPU walk on this machine (tracer_device.h), else the CPU in a background thread
    TracerDevice device = TracerDevice::Auto;
    // Implicit stays the default: on whole profiles (every bin at once) connections cost one
    // connection per bin per collision and reach 1 % far later (bench pathtrace, connect-all).
    pathtrace::Estimator estimator = pathtrace::Estimator::Implicit;
    // Expected-value exits of the CPU histogram walks (pathtrace.h, ExpectedExits): directions
    // scored per collision near the surface, 0 for the actual exits. The GL tracer and the
    // connections estimator tally their own way and ignore it.
    int exitSamples = pathtrace::ExpectedExits{}.samples;
};
// The description of ReferenceSettings' members (core/fields.h).
template <class V> void fields(V& v, ReferenceSettings& s) {
    v("enabled", s.enabled, "path-trace the reference");
    v("paths", s.paths, "photon paths per channel", core::Limits{1, 1e18});
    v("bins", s.bins, "radial bins", core::Limits{1, 1e5});
    v("seed", s.seed, "random seed");
    v("device", s.device, "auto: the GPU where it measured faster than the CPU, else the CPU");
    v("estimator", s.estimator, "slab estimator (connections: CPU only)");
    v("exit_samples", s.exitSamples,
      "expected-value exits: directions scored per collision near the surface (0: the actual "
      "exits; CPU histogram walks)",
      core::Limits{0, 64});
}

struct ReferenceSnapshot {
    bool running = false;
    uint64_t pathsDone = 0, pathsTarget = 0; // per channel
    double pathsPerSecond = 0;               // all channels together
    std::array<pathtrace::SlabResult, 3> channel;
    std::string problem;
    // The run's own energy check (pathtrace::energyProblem) per channel, "" when every channel
    // passes: "channel R: <problem>; ...". The plot then draws no error band, the Errors panel
    // lists it.
    std::string energy;
    std::array<bool, 3> energyFailed{};   // per channel, set with `energy`
    bool energyFails(int channel) const { // channel 0..2, or 3 (luminance: any channel)
        return channel == 3 ? energyFailed[0] || energyFailed[1] || energyFailed[2]
                            : energyFailed[size_t(channel)];
    }
    std::string device = "CPU";
};
// Fills snap.energy and snap.energyFailed from snap.channel.
void checkEnergy(ReferenceSnapshot& snap);

class ReferenceRunner {
  public:
    ReferenceRunner() = default;
    ~ReferenceRunner();
    ReferenceRunner(const ReferenceRunner&) = delete;
    ReferenceRunner& operator=(const ReferenceRunner&) = delete;

    // Restarts the run for these media (R, G, B) and settings. Validates first; a bad input
    // becomes snapshot().problem and nothing runs.
    void start(const std::array<pathtrace::Medium, 3>& media, const pathtrace::SlabSettings& s,
               uint64_t pathsPerChannel);
    void cancel();
    // Blocks until the current run has reached its target (or failed); for captures and CLI.
    void wait();
    ReferenceSnapshot snapshot() const;
    // Monotonic counter bumped with every new snapshot (the plot rebuilds its series then).
    uint64_t version() const { return m_version.load(); }

  private:
    void run(std::array<pathtrace::Medium, 3> media, pathtrace::SlabSettings s, uint64_t target);

    std::thread m_thread;
    std::atomic<bool> m_cancel{false};
    std::atomic<uint64_t> m_version{0};
    mutable std::mutex m_mutex;
    ReferenceSnapshot m_snapshot;
};

// The same reference on the GL compute tracer (shaders/pathtrace_slab.comp). GL work must stay
// on the GL thread, so the frame loop calls step() with a time budget: the UI keeps its frame
// rate while paths accumulate. reload() recompiles the shader after an edit; on a compile
// error the previous program keeps running and problem() names file:line.
class GpuReference {
  public:
    explicit GpuReference(std::filesystem::path shaderFile) : m_shaderFile(std::move(shaderFile)) {}
    void start(const std::array<pathtrace::Medium, 3>& media, const pathtrace::SlabSettings& s,
               uint64_t pathsPerChannel);
    // Traces for about `budgetMs`; returns true when new paths arrived.
    bool step(double budgetMs);
    void reload();
    // Hot reload: reload() when one of `changed` is a file the tracers' program was built from.
    bool reloadShaders(const std::vector<std::filesystem::path>& changed);
    // The tracers' programs by channel ("pathtrace_slab.comp[R]", …), once started.
    shader::Records shaderRecords() const;
    void cancel() { m_target = m_done; }
    const std::filesystem::path& shaderFile() const { return m_shaderFile; }
    ReferenceSnapshot snapshot() const;

  private:
    std::filesystem::path m_shaderFile;
    std::array<std::unique_ptr<pathtrace::GpuSlabTracer>, 3> m_tracers;
    std::array<pathtrace::SlabSettings, 3> m_settings;
    std::array<pathtrace::Medium, 3> m_media;
    uint64_t m_target = 0, m_done = 0;
    double m_seconds = 0;
    std::string m_problem;       // the run cannot go on (bad input, tally error)
    std::string m_shaderProblem; // the last edit failed to compile: old program still runs
};

// The reference as a stage of the workbench: inputs are the σ of the source model (the one
// the lit spheres and the scene use), the user's settings and the plot's radius; a change of
// any restarts the run (CPU in the background, or GPU slices per frame in update()).
struct ReferenceInputs {
    std::optional<material::MaterialParams> params; // none: no usable model, nothing runs
    std::string model;                              // its display path
    ReferenceSettings settings;
    double rMaxMm = 20.0;
};

class ReferenceStage : public StageOf<ReferenceInputs> {
  public:
    explicit ReferenceStage(std::filesystem::path gpuShaderFile)
        : m_gpu(std::move(gpuShaderFile)) {}
    const char* name() const override { return "reference"; }
    // Starts or restarts the run when the inputs changed, gives the GPU tracer a slice;
    // true when new paths arrived (or the run restarted).
    bool update(const ReferenceInputs& in) override;
    StageStatus status() const override; // problems: bad inputs, a failed energy check
    void cancel() override;
    // Runs to the target (captures, CLI, tests).
    ReferenceSnapshot finish(const ReferenceInputs& in);
    // Captures (when enabled): runs to the target, then `reference`, the raw MCML-convention R_d
    // per channel with its standard errors (z-tested on replay); the last row (r_mm = -1) holds
    // the total diffuse reflectance per channel. core::Error with the run's problem.
    void capture(const ReferenceInputs& in, CaptureEntries& out);
    ReferenceSnapshot snapshot() const { return m_gpuMode ? m_gpu.snapshot() : m_cpu.snapshot(); }
    void restart() { m_key.clear(); }
    // Hot reload of the GL tracer when one of `changed` is a file its program was built from.
    bool reloadShaders(const std::vector<std::filesystem::path>& changed) override {
        return m_gpu.reloadShaders(changed);
    }
    shader::Records shaderRecords() const override; // "reference:PROGRAM"
    const std::string& model() const { return m_model; }
    // With device auto: what the measurement found ("CPU … paths/s, GPU … paths/s: CPU"), else "".
    std::string deviceChoice() const { return m_auto ? m_choice : std::string(); }

  private:
    ReferenceRunner m_cpu;
    GpuReference m_gpu;
    bool m_gpuMode = false;
    bool m_auto = false;  // the device was chosen by measurement
    std::string m_choice; // what the measurement found (status)
    std::string m_key, m_model;
    uint64_t m_seen = 0, m_gpuSteps = 0;
};

// The three channels' media of a material (each channel its own medium).
std::array<pathtrace::Medium, 3> mediaOf(const material::MaterialParams& p);

} // namespace app
