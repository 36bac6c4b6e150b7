// GPU slab tracer host side (see gpu_slab.h): uniforms, dispatches, exact readback of the
// fixed-point tallies of shaders/common/pathtrace_tally.glsl.
#include "pathtrace/gpu_slab.h"

#include "core/core.h"
#include "pathtrace/gpu_shader.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace pathtrace {

namespace {

using u128 = unsigned __int128;
using i128 = __int128;

// Must match shaders/pathtrace_slab.comp and common/pathtrace_tally.glsl.
constexpr GLuint kAccBinding = 0, kHeavyBinding = 1, kQueueBinding = 2, kInBinding = 3,
                 kOutBinding = 4;
constexpr uint64_t kLocalSize = 64;
constexpr uint64_t kExtraSlots = 4;         // beyond rMax, absorbed, loss+, loss−
constexpr uint64_t kHeavyPerPath = 3;       // exit, absorbed, loss
constexpr uint64_t kSuspendedWords = 20;    // 5 uvec4 per suspended path
constexpr uint64_t kQueueWords = 5;         // next, inTaken, outCount, events lo/hi
constexpr uint64_t kPathsPerInvocation = 4; // invocations launched per path of work
constexpr uint64_t kMaxGroups = 1024;       // at most 65536 invocations per dispatch
constexpr uint64_t kMaxInvocations = kMaxGroups * kLocalSize;
// Paths ending in one dispatch: at most the round's new paths plus the suspended ones.
constexpr uint64_t kHeavyCapacity =
    kHeavyPerPath * (GpuSlabTracer::kMaxPathsPerRound + kMaxInvocations);
constexpr double kFixedOne = 4294967296.0;     // 2^32: the tallies' unit is 2^-32
constexpr double kMaxHeavy = 35184372088832.0; // 2^45: beyond it a square could overflow u128

enum Uniform {
    uSeed,
    uFirstPath,
    uPathCount,
    uInCount,
    uEventBudget,
    uSigmaT,
    uAbsorbFraction,
    uAnalog,
    uSurviveAlbedo,
    uAlwaysScatter,
    uG,
    uEta,
    uEntryWeight,
    uBinsPerMm,
    uBins,
    uRouletteAfter,
    uRouletteWeight,
    uSurviveWeight,
    uWeightGain,
    uCount
};
constexpr const char* kUniformNames[uCount] = {"Seed",
                                               "FirstPath",
                                               "PathCount",
                                               "InCount",
                                               "EventBudget",
                                               "SigmaT",
                                               "AbsorbFraction",
                                               "Analog",
                                               "SurviveAlbedo",
                                               "AlwaysScatter",
                                               "G",
                                               "Eta",
                                               "EntryWeight",
                                               "BinsPerMm",
                                               "Bins",
                                               "RouletteAfter",
                                               "RouletteWeight",
                                               "SurviveWeight",
                                               "WeightGain"};

// p in [0, 1] as a threshold on a uniform 32-bit word: P(word < t) = t / 2^32.
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

} // namespace

GpuSlabTracer::GpuSlabTracer(std::filesystem::path shaderFile)
    : m_shaderFile(std::move(shaderFile)) {
    reload();
    reset(Medium{}, SlabSettings{});
}

GpuSlabTracer::~GpuSlabTracer() = default;

void GpuSlabTracer::reload() {
    GpuShaderSource source = loadGpuShader(m_shaderFile);
    gl::Program program = buildGpuShader(source); // throws core::Error; nothing changed yet
    std::vector<int> loc(uCount);
    for (int i = 0; i < uCount; ++i)
        loc[static_cast<size_t>(i)] = gl::uniformLocation(program, kUniformNames[i]);
    m_program = std::move(program);
    m_loc = std::move(loc);
    clearSums();
}

void GpuSlabTracer::reset(const Medium& m, const SlabSettings& s) {
    validate(m);
    validate(s);
    m_medium = m;
    m_settings = s;
    const size_t slots = static_cast<size_t>(s.bins) + kExtraSlots;
    m_acc = gl::createBuffer(slots * 4 * sizeof(uint32_t), nullptr);
    if (!m_heavy) m_heavy = gl::createBuffer(8 + kHeavyCapacity * 8, nullptr);
    if (!m_queue) m_queue = gl::createBuffer(kQueueWords * sizeof(uint32_t), nullptr);
    for (auto& list : m_suspended)
        if (!list) list = gl::createBuffer(kMaxInvocations * kSuspendedWords * 4, nullptr);
    clearSums();
}

