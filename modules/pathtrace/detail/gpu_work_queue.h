// pathtrace/detail/gpu_work_queue: the host machinery shared by the GL compute path tracers
// (gpu_slab.cpp, gpu_sphere.cpp, gpu_bssrdf.cpp): program build with its uniform-location
// table, the tally, heavy-list, queue and suspended-path buffers, the suspended-path dispatch
// loop of a round, and the exact readback of the 64-bit fixed-point tallies
// (shaders/common/pathtrace_tally.glsl) into 128-bit host sums.
#pragma once

#include "gl/gl.h"
#include "shader/program.h"

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace pathtrace::detail {

using u128 = unsigned __int128;
using i128 = __int128;

inline constexpr double kFixedOne = 4294967296.0; // 2^32: the tallies' unit is 2^-32

// p in [0, 1] as a threshold on a uniform 32-bit word: P(word < t) = t / 2^32.
uint32_t wordThreshold(double p);
// Fixed-point sums (unit 2^-32) as doubles.
double toDouble(u128 units);
double toDouble(i128 units);

// Loads and compiles `shaderFile` (shader::build: includes relative to its folder, errors as
// file:line, the files read go into `record`; `defines`, "#define …" lines, right after its
// #version) and looks up `names`. Throws core::Error; on failure `program` and `loc` are left
// unchanged.
void buildTracerProgram(const std::filesystem::path& shaderFile, shader::Record& record,
                        std::span<const char* const> names, gl::Program& program,
                        std::vector<int>& loc, const std::string& defines = {});

// When the 64-bit tallies must be emptied. EndOfRun: a path adds at most one value per slot
// (slab, sphere: ≤ 3 items of ≤ 1 value each), so a run of ≤ kRoundsPerRun rounds of ≤ 2^16
// paths adds < 2^19 · 3 · 256 · 2^32 < 2^62 per slot and cannot wrap 64 bits: the host reads
// once per run. EveryDispatch: an item may add a value per loop iteration (the BSSRDF walk's
// connections), bounded per dispatch only: a small kernel folds them into 128-bit sums on the
// GPU after each dispatch and the host reads those once per run (tables of up to 2^20 slots;
// bigger ones are read by the host after every dispatch).
enum class TallyReads { EndOfRun, EveryDispatch };

class GpuWorkQueue {
  public:
    static constexpr uint64_t kRoundsPerRun = 8;

    // heavyPerItem: values one work item may tally through the heavy list; itemsPerRound: the
    // most new work items one round starts (a multiple of itemsPerPath, the items of one path).
    GpuWorkQueue(uint64_t heavyPerItem, uint64_t itemsPerRound, uint64_t itemsPerPath,
                 TallyReads reads);

    // (Re)creates the tally buffer for `slots` slots and, once, the other buffers.
    void allocate(size_t slots);
    // Zeroes the host sums (`slots` slots), the counters and the tally buffer.
    void clear(size_t slots);
    // Who issues the planned dispatches. Gpu: the host issues glDispatchComputeIndirect in
    // batches without reading anything in between. Host: it reads the planner's group count
    // after each dispatch and issues glDispatchCompute with it (the same dispatches, the same
    // tally). Chosen once per process by measuring both costs (planning()); tests may set it.
    enum class Planning { Host, Gpu };
    static void setPlanning(Planning p);
    // Tables of more slots than this (default 2^20) are read after every dispatch instead of
    // folded on the GPU (EveryDispatch; tests compare the two). Applies from the next allocate().
    static void setMaxFoldSlots(uint64_t slots);
    bool folds() const { return m_fold; }
    // Measures on the first call in the process (needs a current GL context).
    static Planning planning();

    // The most paths one run() takes: kRoundsPerRun rounds.
    uint64_t maxPathsPerRun() const;
    // Traces paths [firstPath, firstPath + paths) to completion with `program` (the caller has
    // set its uniforms), in rounds of itemsPerRound items. Dispatches and rounds hand over on
    // the GPU (common/pathtrace_queue.glsl): the host issues dispatches in growing batches by
    // glDispatchComputeIndirect and reads the queue once per batch, and the tallies once per
    // run (or per dispatch, see TallyReads). Adds the tallies into sum/sumSq. Throws
    // core::Error naming `shaderFile` for an impossible queue or tally.
    void run(GLuint program, uint64_t firstPath, uint64_t paths,
             const std::filesystem::path& shaderFile);

    // Exact sums in units of 2^-32 per slot.
    const std::vector<u128>& sum() const { return m_sum; }
    const std::vector<u128>& sumSq() const { return m_sumSq; }
    uint64_t events() const { return m_events; }
    uint64_t heavyTallies() const { return m_heavyTallies; }
    // Since construction (diagnostics, tests): rounds and dispatches that ran, reads of the
    // queue and of the tallies by the host.
    uint64_t rounds() const { return m_rounds; }
    uint64_t dispatches() const { return m_dispatches; }
    uint64_t queueReads() const { return m_queueReads; }
    uint64_t tallyReads() const { return m_tallyReads; }

  private:
    void readTallies(const std::filesystem::path& shaderFile);
    void fold(); // the 64-bit sums into the 128-bit ones, on the GPU

    uint64_t m_heavyPerItem;
    uint64_t m_heavyCapacity = 0;
    gl::Buffer m_acc, m_heavy, m_queue;
    gl::Buffer m_wide; // 128-bit sums when folding
    bool m_fold = false;
    gl::Program m_foldProgram;
    int m_foldSlotsLoc = -1;
    gl::Buffer m_suspended[2]; // ping-pong lists of paths suspended between dispatches
    std::vector<u128> m_sum, m_sumSq;
    uint64_t m_events = 0;
    uint64_t m_heavyTallies = 0;
    uint64_t m_itemsPerRound, m_itemsPerPath;
    TallyReads m_reads;
    uint64_t m_rounds = 0, m_dispatches = 0, m_queueReads = 0, m_tallyReads = 0;
};

} // namespace pathtrace::detail
