// pathtrace GPU half of the oblique-incidence BSSRDF estimate (bssrdf_estimate.h): the random
// walk of Dal Corso & Frisvad ("On BSSRDF estimation", 2018; seed 001) with the estimators
// analog, implicit and connections, as an OpenGL 4.5 compute shader, shaders/bssrdf_walk.comp.
//   No radial splitting (its tables say levels 0; same expectation).
//   Same physics, conventions, bins, orders and termination as the CPU walk (bssrdf_walk.cpp),
//   traced in float with a Philox4x32-10 stream per (seed of the angle, path index): equal to
//   the CPU estimate in distribution, not bitwise. The result is a BssrdfTally of the same
//   shape, so finalize(), energyProblem(), the table CSVs and the .bwtable writer take it.
//   Work: as gpu_slab.h (rounds of ≤ kMaxPathsPerRound new paths, an iteration budget per
//   dispatch, unfinished paths suspended and resumed: llvmpipe's loop limit drops nothing);
//   a connection walk spends one loop iteration per connection sample (r_bins + 1 per
//   collision), so no iteration is long. Sums: exact 64-bit fixed-point integer tallies
//   (shaders/common/pathtrace_tally.glsl) read back after every dispatch into 128-bit host sums
//   (a connection walk adds a value per loop iteration: only a dispatch bounds the sums; the
//   dispatches themselves are planned on the GPU, common/pathtrace_queue.glsl).
//   On one device and driver the tally is a function of (medium, settings, angle, seed, paths
//   done), bitwise: not of step sizes, budgets or scheduling.
//
// Tally scale. Every walk weight is at most W = max(1 − R(θi), roulette_weight /
// roulette_survival) (analog: 1 − R(θi)), and every connection term at most α·W (its bound in
// bssrdf_walk.cpp; a vertex past the connection roulette's d₀ at most 2·e^{−2}·α·W, the 2 from
// the 32-bit roulette threshold). The shader
// tallies values times s = 2^−k, the smallest k ≥ 0 with W·s ≤ 8, and the host divides
// exactly. So the atomic tallies never see a value above 8: per slot and dispatch at most
// 2^16 invocations × kMaxEventBudget (2^12) iterations × 8 < 2^32, which a 64-bit sum in
// units of 2^−32 holds. Only per-path totals (absorbed, roulette loss, the energy gap D) can
// exceed 16 and go through the exact heavy-value list.
//
// Standard errors: batch means. A histogram path adds one value to one bin (and one cell), so
// the shader tallies Σv and Σv² there, exactly as the CPU (per-path second moments). A
// connection path adds to many bins at many collisions; its per-path square per bin would need
// a per-path accumulator of every bin. Instead bins and cells are tallied into B batches,
// batch b holding the paths with index ≡ b (mod B), n_b of the N paths so far, with sum T_b.
// With X the per-path value in a bin (i.i.d., mean μ, variance σ²) and m = Σ_b T_b / N:
//   Var(T_b − n_b m) = n_b σ² − n_b² σ² / N,  so  E[Σ_b (T_b − n_b m)²] = σ² (N − Σ_b n_b² / N),
//   σ̂² = Σ_b (T_b − n_b m)² / (N − Σ_b n_b² / N)   is unbiased for σ²,
// and Var(m) = σ²/N. BssrdfTally keeps Σ and Σ² per bin, from which meanStderr forms
// (Σ²/N − m²)/(N − 1); the host fills Σ² with the per-path-equivalent second moment
//   Σ² := N m² + (N − 1) σ̂²,
// for which that formula returns exactly σ̂²/N. E[N m² + (N − 1)σ̂²] = N(μ² + σ²) = E[Σ X²], so
// the field is an unbiased estimate of the per-path sum it replaces (it adds like one), and with
// one path per batch (N ≤ B) it is Σ X² exactly. The batch count is a power of two chosen from
// the bins alone (kMaxBatches, fewer only when the cells would not fit kMaxSlots), so the
// error bar has B − 1 ≥ kMinBatches − 1 degrees of freedom: with B = 128 its relative error is
// about 1/sqrt(2·127) = 6 %. Every other field (exits, absorbed, roulette, truncation, D) is a
// per-path value tallied with its square: energyProblem's checks, the accounting identity and
// the z-test of the connections' gap D against the walk's exits, keep their exact meaning.
//   Needs the same current OpenGL 4.5 context on the calling thread for every call.
#pragma once

#include "gl/gl.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/bssrdf_table.h"
#include "pathtrace/detail/gpu_work_queue.h"
#include "pathtrace/pathtrace.h"

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

