// pathtrace/detail/gpu_work_queue (see gpu_work_queue.h): buffers, the suspended-path dispatch
// loop and the exact fixed-point tally readback shared by the GL compute path tracers.
#include "pathtrace/detail/gpu_work_queue.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <atomic>
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
    qRounds,
    qGroups, // (groups, 1, 1, pad): glDispatchComputeIndirect's arguments
    qFirstLo = qGroups + 4,
    qFirstHi,
    qRoundCount,
    qItemsLeft,
    qItemsPerPath,
    qMaxRound,
    kQueueWords
};
constexpr uint64_t kItemsPerInvocation = 4; // invocations launched per item of work
constexpr uint64_t kMaxGroups = 1024;       // at most 65536 invocations per dispatch
// The fold (TallyReads::EveryDispatch with at most g_maxFoldSlots slots): after each dispatch,
// every slot's 64-bit sums (4 words: Σ lo, hi, Σ² lo, hi) are added exactly into 128-bit ones
// (8 words: Σ in 4, Σ² in 4, least significant first) and zeroed, on the GPU. A utility kernel
// of the queue, not a tracer: it has no file of its own to edit.
constexpr GLuint kWideBinding = 7;
std::atomic<uint64_t> g_maxFoldSlots{uint64_t(1) << 20}; // 32 MiB of 128-bit sums
constexpr const char* kFoldSource = R"(#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer PtTally { uint acc[]; };
layout(std430, binding = 7) buffer PtWide { uint wide[]; };
uniform uint Slots;
// wide[w .. w + 3] += (hi, lo), exactly (carries through all four words)
void add128(uint w, uint lo, uint hi) {
    uint a = wide[w];
    uint s = a + lo;
    uint c = s < a ? 1u : 0u;
    wide[w] = s;
    a = wide[w + 1u];
    s = a + hi;
    uint c2 = s < a ? 1u : 0u;
    uint t = s + c;
    c2 += t < s ? 1u : 0u;
    wide[w + 1u] = t;
    a = wide[w + 2u];
    s = a + c2;
    wide[w + 2u] = s;
    wide[w + 3u] += s < a ? 1u : 0u;
}
void main() {
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x; // at most 2^20 / 2^16 passes
    for (uint slot = gl_GlobalInvocationID.x; slot < Slots; slot += stride)
        for (uint m = 0u; m < 2u; ++m) {
            uint w = 4u * slot + 2u * m;
            uint lo = acc[w], hi = acc[w + 1u];
            if ((lo | hi) == 0u) continue;
            add128(8u * slot + 4u * m, lo, hi);
            acc[w] = 0u;
            acc[w + 1u] = 0u;
        }
}
)";

// Dispatches issued between two reads of the queue: 1 after the first dispatch of a run, then
// doubling to this many (a run of many rounds reads the queue a few times; a short one issues
// few surplus dispatches, which have 0 groups and still cost a driver round on llvmpipe).
constexpr int kMaxDispatchBatch = 16;
constexpr double kBatchDeadlineS = 60.0; // see run()
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
                        std::vector<int>& loc, const std::string& defines) {
    // throws core::Error; nothing changed yet
    shader::Extension ext;
    if (!defines.empty())
        ext.afterVersion = [&](shader::Emitter& e) {
            e.text(defines);
            e.line(2, 0); // the template's own line numbers go on after its #version
        };
    gl::Program built =
        shader::build(shader::Sources::forFile(shaderFile),
                      {{GL_COMPUTE_SHADER, shaderFile.filename().string()}}, record, ext);
    std::vector<int> found(names.size());
    for (size_t i = 0; i < names.size(); ++i)
        found[i] = gl::uniformLocation(built, names[i]);
    program = std::move(built);
    loc = std::move(found);
}

GpuWorkQueue::GpuWorkQueue(uint64_t heavyPerItem, uint64_t itemsPerRound, uint64_t itemsPerPath,
                           TallyReads reads)
    : m_heavyPerItem(heavyPerItem), m_itemsPerRound(itemsPerRound), m_itemsPerPath(itemsPerPath),
      m_reads(reads) {
    // Items whose values one read of the heavy list can hold: those ending in one run of
    // rounds (read once per run, also when the tallies are read per dispatch).
    m_heavyCapacity = heavyPerItem * maxPathsPerRun() * itemsPerPath;
}

namespace {
std::atomic<int> g_planning{-1}; // -1: not measured yet, else a Planning
} // namespace

void GpuWorkQueue::setMaxFoldSlots(uint64_t slots) {
    g_maxFoldSlots = slots;
}

void GpuWorkQueue::setPlanning(Planning p) {
    g_planning = static_cast<int>(p);
}

