// pathtrace/detail/gpu_work_queue (see gpu_work_queue.h): buffers, the suspended-path dispatch
// loop and the exact fixed-point tally readback shared by the GL compute path tracers.
#include "pathtrace/detail/gpu_work_queue.h"

#include "core/core.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

namespace pathtrace::detail {

namespace {

// Must match shaders/pathtrace_*.comp and common/pathtrace_tally.glsl.
constexpr GLuint kAccBinding = 0, kHeavyBinding = 1, kQueueBinding = 2, kInBinding = 3,
                 kOutBinding = 4;
constexpr uint64_t kLocalSize = 64;
constexpr uint64_t kSuspendedWords = 20; // 5 uvec4 per suspended path
// common/pathtrace_queue.glsl: PtQueue's words and the planner's constants
enum QueueWord : uint32_t {
    qNext,
    qInTaken,
    qOutCount,
    qEventsLo,
    qEventsHi,
    qInCount,
    qFinished,
    qFault,
    qFaultValue,
    qFaultCount,
    qDispatches,
    qPad,
    qGroups, // (groups, 1, 1, pad): glDispatchComputeIndirect's arguments
    kQueueWords = qGroups + 4
};
constexpr uint64_t kItemsPerInvocation = 4; // invocations launched per item of work
constexpr uint64_t kMaxGroups = 1024;       // at most 65536 invocations per dispatch
// Dispatches issued between two reads of the queue when the tallies need no read per dispatch:
// a round of the slab tracer takes 2–6 on the reference case; the surplus ones have 0 groups.
constexpr int kDispatchBatch = 4;
constexpr uint64_t kMaxInvocations = kMaxGroups * kLocalSize;
constexpr double kMaxHeavy = 35184372088832.0; // 2^45: beyond it a square could overflow u128

} // namespace

uint32_t wordThreshold(double p) {
    const double t = std::floor(p * kFixedOne);
    return t >= kFixedOne - 1.0 ? 0xFFFFFFFFu : static_cast<uint32_t>(std::max(0.0, t));
}

double toDouble(u128 units) {
    return std::ldexp(static_cast<double>(units), -32);
}
double toDouble(i128 units) {
    return units < 0 ? -toDouble(static_cast<u128>(-units)) : toDouble(static_cast<u128>(units));
}

void buildTracerProgram(const std::filesystem::path& shaderFile, shader::Record& record,
                        std::span<const char* const> names, gl::Program& program,
                        std::vector<int>& loc) {
    // throws core::Error; nothing changed yet
    gl::Program built =
        shader::build(shader::Sources::forFile(shaderFile),
                      {{GL_COMPUTE_SHADER, shaderFile.filename().string()}}, record);
    std::vector<int> found(names.size());
    for (size_t i = 0; i < names.size(); ++i)
        found[i] = gl::uniformLocation(built, names[i]);
    program = std::move(built);
    loc = std::move(found);
}

GpuWorkQueue::GpuWorkQueue(uint64_t heavyPerItem, uint64_t maxItemsPerRound, TallyReads reads)
    // Items ending in one dispatch: at most the round's new items plus the suspended ones; in a
    // round: its new items.
    : m_heavyPerItem(heavyPerItem),
      m_heavyCapacity(heavyPerItem * (maxItemsPerRound + kMaxInvocations)), m_reads(reads) {}

void GpuWorkQueue::allocate(size_t slots) {
    m_acc = gl::createBuffer(slots * 4 * sizeof(uint32_t), nullptr);
    if (!m_heavy) m_heavy = gl::createBuffer(8 + m_heavyCapacity * 8, nullptr);
    if (!m_queue) m_queue = gl::createBuffer(kQueueWords * sizeof(uint32_t), nullptr);
    for (auto& list : m_suspended)
        if (!list) list = gl::createBuffer(kMaxInvocations * kSuspendedWords * 4, nullptr);
}

void GpuWorkQueue::clear(size_t slots) {
    m_sum.assign(slots, 0);
    m_sumSq.assign(slots, 0);
    m_events = 0;
    m_heavyTallies = 0;
    if (m_acc)
        glClearNamedBufferData(m_acc.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
}

void GpuWorkQueue::runRound(GLuint p, uint64_t count, const std::filesystem::path& shaderFile) {
    glProgramUniform1ui(p, glGetUniformLocation(p, "PtHeavyCapacity"),
                        static_cast<GLuint>(std::min<uint64_t>(m_heavyCapacity, 0xFFFFFFFFu)));
    // The first dispatch: no suspended paths, about kItemsPerInvocation items per invocation.
    // Every later one is planned by the last invocation of the one before
    // (common/pathtrace_queue.glsl).
    uint32_t queue[kQueueWords] = {};
    const uint64_t perGroup = kLocalSize * kItemsPerInvocation;
    queue[qGroups] = static_cast<uint32_t>(
        std::clamp<uint64_t>((count + perGroup - 1) / perGroup, 1, kMaxGroups));
    queue[qGroups + 1] = queue[qGroups + 2] = 1;
    glNamedBufferSubData(m_queue.id(), 0, sizeof queue, queue);
    const uint32_t zeros[2] = {0, 0};
    glNamedBufferSubData(m_heavy.id(), 0, 8, zeros);
    const bool everyDispatch = m_reads == TallyReads::EveryDispatch;
    const int batch = everyDispatch ? 1 : kDispatchBatch;
    for (int cur = 0;;) {
        for (int b = 0; b < batch; ++b, cur ^= 1) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAccBinding, m_acc.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kHeavyBinding, m_heavy.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kQueueBinding, m_queue.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kInBinding, m_suspended[cur].id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kOutBinding, m_suspended[cur ^ 1].id());
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, m_queue.id());
            glUseProgram(p);
            glDispatchComputeIndirect(static_cast<GLintptr>(qGroups * sizeof(uint32_t)));
            glUseProgram(0);
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
            // barrier: the tracer's queue (with the next dispatch's group count), tallies and
            // suspended paths → the next glDispatchComputeIndirect, the next dispatch, which
            // reads the suspended paths, and the readbacks and clears below
            glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                            GL_BUFFER_UPDATE_BARRIER_BIT);
            if (everyDispatch) readTallies(shaderFile);
        }
        glGetNamedBufferSubData(m_queue.id(), 0, sizeof queue, queue);
        ++m_queueReads;
        if (queue[qFault] != 0)
            throw core::Error(shaderFile.string(), 0,
                              "suspended paths left behind (" + std::to_string(queue[qFaultValue]) +
                                  " of " + std::to_string(queue[qFaultCount]) + " resumed)");
        if (queue[qGroups] == 0) break; // the round is done
    }
    m_dispatches += queue[qDispatches];
    m_events += (uint64_t(queue[qEventsHi]) << 32) | queue[qEventsLo];
    if (!everyDispatch) readTallies(shaderFile);
}

