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
// file:line, the files read go into `record`) and looks up `names`. Throws core::Error; on
// failure `program` and `loc` are left unchanged.
void buildTracerProgram(const std::filesystem::path& shaderFile, shader::Record& record,
                        std::span<const char* const> names, gl::Program& program,
                        std::vector<int>& loc);

// When the host reads the 64-bit tallies. EndOfRound: a work item adds at most one value per
// slot (slab, sphere), so a round of ≤ 2^16 items adds < 2^16 · 256 · 2^32 = 2^56 per slot and
// cannot wrap 64 bits: the host reads once per round. EveryDispatch: an item may add a value
// per loop iteration (the BSSRDF walk's connections), bounded per dispatch only.
enum class TallyReads { EndOfRound, EveryDispatch };

class GpuWorkQueue {
  public:
    // heavyPerItem: values one work item may tally through the heavy list; maxItemsPerRound:
    // the most new work items one round starts.
    GpuWorkQueue(uint64_t heavyPerItem, uint64_t maxItemsPerRound, TallyReads reads);

    // (Re)creates the tally buffer for `slots` slots and, once, the other buffers.
    void allocate(size_t slots);
    // Zeroes the host sums (`slots` slots), the counters and the tally buffer.
    void clear(size_t slots);
    // Runs one round of `count` new work items to completion with `program` (the caller has
    // set its uniforms). The dispatches hand over on the GPU (common/pathtrace_queue.glsl): the
    // host issues them in batches by glDispatchComputeIndirect and reads the queue once per
    // batch, and the tallies once per round (or per dispatch, see TallyReads). Adds the tallies
    // into sum/sumSq. Throws core::Error naming `shaderFile` for an impossible queue or tally.
    void runRound(GLuint program, uint64_t count, const std::filesystem::path& shaderFile);

    // Exact sums in units of 2^-32 per slot.
    const std::vector<u128>& sum() const { return m_sum; }
    const std::vector<u128>& sumSq() const { return m_sumSq; }
    uint64_t events() const { return m_events; }
    uint64_t heavyTallies() const { return m_heavyTallies; }
    // Since construction (diagnostics, tests): dispatches that ran, reads of the queue and of
    // the tallies by the host.
    uint64_t dispatches() const { return m_dispatches; }
    uint64_t queueReads() const { return m_queueReads; }
    uint64_t tallyReads() const { return m_tallyReads; }

  private:
    void readTallies(const std::filesystem::path& shaderFile);

    uint64_t m_heavyPerItem;
    uint64_t m_heavyCapacity;
    gl::Buffer m_acc, m_heavy, m_queue;
    gl::Buffer m_suspended[2]; // ping-pong lists of paths suspended between dispatches
    std::vector<u128> m_sum, m_sumSq;
    uint64_t m_events = 0;
    uint64_t m_heavyTallies = 0;
    TallyReads m_reads;
    uint64_t m_dispatches = 0, m_queueReads = 0, m_tallyReads = 0;
};

} // namespace pathtrace::detail