GpuWorkQueue::Planning GpuWorkQueue::planning() {
    if (const int p = g_planning.load(); p >= 0) return static_cast<Planning>(p);
    // Measured once per process: the same small workload (256 groups of a loop of 512
    // iterations that also writes the arguments, as the planner does) dispatched directly and
    // through glDispatchComputeIndirect, four back to back with their barriers, the fastest of
    // three such runs of each. Planning on the GPU saves a readback per dispatch but needs
    // indirect dispatches about as fast as direct ones; a driver that runs them much slower
    // gets the host's planning. (Mesa llvmpipe and zink: equal.)
    const gl::Program busy = gl::buildProgram({{GL_COMPUTE_SHADER, R"(#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Out { float outv[]; };
layout(std430, binding = 1) buffer Args { uint args[3]; };
void main() {
    float x = float(gl_GlobalInvocationID.x);
    for (int i = 0; i < 512; ++i) x = x * 0.999 + 1.0;
    outv[gl_GlobalInvocationID.x] = x;
    if (gl_GlobalInvocationID.x == 0u) args[0] = gl_NumWorkGroups.x; // as the planner does
}
)"}});
    const uint32_t groups[3] = {256, 1, 1};
    const gl::Buffer args = gl::createBuffer(sizeof groups, groups);
    const gl::Buffer out = gl::createBuffer(256 * 64 * sizeof(float), nullptr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, out.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, args.id());
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, args.id());
    glUseProgram(busy.id());
    auto time = [&](bool indirect) {
        double best = 1e30;
        for (int i = 0; i < 4; ++i) {
            glFinish();
            core::Stopwatch clock;
            for (int k = 0; k < 4; ++k) { // back to back, as the tracers issue them
                if (indirect)
                    glDispatchComputeIndirect(0);
                else
                    glDispatchCompute(groups[0], 1, 1);
                glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
            }
            glFinish();
            if (i > 0) best = std::min(best, clock.ms() / 4);
        }
        return best;
    };
    const double directMs = time(false), indirectMs = time(true);
    glUseProgram(0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, 0);
    const Planning p = indirectMs < 1.5 * directMs + 0.2 ? Planning::Gpu : Planning::Host;
    core::logInfo(std::string("GL tracers: dispatches planned on the ") +
                  (p == Planning::Gpu ? "GPU" : "host") + " (a test dispatch " +
                  core::formatNumber(directMs, 3) + " ms direct, " +
                  core::formatNumber(indirectMs, 3) + " ms indirect)");
    g_planning = static_cast<int>(p);
    return p;
}

uint64_t GpuWorkQueue::maxPathsPerRun() const {
    return kRoundsPerRun * (m_itemsPerRound / m_itemsPerPath);
}

void GpuWorkQueue::allocate(size_t slots) {
    m_acc = gl::createBuffer(slots * 4 * sizeof(uint32_t), nullptr);
    m_fold = m_reads == TallyReads::EveryDispatch && slots <= g_maxFoldSlots.load();
    m_wide = m_fold ? gl::createBuffer(slots * 8 * sizeof(uint32_t), nullptr) : gl::Buffer{};
    if (m_fold && !m_foldProgram) {
        m_foldProgram = gl::buildProgram({{GL_COMPUTE_SHADER, kFoldSource}});
        m_foldSlotsLoc = gl::uniformLocation(m_foldProgram, "Slots");
    }
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
    if (m_wide)
        glClearNamedBufferData(m_wide.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
}

void GpuWorkQueue::fold() {
    const uint64_t slots = m_sum.size();
    glProgramUniform1ui(m_foldProgram.id(), m_foldSlotsLoc, static_cast<GLuint>(slots));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAccBinding, m_acc.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kWideBinding, m_wide.id());
    glUseProgram(m_foldProgram.id());
    glDispatchCompute(
        static_cast<GLuint>(std::clamp<uint64_t>((slots + kLocalSize - 1) / kLocalSize, 1, 1024)),
        1, 1);
    glUseProgram(0);
    // barrier: the fold's zeroed 64-bit sums → the tracer's next dispatch, which adds to them;
    // its 128-bit sums → the readback at the end of the run
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

void GpuWorkQueue::run(GLuint p, uint64_t firstPath, uint64_t paths,
                       const std::filesystem::path& shaderFile) {
    if (paths == 0) return;
    if (paths > maxPathsPerRun())
        throw core::Error(shaderFile.string(), 0,
                          "internal: " + std::to_string(paths) + " paths in one run (at most " +
                              std::to_string(maxPathsPerRun()) + ")");
    const bool gpuPlanned = planning() == Planning::Gpu;
    glProgramUniform1ui(p, glGetUniformLocation(p, "PtHeavyCapacity"),
                        static_cast<GLuint>(std::min<uint64_t>(m_heavyCapacity, 0xFFFFFFFFu)));
    // The first round and its first dispatch (no suspended paths, about kItemsPerInvocation
    // items per invocation); every later dispatch and round is planned by the last invocation of
    // the dispatch before (common/pathtrace_queue.glsl).
    const uint64_t items = paths * m_itemsPerPath;
    const uint64_t round = std::min(items, m_itemsPerRound);
    uint32_t queue[kQueueWords] = {};
    const uint64_t perGroup = kLocalSize * kItemsPerInvocation;
    queue[qRounds] = 1;
    queue[qGroups] = static_cast<uint32_t>(
        std::clamp<uint64_t>((round + perGroup - 1) / perGroup, 1, kMaxGroups));
    queue[qGroups + 1] = queue[qGroups + 2] = 1;
    queue[qFirstLo] = static_cast<uint32_t>(firstPath);
    queue[qFirstHi] = static_cast<uint32_t>(firstPath >> 32);
    queue[qRoundCount] = static_cast<uint32_t>(round);
    queue[qItemsLeft] = static_cast<uint32_t>(items - round);
    queue[qItemsPerPath] = static_cast<uint32_t>(m_itemsPerPath);
    queue[qMaxRound] = static_cast<uint32_t>(m_itemsPerRound);
    glNamedBufferSubData(m_queue.id(), 0, sizeof queue, queue);
    const uint32_t zeros[2] = {0, 0};
    glNamedBufferSubData(m_heavy.id(), 0, 8, zeros);
    // tallies read after every dispatch only where they cannot be folded on the GPU
    const bool everyDispatch = m_reads == TallyReads::EveryDispatch && !m_fold;
    for (int cur = 0, batch = 1;; batch = std::min(2 * batch, kMaxDispatchBatch)) {
        if (!gpuPlanned) batch = 1;
        for (int b = 0; b < batch; ++b, cur ^= 1) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kAccBinding, m_acc.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kHeavyBinding, m_heavy.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kQueueBinding, m_queue.id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kInBinding, m_suspended[cur].id());
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kOutBinding, m_suspended[cur ^ 1].id());
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, m_queue.id());
            glUseProgram(p);
            if (gpuPlanned)
                glDispatchComputeIndirect(static_cast<GLintptr>(qGroups * sizeof(uint32_t)));
            else // the planner's group count, read back below after the previous dispatch
                glDispatchCompute(queue[qGroups], 1, 1);
            glUseProgram(0);
            glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
            // barrier: the tracer's queue (with the next dispatch's group count), tallies and
            // suspended paths → the next glDispatchComputeIndirect, the next dispatch, which
            // reads the suspended paths, and the readbacks and clears below
            glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                            GL_BUFFER_UPDATE_BARRIER_BIT);
            if (m_fold) fold();
            if (everyDispatch) readTallies(shaderFile);
        }
        // the batch with a deadline: a hung driver is a message, not a frozen program (each
        // dispatch's work is bounded by its event budget, so a batch takes well under this)
        gl::finishWithin(shaderFile.filename().string() + " (GL path tracer)", kBatchDeadlineS);
        glGetNamedBufferSubData(m_queue.id(), 0, sizeof queue, queue);
        ++m_queueReads;
        if (queue[qFault] != 0)
            throw core::Error(shaderFile.string(), 0,
                              "suspended paths left behind (" + std::to_string(queue[qFaultValue]) +
                                  " of " + std::to_string(queue[qFaultCount]) + " resumed)");
        if (queue[qGroups] == 0) break; // every round is done
    }
    const uint64_t rounds = (items + m_itemsPerRound - 1) / m_itemsPerRound;
    if (queue[qRounds] != rounds || queue[qItemsLeft] != 0)
        throw core::Error(shaderFile.string(), 0,
                          "the queue ran " + std::to_string(queue[qRounds]) + " rounds of " +
                              std::to_string(rounds));
    m_rounds += queue[qRounds];
    m_dispatches += queue[qDispatches];
    m_events += (uint64_t(queue[qEventsHi]) << 32) | queue[qEventsLo];
    if (!everyDispatch) readTallies(shaderFile);
}

