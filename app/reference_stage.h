// Pencil-plot reference: the volumetric path tracer (modules/pathtrace) run progressively in
// a background thread for the three colour channels (each its own medium, its own seed), so
// the UI never waits. The plot reads snapshots; any change of inputs restarts the run.
#pragma once

#include "pathtrace/gpu_slab.h"
#include "pathtrace/pathtrace.h"

#include <array>
#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace app {

struct ReferenceSettings {
    bool enabled = false;
    uint64_t paths = 2000000; // per channel
    int bins = 200;
    uint64_t seed = 1;
    bool gpu = false; // GL compute tracer, sliced per frame on the GL thread, instead of the CPU
};
// The description of ReferenceSettings' members (core/fields.h).
template <class V> void fields(V& v, ReferenceSettings& s) {
    v("enabled", s.enabled, "path-trace the reference");
    v("paths", s.paths, "photon paths per channel");
    v("bins", s.bins, "radial bins");
    v("seed", s.seed, "random seed");
    v("gpu", s.gpu, "GL compute tracer instead of the CPU");
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
    bool energyFails(int channel) const; // channel 0..2, or 3 (luminance: any channel)
    std::string device = "CPU";
};
// Fills snap.energy from snap.channel.
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
    void cancel() { m_target = m_done; }
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

} // namespace app