namespace pathtrace {

class GpuBssrdfEstimator {
  public:
    // New paths per round; a round dispatches until all of them have ended.
    static constexpr uint64_t kMaxPathsPerRound = uint64_t(1) << 16;
    static constexpr uint32_t kDefaultEventBudget = 2048;
    static constexpr uint32_t kMaxEventBudget = 4096; // keeps the 64-bit tallies from wrapping
    static constexpr uint32_t kMaxBatches = 128;
    static constexpr uint32_t kMinBatches = 16;
    static constexpr uint64_t kMaxSlots = uint64_t(1) << 23; // tally slots of 16 bytes: 128 MiB

    // Compiles `shaderFile` (<root>/shaders/bssrdf_walk.comp; its #includes relative to its
    // folder) and resets to Medium{} and EstimateSettings{}. Throws core::Error like reload().
    explicit GpuBssrdfEstimator(std::filesystem::path shaderFile);
    ~GpuBssrdfEstimator();
    GpuBssrdfEstimator(const GpuBssrdfEstimator&) = delete;
    GpuBssrdfEstimator& operator=(const GpuBssrdfEstimator&) = delete;

    // Validates (core::Error naming the field; also when the bins need more than kMaxSlots
    // tally slots or roulette_weight / roulette_survival exceeds 2^35) and starts over at path 0
    // of incidence angle `angleIndex` with an empty tally. EstimateSettings::threads is ignored.
    void reset(const Medium& m, const EstimateSettings& s, size_t angleIndex = 0);
    // Traces up to `maxPaths` more paths, never beyond settings().paths; returns pathsDone().
    // Blocks until they are tallied. Throws core::Error only for an impossible tally (a
    // non-finite or negative value from an edited shader); the tally then starts over.
    uint64_t step(uint64_t maxPaths);
    // The sums so far (bins and cells: second moments from batch means, see above).
    const BssrdfTally& tally() const { return m_tally; }
    uint64_t pathsDone() const { return m_tally.paths; }
    bool finished() const { return m_tally.paths >= m_settings.paths; }
    double seconds() const { return m_seconds; } // wall time spent in step() since reset
    // Dispatches, rounds and host reads since construction (diagnostics, tests).
    const detail::GpuWorkQueue& workQueue() const { return m_work; }
    // Batches per bin and cell of the current settings (1 for the histogram estimators).
    uint32_t batches() const { return m_batches; }

    // Loop iterations one invocation runs per dispatch before it suspends its path (clamped
    // to [1, kMaxEventBudget]); the result does not depend on it.
    void setEventBudget(uint32_t iterations);
    uint32_t eventBudget() const { return m_eventBudget; }

    // Recompiles the shader from disk. On failure throws core::Error ("shaders/
    // bssrdf_walk.comp:LINE: message", or the shaders/common/… file with the error) and keeps
    // the previous program and tally. On success the tally starts over.
    void reload();

    const std::filesystem::path& shaderFile() const { return m_shaderFile; }
    const shader::Record& shaderRecord() const { return m_shader; }
    const Medium& medium() const { return m_medium; }
    const EstimateSettings& settings() const { return m_settings; }
    size_t angleIndex() const { return m_angle; }

  private:
    void clearSums();
    void setUniforms();
    void publish();

    std::filesystem::path m_shaderFile;
    shader::Record m_shader;
    gl::Program m_program;
    std::vector<int> m_loc; // uniform locations, indexed by the Uniform enum in gpu_bssrdf.cpp
    detail::GpuWorkQueue m_work;
    gl::Buffer m_edges; // radial bin edges (float)
    uint32_t m_eventBudget = kDefaultEventBudget;
    Medium m_medium;
    EstimateSettings m_settings;
    size_t m_angle = 0;
    uint32_t m_batches = 1;
    int m_scaleExp = 0; // tally scale 2^-m_scaleExp
    BssrdfTally m_tally;
    double m_seconds = 0;
};

// The whole run of `s` (every angle, all s.paths) on `gpu`, as a table of one run (chunks
// [0, chunkCount)), traced one chunk of kChunkPaths paths per step. `progress` gets the paths
// done over all angles. When `cancel` is set, the table keeps the completed prefix of whole
// chunks of the angle being traced if it is the only angle, else throws core::Error (no
// consistent partial table).
BssrdfTable estimateTableGpu(GpuBssrdfEstimator& gpu, const Medium& m, const EstimateSettings& s,
                             const std::function<void(uint64_t)>& progress = {},
                             const std::atomic<bool>* cancel = nullptr);

} // namespace pathtrace