void GpuWorkQueue::readTallies(const std::filesystem::path& shaderFile) {
    const size_t slots = m_sum.size();
    ++m_tallyReads;
    if (m_fold) { // the 128-bit sums of the run
        std::vector<uint32_t> w(slots * 8);
        glGetNamedBufferSubData(m_wide.id(), 0, static_cast<GLsizeiptr>(w.size() * 4), w.data());
        glClearNamedBufferData(m_wide.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
        auto wide = [&](size_t k) {
            return (u128(w[k + 3]) << 96) | (u128(w[k + 2]) << 64) | (u128(w[k + 1]) << 32) | w[k];
        };
        for (size_t i = 0; i < slots; ++i) {
            m_sum[i] += wide(8 * i);
            m_sumSq[i] += wide(8 * i + 4);
        }
    } else {
        std::vector<uint32_t> acc(slots * 4);
        glGetNamedBufferSubData(m_acc.id(), 0, static_cast<GLsizeiptr>(acc.size() * 4), acc.data());
        glClearNamedBufferData(m_acc.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
        for (size_t i = 0; i < slots; ++i) {
            m_sum[i] += (u128(acc[4 * i + 1]) << 32) | acc[4 * i];
            m_sumSq[i] += (u128(acc[4 * i + 3]) << 32) | acc[4 * i + 2];
        }
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
