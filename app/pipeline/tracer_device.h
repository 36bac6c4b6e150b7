// Which device traces a reference: the CPU walk (modules/pathtrace, all hardware threads, in a
// background thread) or the GL compute tracer (sliced per frame on the GL thread). `auto`, the
// default, decides by a throughput measured on this machine once per process, not by the GL
// vendor string: a card that traces more paths per second than the CPU gets the references;
// Mesa's llvmpipe (several times slower than one CPU core) does not.
//
// The measure is paths per second of the same walk on the same medium (MCML's reference case,
// thesis 3.2: σa 0.01/mm, σs 1/mm, g 0, η 1.3) with the settings the reference uses. A CPU path
// also carries radial splitting (pathtrace.h, Splitting), which makes its far bins several
// times cheaper per path: a card has to beat that by throughput to win there too, and every
// real card measured did so by a wide margin (README, bench pathtrace), so no factor is added.
// The CPU walk is measured with the actual exits, as the GL tracer tallies them: its default,
// expected-value exits, costs about twice as much per path for a variance per path lower by
// more than that (docs/ARCHITECTURE.md, Expected-value exits), so a card that outruns the plain
// walk is the better device either way, and llvmpipe stays behind it.
#pragma once

#include "pathtrace/pathtrace.h"

#include <array>
#include <filesystem>
#include <string>
#include <utility>

namespace app {

enum class TracerDevice { Auto, Cpu, Gpu };
constexpr auto enumNames(TracerDevice) {
    return std::array{std::pair{TracerDevice::Auto, "auto"}, std::pair{TracerDevice::Cpu, "cpu"},
                      std::pair{TracerDevice::Gpu, "gpu"}};
}

struct ThroughputProbe {
    double cpuPathsPerSecond = 0;
    double gpuPathsPerSecond = 0;
    std::string gpuProblem; // the GL tracer could not run (then the CPU is chosen)
    bool gpuFaster() const { return gpuProblem.empty() && gpuPathsPerSecond > cpuPathsPerSecond; }
    // "GPU 4.1e+07 paths/s, CPU 1.3e+06 paths/s: GPU" (or the GL problem)
    std::string summary() const;
};

// Traces the probe medium for about `budgetMs` on each device (after a warm-up) with the CPU
// walk of `s` and the GL tracer built from `slabShader` (shaders/pathtrace_slab.comp). Needs
// the current GL context. Never throws: a GL failure becomes gpuProblem.
ThroughputProbe measureSlabThroughput(const std::filesystem::path& slabShader,
                                      const pathtrace::SlabSettings& s, double budgetMs = 40.0);

// The first measurement in this process for `slabShader` (measured on the first call, with the
// default SlabSettings; later calls return it).
const ThroughputProbe& slabThroughput(const std::filesystem::path& slabShader);

// Whether the GL tracer runs: Gpu always, Cpu never, Auto by slabThroughput (measured on the
// first call that needs it).
bool chooseGpu(TracerDevice d, const std::filesystem::path& slabShader);

} // namespace app