void GpuSlabTracer::clearSums() {
    const size_t slots = static_cast<size_t>(std::max(m_settings.bins, 0)) + kExtraSlots;
    m_sum.assign(slots, 0);
    m_sumSq.assign(slots, 0);
    m_events = 0;
    m_heavyTallies = 0;
    m_seconds = 0;
    m_tally = makeTally(m_settings);
    if (m_acc)
        glClearNamedBufferData(m_acc.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
}

uint64_t GpuSlabTracer::step(uint64_t maxPaths) {
    const uint64_t todo =
        std::min(maxPaths, m_settings.paths - std::min(m_settings.paths, m_tally.paths));
    if (todo == 0) return m_tally.paths;
    core::Stopwatch clock;
    try {
        gl::ScopedStageTimer timer("path tracer (GPU)");
        setMediumUniforms();
        for (uint64_t done = 0; done < todo;) {
            const uint64_t n = std::min(kMaxPathsPerRound, todo - done);
            runRound(m_tally.paths, n);
            m_tally.paths += n;
            done += n;
        }
    } catch (...) {
        clearSums(); // a round cut short leaves sums of a partial path set
        throw;
    }
    publish();
    m_seconds += clock.ms() * 1e-3;
    return m_tally.paths;
}

void GpuSlabTracer::setEventBudget(uint32_t events) {
    m_eventBudget = std::clamp<uint32_t>(events, 1, kMaxEventBudget);
}

void GpuSlabTracer::setMediumUniforms() {
    const Medium& m = m_medium;
    const SlabSettings& s = m_settings;
    const GLuint p = m_program.id();
    const auto at = [&](Uniform u) { return m_loc[static_cast<size_t>(u)]; };
    const double sigmaT = m.sigmaA + m.sigmaS;
    const double r = (m.eta - 1.0) / (m.eta + 1.0);
    const uint32_t surviveWeight = wordThreshold(s.rouletteSurvival);
    const bool weightRoulette = s.rouletteSurvival < 1.0 && surviveWeight > 0;
    glProgramUniform2ui(p, at(uSeed), static_cast<GLuint>(s.seed),
                        static_cast<GLuint>(s.seed >> 32));
    glProgramUniform1f(p, at(uSigmaT), static_cast<float>(sigmaT));
    glProgramUniform1f(p, at(uAbsorbFraction), static_cast<float>(m.sigmaA / sigmaT));
    glProgramUniform1i(p, at(uAnalog), s.estimator == Estimator::Analog ? 1 : 0);
    glProgramUniform1ui(p, at(uSurviveAlbedo), wordThreshold(m.sigmaS / sigmaT));
    glProgramUniform1i(p, at(uAlwaysScatter), m.sigmaA == 0.0 ? 1 : 0);
    glProgramUniform1f(p, at(uG), static_cast<float>(m.g));
    glProgramUniform1f(p, at(uEta), static_cast<float>(m.eta));
    glProgramUniform1f(p, at(uEntryWeight), static_cast<float>(1.0 - r * r));
    glProgramUniform1f(p, at(uBinsPerMm), static_cast<float>(s.bins / s.rMaxMm));
    glProgramUniform1ui(p, at(uBins), static_cast<GLuint>(s.bins));
    glProgramUniform1ui(p, at(uRouletteAfter), static_cast<GLuint>(s.rouletteAfter));
    // p = 1 (or below 2^-32) plays no weight roulette: a threshold no weight goes below
    glProgramUniform1f(p, at(uRouletteWeight),
                       weightRoulette ? static_cast<float>(s.rouletteWeight) : -1.0f);
    glProgramUniform1ui(p, at(uSurviveWeight), surviveWeight);
    glProgramUniform1f(p, at(uWeightGain),
                       weightRoulette ? static_cast<float>(kFixedOne / surviveWeight) : 1.0f);
}

void GpuSlabTracer::runRound(uint64_t first, uint64_t count) {
    const GLuint p = m_program.id();
    const auto at = [&](Uniform u) { return m_loc[static_cast<size_t>(u)]; };
    glProgramUniform2ui(p, at(uFirstPath), static_cast<GLuint>(first),
                        static_cast<GLuint>(first >> 32));
    glProgramUniform1ui(p, at(uPathCount), static_cast<GLuint>(count));
    glProgramUniform1ui(p, at(uEventBudget), m_eventBudget);
    glClearNamedBufferData(m_queue.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    uint64_t taken = 0;   // new paths started so far
    uint32_t inCount = 0; // paths suspended by the previous dispatch
    for (int cur = 0;; cur ^= 1) {
        glProgramUniform1ui(p, at(uInCount), inCount);
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
        const uint64_t perGroup = kLocalSize * kPathsPerInvocation;
        const uint64_t groups =
            std::clamp<uint64_t>(std::max((inCount + kLocalSize - 1) / kLocalSize,
                                          (inCount + (count - taken) + perGroup - 1) / perGroup),
                                 1, kMaxGroups);
        glUseProgram(p);
        glDispatchCompute(static_cast<GLuint>(groups), 1, 1);
        glUseProgram(0);
        // readback and clears below, suspended paths read by the next dispatch
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);

        uint32_t queue[kQueueWords] = {};
        glGetNamedBufferSubData(m_queue.id(), 0, sizeof queue, queue);
        readTallies();
        m_events += (uint64_t(queue[4]) << 32) | queue[3];
        taken = std::min<uint64_t>(queue[0], count);
        if (queue[1] < inCount)
            throw core::Error(m_shaderFile.string(), 0,
                              "suspended paths left behind (" + std::to_string(queue[1]) + " of " +
                                  std::to_string(inCount) + " resumed)");
        inCount = queue[2];
        if (inCount > groups * kLocalSize)
            throw core::Error(m_shaderFile.string(), 0,
                              "suspended-path list overflowed (" + std::to_string(inCount) +
                                  " paths from " + std::to_string(groups * kLocalSize) +
                                  " invocations)");
        if (taken >= count && inCount == 0) return;
    }
}

void GpuSlabTracer::readTallies() {
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
    if (heavyCount > kHeavyCapacity)
        throw core::Error(m_shaderFile.string(), 0,
                          "heavy-weight list overflowed (" + std::to_string(heavyCount) +
                              " entries): the shader tallied more than 3 values per path");
    m_heavyTallies += heavyCount;
    std::vector<uint32_t> heavy(2 * size_t(heavyCount));
    glGetNamedBufferSubData(m_heavy.id(), 8, static_cast<GLsizeiptr>(heavy.size() * 4),
                            heavy.data());
    for (size_t k = 0; k < heavyCount; ++k) {
        const uint32_t slot = heavy[2 * k];
        const double v = std::bit_cast<float>(heavy[2 * k + 1]);
        if (slot >= slots || !std::isfinite(v) || v < 0.0 || v > kMaxHeavy)
            throw core::Error(m_shaderFile.string(), 0,
                              "path tally out of range: slot " + std::to_string(slot) + ", value " +
                                  std::to_string(v));
        // v > 16 is a float with ulp >= 2^-19: v·2^32 is an integer; v² is exact in double and
        // rounded to the nearest 2^-32 (error < 2^-33, in a second moment only)
        m_sum[slot] += static_cast<u128>(v * kFixedOne);
        m_sumSq[slot] += static_cast<u128>(std::nearbyint(v * v * kFixedOne));
    }
}

void GpuSlabTracer::publish() {
    const size_t bins = static_cast<size_t>(m_settings.bins);
    SlabTally& t = m_tally;
    u128 rd = 0, rdSq = 0;
    for (size_t i = 0; i <= bins; ++i) { // the radial bins and "beyond rMax"
        if (i < bins) {
            t.binSum[i] = toDouble(m_sum[i]);
            t.binSumSq[i] = toDouble(m_sumSq[i]);
        }
        rd += m_sum[i];
        rdSq += m_sumSq[i];
    }
    t.rdSum = toDouble(rd);
    t.rdSumSq = toDouble(rdSq);
    t.absSum = toDouble(m_sum[bins + 1]);
    t.absSumSq = toDouble(m_sumSq[bins + 1]);
    // a path's loss is either positive (slot +2) or negative (slot +3): Σ loss² adds up
    t.rouletteSum =
        toDouble(static_cast<i128>(m_sum[bins + 2]) - static_cast<i128>(m_sum[bins + 3]));
    t.rouletteSumSq = toDouble(m_sumSq[bins + 2] + m_sumSq[bins + 3]);
    const double r = (m_medium.eta - 1.0) / (m_medium.eta + 1.0);
    t.specular = t.paths > 0 ? r * r : 0.0;
    t.events = m_events;
}

} // namespace pathtrace
