// Pencil-plot reference: the volumetric path tracer (modules/pathtrace) run progressively in
// a background thread for the three colour channels (each its own medium, its own seed), so
// the UI never waits. The plot reads snapshots; any change of inputs restarts the run.
#pragma once

#include "pathtrace/pathtrace.h"

#include <array>
#include <atomic>
#include <mutex>
#include <string>
#include <thread>

namespace app {

struct ReferenceSettings {
    bool enabled = false;
    uint64_t paths = 2000000; // per channel
    int bins = 200;
    uint64_t seed = 1;
};

struct ReferenceSnapshot {
    bool running = false;
    uint64_t pathsDone = 0, pathsTarget = 0; // per channel
    double pathsPerSecond = 0;               // all channels together
    std::array<pathtrace::SlabResult, 3> channel;
    std::string problem;
};

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

} // namespace app
