// GPU slab tracer host side (see gpu_slab.h): uniforms, dispatches, exact readback of the
// fixed-point tallies of shaders/common/pathtrace_tally.glsl.
#include "pathtrace/gpu_slab.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <string>

namespace pathtrace {

namespace {

using detail::i128;
using detail::kFixedOne;
using detail::toDouble;
using detail::u128;
using detail::wordThreshold;

// Must match shaders/pathtrace_slab.comp and common/pathtrace_tally.glsl.
constexpr uint64_t kExtraSlots = 6; // beyond rMax, absorbed, loss+, loss−, truncated (w, count)
constexpr uint64_t kSharedSlots = 512; // PT_SHARED_SLOTS in shaders/pathtrace_slab.comp
constexpr uint64_t kHeavyPerPath = 3;  // exit, absorbed, loss

// Whether workgroup-shared tallies pay on this driver: -1 not measured yet (see
// GpuSlabTracer::measureSharedTallies), else 0 / 1.
std::mutex g_sharedMutex;
int g_sharedPays = -1;

// The program's uniforms, by name (a namespace of their own: each tracer has its table).
namespace slab_uniforms {
enum Uniform {
    uSeed,
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
    uMaxEvents,
    uRouletteWeight,
    uSurviveWeight,
    uWeightGain,
    uSharedTally,
    uCount
};
constexpr const char* kUniformNames[uCount] = {
    "Seed",         "EventBudget",    "SigmaT",        "AbsorbFraction",
    "Analog",       "SurviveAlbedo",  "AlwaysScatter", "G",
    "Eta",          "EntryWeight",    "BinsPerMm",     "Bins",
    "MaxEvents",    "RouletteWeight", "SurviveWeight", "WeightGain",
    "PtSharedTally"};
} // namespace slab_uniforms

} // namespace

GpuSlabTracer::GpuSlabTracer(std::filesystem::path shaderFile)
    : m_shaderFile(std::move(shaderFile)), m_sharedTallies(false),
      m_work(kHeavyPerPath, kMaxPathsPerRound, 1, detail::TallyReads::EndOfRun) {
    reload();
    reset(Medium{}, SlabSettings{});
    measureSharedTallies();
}

void GpuSlabTracer::measureSharedTallies() {
    std::lock_guard lock(g_sharedMutex);
    if (g_sharedPays < 0) {
        // Once per process: MCML's case traced both ways, 4096 paths after a warm-up of 1024,
        // the faster kept. A GPU with parallel workgroups saves the contended global atomics
        // of the hot bins; Mesa llvmpipe runs a group's invocations as coroutines around each
        // barrier() and traces a third slower with them.
        SlabSettings probe;
        probe.bins = 160;
        probe.rMaxMm = 24;
        probe.paths = 5120;
        double ms[2] = {0, 0};
        g_sharedPays = 0;
        try {
            for (int shared = 0; shared < 2; ++shared) {
                setSharedTallies(shared == 1);
                reset(Medium{0.01, 1.0, 0.0, 1.3}, probe);
                step(1024);
                core::Stopwatch clock;
                step(4096);
                ms[shared] = clock.ms();
            }
            g_sharedPays = ms[1] < ms[0] ? 1 : 0;
            core::logInfo("GL slab tracer: workgroup-shared tallies " +
                          std::string(g_sharedPays ? "on" : "off") + " (4096 paths in " +
                          core::formatNumber(ms[1], 3) + " ms with them, " +
                          core::formatNumber(ms[0], 3) + " ms without)");
        } catch (const core::Error& e) { // the shared variant does not build: off
            core::logWarn(std::string("GL slab tracer: workgroup-shared tallies off: ") + e.what());
        }
    }
    try {
        setSharedTallies(g_sharedPays == 1);
    } catch (const core::Error&) {
        m_sharedTallies = false; // the global variant, built above, is the program
    }
    reset(Medium{}, SlabSettings{});
}

GpuSlabTracer::~GpuSlabTracer() = default;

void GpuSlabTracer::reload() {
    using namespace slab_uniforms;
    // the workgroup-shared tallies are compiled in only when on (see gpu_slab.h)
    detail::buildTracerProgram(
        m_shaderFile, m_shader, kUniformNames, m_program, m_loc,
        m_sharedTallies ? "#define PT_SHARED_SLOTS " + std::to_string(kSharedSlots) + "u\n" : "");
    clearSums();
}

void GpuSlabTracer::reset(const Medium& m, const SlabSettings& s) {
    validate(m);
    validate(s);
    if (s.estimator == Estimator::Connections)
        throw core::Error("--gpu", 0,
                          "the GL compute tracer has the analog and implicit estimators only; "
                          "run the connections estimator on the CPU");
    m_medium = m;
    m_settings = s;
    m_work.allocate(static_cast<size_t>(s.bins) + kExtraSlots);
    clearSums();
}

void GpuSlabTracer::clearSums() {
    m_work.clear(static_cast<size_t>(std::max(m_settings.bins, 0)) + kExtraSlots);
    m_seconds = 0;
    m_tally = makeTally(m_settings);
    m_tally.batchSum.clear(); // the GL tracer keeps no batch sums
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
            const uint64_t n = std::min(m_work.maxPathsPerRun(), todo - done);
            runPaths(m_tally.paths, n);
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

void GpuSlabTracer::setSharedTallies(bool on) {
    if (on == m_sharedTallies) return;
    m_sharedTallies = on;
    try {
        reload(); // the other variant of the program; the tally starts over
    } catch (...) {
        m_sharedTallies = !on; // the program that is kept
        throw;
    }
}

bool GpuSlabTracer::sharedTallies() const {
    return m_sharedTallies && uint64_t(m_settings.bins) + kExtraSlots <= kSharedSlots;
}

void GpuSlabTracer::setEventBudget(uint32_t events) {
    m_eventBudget = std::clamp<uint32_t>(events, 1, kMaxEventBudget);
}

void GpuSlabTracer::setMediumUniforms() {
    using namespace slab_uniforms;
    const Medium& m = m_medium;
    const SlabSettings& s = m_settings;
    const GLuint p = m_program.id();
    const auto at = [&](Uniform u) { return m_loc[static_cast<size_t>(u)]; };
    const double sigmaT = m.sigmaA + m.sigmaS;
    const double r = (m.eta - 1.0) / (m.eta + 1.0);
    const Termination& term = s.termination;
    const uint32_t surviveWeight = wordThreshold(term.rouletteSurvival);
    const bool weightRoulette = term.rouletteSurvival < 1.0 && surviveWeight > 0;
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
    glProgramUniform1ui(p, at(uMaxEvents), static_cast<GLuint>(term.maxEvents));
    // p = 1 (or below 2^-32) plays no weight roulette: a threshold no weight goes below
    glProgramUniform1f(p, at(uRouletteWeight),
                       weightRoulette ? static_cast<float>(term.rouletteWeight) : -1.0f);
    glProgramUniform1ui(p, at(uSurviveWeight), surviveWeight);
    glProgramUniform1f(p, at(uWeightGain),
                       weightRoulette ? static_cast<float>(kFixedOne / surviveWeight) : 1.0f);
}

void GpuSlabTracer::runPaths(uint64_t first, uint64_t count) {
    using namespace slab_uniforms;
    const GLuint p = m_program.id();
    const auto at = [&](Uniform u) { return m_loc[static_cast<size_t>(u)]; };
    glProgramUniform1ui(p, at(uEventBudget), m_eventBudget);
    glProgramUniform1i(p, at(uSharedTally), sharedTallies() ? 1 : 0);
    m_work.run(p, first, count, m_shaderFile);
}

void GpuSlabTracer::publish() {
    const size_t bins = static_cast<size_t>(m_settings.bins);
    const std::vector<u128>& sum = m_work.sum();
    const std::vector<u128>& sumSq = m_work.sumSq();
    SlabTally& t = m_tally;
    u128 rd = 0, rdSq = 0;
    for (size_t i = 0; i <= bins; ++i) { // the radial bins and "beyond rMax"
        if (i < bins) {
            t.binSum[i] = toDouble(sum[i]);
            t.binSumSq[i] = toDouble(sumSq[i]);
        }
        rd += sum[i];
        rdSq += sumSq[i];
    }
    t.rdSum = toDouble(rd);
    t.rdSumSq = toDouble(rdSq);
    t.absSum = toDouble(sum[bins + 1]);
    t.absSumSq = toDouble(sumSq[bins + 1]);
    // a path's loss is either positive (slot +2) or negative (slot +3): Σ loss² adds up
    t.rouletteSum = toDouble(static_cast<i128>(sum[bins + 2]) - static_cast<i128>(sum[bins + 3]));
    t.rouletteSumSq = toDouble(sumSq[bins + 2] + sumSq[bins + 3]);
    t.truncSum = toDouble(sum[bins + 4]);
    t.truncSumSq = toDouble(sumSq[bins + 4]);
    t.truncatedPaths = static_cast<uint64_t>(toDouble(sum[bins + 5]) + 0.5);
    const double r = (m_medium.eta - 1.0) / (m_medium.eta + 1.0);
    t.specular = t.paths > 0 ? r * r : 0.0;
    t.events = m_work.events();
}

} // namespace pathtrace
