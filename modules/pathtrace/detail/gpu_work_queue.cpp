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
constexpr uint64_t kSuspendedWords = 20;    // 5 uvec4 per suspended path
constexpr uint64_t kQueueWords = 5;         // next, inTaken, outCount, events lo/hi
constexpr uint64_t kItemsPerInvocation = 4; // invocations launched per item of work
constexpr uint64_t kMaxGroups = 1024;       // at most 65536 invocations per dispatch
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

GpuWorkQueue::GpuWorkQueue(uint64_t heavyPerItem, uint64_t maxItemsPerRound)
    // Items ending in one dispatch: at most the round's new items plus the suspended ones.
    : m_heavyPerItem(heavyPerItem),
      m_heavyCapacity(heavyPerItem * (maxItemsPerRound + kMaxInvocations)) {}

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

void GpuWorkQueue::runRound(GLuint p, int inCountLoc, uint64_t count,
                            const std::filesystem::path& shaderFile) {
    glClearNamedBufferData(m_queue.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    glProgramUniform1ui(p, glGetUniformLocation(p, "PtHeavyCapacity"),
                        static_cast<GLuint>(std::min<uint64_t>(m_heavyCapacity, 0xFFFFFFFFu)));
    uint64_t taken = 0;   // new items started so far
    uint32_t inCount = 0; // paths suspended by the previous dispatch
    for (int cur = 0;; cur ^= 1) {
        glProgramUniform1ui(p, inCountLoc, inCount);
        const uint32_t zeros[4] = {0, 0, 0, 0}; // inTaken, outCount, events (next stays)
        glNamedBufferSubData(m_queue.id(), 4, 16, zeros);
        glNamedBufferSubData(m_heavy.id(), 0, 8, zeros);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAccBinding, m_acc.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kHeavyBinding, m_heavy.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kQueueBinding, m_queue.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kInBinding, m_suspended[cur].id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kOutBinding, m_suspended[cur ^ 1].id());
        // Every invocation takes one piece of work on its first iteration, suspended paths
        // first: at least one invocation per suspended path takes them all (inCount never
        // exceeds the previous dispatch's invocations, so this fits in kMaxGroups).
        const uint64_t perGroup = kLocalSize * kItemsPerInvocation;
        const uint64_t groups =
            std::clamp<uint64_t>(std::max((inCount + kLocalSize - 1) / kLocalSize,
                                          (inCount + (count - taken) + perGroup - 1) / perGroup),
                                 1, kMaxGroups);
        glUseProgram(p);
        glDispatchCompute(static_cast<GLuint>(groups), 1, 1);
        glUseProgram(0);
        // barrier: the tracer's queue, tallies and suspended paths → the readback and clears
        // below and the next dispatch, which reads the suspended paths
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);

        uint32_t queue[kQueueWords] = {};
        glGetNamedBufferSubData(m_queue.id(), 0, sizeof queue, queue);
        readTallies(shaderFile);
        m_events += (uint64_t(queue[4]) << 32) | queue[3];
        taken = std::min<uint64_t>(queue[0], count);
        if (queue[1] < inCount)
            throw core::Error(shaderFile.string(), 0,
                              "suspended paths left behind (" + std::to_string(queue[1]) + " of " +
                                  std::to_string(inCount) + " resumed)");
        inCount = queue[2];
        if (inCount > groups * kLocalSize)
            throw core::Error(shaderFile.string(), 0,
                              "suspended-path list overflowed (" + std::to_string(inCount) +
                                  " paths from " + std::to_string(groups * kLocalSize) +
                                  " invocations)");
        if (taken >= count && inCount == 0) return;
    }
}

void GpuWorkQueue::readTallies(const std::filesystem::path& shaderFile) {
    const size_t slots = m_sum.size();
    std::vector<uint32_t> acc(slots * 4);
    glGetNamedBufferSubData(m_acc.id(), 0, static_cast<GLsizeiptr>(acc.size() * 4), acc.data());
    glClearNamedBufferData(m_acc.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    for (size_t i = 0; i < slots; ++i) {
        m_sum[i] += (u128(acc[4 * i + 1]) << 32) | acc[4 * i];
        m_sumSq[i] += (u128(acc[4 * i + 3]) << 32) | acc[4 * i + 2];
    }
    uint32_t heavyCount = 0;
    glGetNamedBufferSubData(m_heavy.id(), 0, 4, &heavyCount);
    if (heavyCount == 0) return;
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
