// Tracer device choice by measured throughput (tracer_device.h).
#include "pipeline/tracer_device.h"

#include "core/core.h"
#include "pathtrace/gpu_slab.h"

#include <cstdio>
#include <map>
#include <mutex>

namespace app {

namespace {

// MCML's reference case (thesis 3.2): the medium bench pathtrace measures too.
pathtrace::Medium probeMedium() {
    return pathtrace::Medium{0.01, 1.0, 0.0, 1.3};
}

// Paths per second of `trace(first, n)`, growing n from `n0` until one call takes `budgetMs`.
template <class Trace> double rateOf(Trace&& trace, uint64_t n0, double budgetMs) {
    uint64_t first = 0;
    trace(first, n0); // warm-up: code paths, caches, the driver's first dispatch
    first += n0;
    for (uint64_t n = n0;; n *= 2) {
        core::Stopwatch clock;
        trace(first, n);
        first += n;
        const double ms = clock.ms();
        if (ms >= budgetMs || n >= (uint64_t(1) << 26)) return double(n) / std::max(ms, 1e-3) * 1e3;
    }
}

} // namespace

std::string ThroughputProbe::summary() const {
    char buf[160];
    std::snprintf(buf, sizeof buf, "CPU %.3g paths/s, GPU %.3g paths/s: %s", cpuPathsPerSecond,
                  gpuPathsPerSecond, gpuFaster() ? "GPU" : "CPU");
    return gpuProblem.empty() ? std::string(buf)
                              : std::string(buf) + " (GL tracer: " + gpuProblem + ")";
}

ThroughputProbe measureSlabThroughput(const std::filesystem::path& slabShader,
                                      const pathtrace::SlabSettings& s, double budgetMs) {
    ThroughputProbe p;
    const pathtrace::Medium m = probeMedium();
    pathtrace::SlabSettings cpu = s;
    cpu.estimator = pathtrace::Estimator::Implicit;
    // The walk's own rate, as the GL tracer's is: with the actual exits. Expected-value exits
    // (the CPU default) cost about twice as much per path and give more per path, so the CPU
    // is at least this good a choice; the GPU is taken only where it outruns even this.
    cpu.exits.samples = 0;
    cpu.paths = uint64_t(1) << 40;
    p.cpuPathsPerSecond =
        rateOf([&](uint64_t first, uint64_t n) { (void)pathtrace::traceSlab(m, cpu, first, n); },
               1024, budgetMs);
    try {
        pathtrace::GpuSlabTracer gpu(slabShader);
        gpu.reset(m, cpu);
        p.gpuPathsPerSecond = rateOf([&](uint64_t, uint64_t n) { gpu.step(n); }, 1024, budgetMs);
    } catch (const core::Error& e) {
        p.gpuProblem = e.what();
    }
    return p;
}

const ThroughputProbe& slabThroughput(const std::filesystem::path& slabShader) {
    static std::mutex mutex;
    static std::map<std::filesystem::path, ThroughputProbe> measured;
    std::lock_guard lock(mutex);
    auto it = measured.find(slabShader);
    if (it == measured.end()) {
        core::Stopwatch clock;
        it = measured.emplace(slabShader, measureSlabThroughput(slabShader, {})).first;
        char took[48];
        std::snprintf(took, sizeof took, " (in %.0f ms)", clock.ms());
        core::logInfo("tracer device (measured once): " + it->second.summary() + took);
    }
    return it->second;
}

bool chooseGpu(TracerDevice d, const std::filesystem::path& slabShader) {
    switch (d) {
    case TracerDevice::Cpu:
        return false;
    case TracerDevice::Gpu:
        return true;
    case TracerDevice::Auto:
        break;
    }
    return slabThroughput(slabShader).gpuFaster();
}

} // namespace app