void GpuWorkQueue::readTallies(const std::filesystem::path& shaderFile) {
    const size_t slots = m_sum.size();
    std::vector<uint32_t> acc(slots * 4);
    glGetNamedBufferSubData(m_acc.id(), 0, static_cast<GLsizeiptr>(acc.size() * 4), acc.data());
    glClearNamedBufferData(m_acc.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    ++m_tallyReads;
    for (size_t i = 0; i < slots; ++i) {
        m_sum[i] += (u128(acc[4 * i + 1]) << 32) | acc[4 * i];
        m_sumSq[i] += (u128(acc[4 * i + 3]) << 32) | acc[4 * i + 2];
    }
    uint32_t heavyCount = 0;
    glGetNamedBufferSubData(m_heavy.id(), 0, 4, &heavyCount);
    if (heavyCount == 0) return;
    const uint32_t zero = 0;
    glNamedBufferSubData(m_heavy.id(), 0, 4, &zero); // the list starts over after this read
    if (heavyCount > m_heavyCapacity)
        throw core::Error(shaderFile.string(), 0,
                          "heavy-weight list overflowed (" + std::to_string(heavyCount) +
                              " entries): the shader tallied more than " +
                              std::to_string(m_heavyPerItem) + " values per path");
    m_heavyTallies += heavyCount;
    std::vector<uint32_t> heavy(2 * size_t(heavyCount));
    glGetNamedBufferSubData(m_heavy.id(), 8, static_cast<GLsizeiptr>(heavy.size() * 4),
                            heavy.data());
    for (size_t k = 0; k < heavyCount; ++k) {
        const uint32_t slot = heavy[2 * k];
        const double v = std::bit_cast<float>(heavy[2 * k + 1]);
        if (slot >= slots || !std::isfinite(v) || v < 0.0 || v > kMaxHeavy)
            throw core::Error(shaderFile.string(), 0,
                              "path tally out of range: slot " + std::to_string(slot) + ", value " +
                                  std::to_string(v));
        // v > 16 is a float with ulp >= 2^-19: v·2^32 is an integer; v² is exact in double and
        // rounded to the nearest 2^-32 (error < 2^-33, in a second moment only)
        m_sum[slot] += static_cast<u128>(v * kFixedOne);
        m_sumSq[slot] += static_cast<u128>(std::nearbyint(v * v * kFixedOne));
    }
}

} // namespace pathtrace::detail
