// GPU BSSRDF estimate host side (see gpu_bssrdf.h): settings to uniforms, the radial edges,
// dispatch rounds, and the exact fixed-point sums turned into a BssrdfTally (batch means for the
// connections' bins and cells).
#include "pathtrace/gpu_bssrdf.h"

#include "core/core.h"
#include "core/text.h"
#include "pathtrace/detail/bssrdf_chunk.h"
#include "pathtrace/fresnel.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pathtrace {

namespace {

using detail::ExactSum;
using detail::i128;
using detail::kFixedOne;
using detail::u128;
using detail::wordThreshold;

// Must match shaders/bssrdf_walk.comp.
constexpr uint64_t kWalkExtraSlots = 8; // exit, absorbed, loss±, truncated, truncated paths, D±
constexpr uint64_t kHeavyPerWalk = 8;   // every per-path value a path may tally when it ends
constexpr double kTallyMax = 8.0;       // largest value the scaled walk tallies mid-path
using detail::kRouletteMfp;

// The program's uniforms, by name (a namespace of their own: each tracer has its table).
namespace bssrdf_uniforms {
enum Uniform {
    uSeed,
    uEventBudget,
    uEstimator,
    uOrders,
    uSigmaT,
    uAlbedo,
    uSurviveAlbedo,
    uAlwaysScatter,
    uG,
    uEta,
    uEntryWeight,
    uEntryDir,
    uMaxEvents,
    uRouletteWeight,
    uSurviveWeight,
    uWeightGain,
    uRBins,
    uRSpacing,
    uRGuess0,
    uRGuessScale,
    uThetaSBins,
    uDirCos,
    uDirPhi,
    uBatches,
    uDirBase,
    uExtraBase,
    uTallyScale,
    uRouletteDistance,
    uCount
};
constexpr const char* kUniformNames[uCount] = {"Seed",
                                               "EventBudget",
                                               "Estimator",
                                               "Orders",
                                               "SigmaT",
                                               "Albedo",
                                               "SurviveAlbedo",
                                               "AlwaysScatter",
                                               "G",
                                               "Eta",
                                               "EntryWeight",
                                               "EntryDir",
                                               "MaxEvents",
                                               "RouletteWeight",
                                               "SurviveWeight",
                                               "WeightGain",
                                               "RBins",
                                               "RSpacing",
                                               "RGuess0",
                                               "RGuessScale",
                                               "ThetaSBins",
                                               "DirCos",
                                               "DirPhi",
                                               "Batches",
                                               "DirBase",
                                               "ExtraBase",
                                               "TallyScale",
                                               "RouletteDistance"};
} // namespace bssrdf_uniforms

// The fixed-point sum `units`·2^−fracBits as an exact sum (fracBits in [−32, 127]).
ExactSum exactOf(u128 units, int fracBits) {
    ExactSum s;
    if (fracBits <= 0) {
        s.hi = static_cast<i128>(units << -fracBits);
        return s;
    }
    s.hi = static_cast<i128>(units >> fracBits);
    s.lo = units << (128 - fracBits);
    return s;
}
// A signed one: the two's complement of the 256-bit magnitude when negative.
ExactSum exactOf(i128 units, int fracBits) {
    ExactSum s = exactOf(static_cast<u128>(units < 0 ? -units : units), fracBits);
    if (units < 0) {
        s.lo = ~s.lo + 1;
        s.hi = ~s.hi + (s.lo == 0 ? 1 : 0);
    }
    return s;
}

// Paths of [0, n) with index ≡ b (mod B).
uint64_t batchPaths(uint64_t n, uint64_t b, uint64_t batches) {
    return n > b ? (n - b - 1) / batches + 1 : 0;
}

} // namespace

GpuBssrdfEstimator::GpuBssrdfEstimator(std::filesystem::path shaderFile)
    : m_shaderFile(std::move(shaderFile)),
      m_work(kHeavyPerWalk, kMaxPathsPerRound, 1, detail::TallyReads::EveryDispatch) {
    reload();
    reset(Medium{}, EstimateSettings{});
}

GpuBssrdfEstimator::~GpuBssrdfEstimator() = default;

void GpuBssrdfEstimator::reload() {
    using namespace bssrdf_uniforms;
    detail::buildTracerProgram(m_shaderFile, m_shader, kUniformNames, m_program, m_loc);
    clearSums();
}

void GpuBssrdfEstimator::reset(const Medium& m, const EstimateSettings& s, size_t angleIndex) {
    validate(m);
    validate(s);
    if (angleIndex >= s.thetaIDeg.size())
        throw core::Error("estimate", 0,
                          "angle index " + std::to_string(angleIndex) + " out of range (" +
                              std::to_string(s.thetaIDeg.size()) + " angles)");
    const BssrdfBins& b = s.bins;
    const uint64_t cells = uint64_t(b.spatialBins()) * (b.dirBins() > 1 ? 1 + b.dirBins() : 1);
    uint32_t batches = 1;
    if (s.estimator == BssrdfEstimator::Connections) {
        batches = kMaxBatches;
        while (batches > kMinBatches && cells * batches + kWalkExtraSlots > kMaxSlots)
            batches /= 2;
    }
    if (cells * batches + kWalkExtraSlots > kMaxSlots)
        throw core::Error("bins", 0,
                          core::formatNumber(double(cells)) + " bins and cells x " +
                              std::to_string(batches) +
                              " batches are more tally slots than the GL compute tracer holds (" +
                              std::to_string(kMaxSlots) +
                              "); use fewer cells or run on the CPU (leave out --gpu)");
    // The largest weight of the walk and the tally scale that keeps it at most kTallyMax.
    const double cosI = std::cos(s.thetaIDeg[angleIndex] * std::numbers::pi / 180.0);
    const double w0 = 1.0 - fresnelDielectric(std::max(cosI, 1e-300), m.eta);
    const Termination& term = s.termination;
    const double wMax = s.estimator == BssrdfEstimator::Analog
                            ? w0
                            : std::max(w0, term.rouletteWeight / term.rouletteSurvival);
    int k = 0;
    while (wMax * std::ldexp(1.0, -k) > kTallyMax)
        ++k;
    if (k > 32)
        throw core::Error("termination", 0,
                          "roulette_weight / roulette_survival = " + core::formatNumber(wMax) +
                              " exceeds what the GL compute tracer tallies (2^35); raise "
                              "roulette_survival or run on the CPU");
    m_medium = m;
    m_settings = s;
    m_angle = angleIndex;
    m_batches = batches;
    m_scaleExp = k;
    m_work.allocate(static_cast<size_t>(cells * batches + kWalkExtraSlots));
    std::vector<float> edges;
    for (double e : b.rEdges())
        edges.push_back(static_cast<float>(e));
    m_edges = gl::createBuffer(edges.size() * sizeof(float), edges.data());
    clearSums();
}

void GpuBssrdfEstimator::clearSums() {
    const BssrdfBins& b = m_settings.bins;
    const uint64_t cells = uint64_t(b.spatialBins()) * (b.dirBins() > 1 ? 1 + b.dirBins() : 1);
    m_work.clear(static_cast<size_t>(cells * m_batches + kWalkExtraSlots));
    m_seconds = 0;
    m_tally = makeTally(b);
    m_tally.batchSum.clear(); // the GL walk keeps no batch sums
}

void GpuBssrdfEstimator::setEventBudget(uint32_t iterations) {
    m_eventBudget = std::clamp<uint32_t>(iterations, 1, kMaxEventBudget);
}

void GpuBssrdfEstimator::setUniforms() {
    using namespace bssrdf_uniforms;
    const Medium& m = m_medium;
    const EstimateSettings& s = m_settings;
    const BssrdfBins& b = s.bins;
    const GLuint p = m_program.id();
    const auto at = [&](Uniform u) { return m_loc[static_cast<size_t>(u)]; };
    const double sigmaT = m.sigmaA + m.sigmaS;
    const double albedo = m.sigmaS / sigmaT;
    const double thetaI = s.thetaIDeg[m_angle] * std::numbers::pi / 180.0;
    const double w0 = 1.0 - fresnelDielectric(std::max(std::cos(thetaI), 1e-300), m.eta);
    const double sinT = std::sin(thetaI) / m.eta;
    const Termination& term = s.termination;
    const uint32_t surviveWeight = wordThreshold(term.rouletteSurvival);
    const bool weightRoulette = term.rouletteSurvival < 1.0 && surviveWeight > 0;
    const uint64_t seed = detail::bssrdfStreamSeed(s.seed, m_angle);
    glProgramUniform2ui(p, at(uSeed), static_cast<GLuint>(seed), static_cast<GLuint>(seed >> 32));
    glProgramUniform1i(p, at(uEstimator), static_cast<int>(s.estimator));
    glProgramUniform1i(p, at(uOrders), static_cast<int>(s.orders));
    glProgramUniform1f(p, at(uSigmaT), static_cast<float>(sigmaT));
    glProgramUniform1f(p, at(uAlbedo), static_cast<float>(albedo));
    glProgramUniform1ui(p, at(uSurviveAlbedo), wordThreshold(albedo));
    glProgramUniform1i(p, at(uAlwaysScatter), m.sigmaA == 0.0 ? 1 : 0);
    glProgramUniform1f(p, at(uG), static_cast<float>(m.g));
    glProgramUniform1f(p, at(uEta), static_cast<float>(m.eta));
    glProgramUniform1f(p, at(uEntryWeight), static_cast<float>(w0));
    glProgramUniform3f(p, at(uEntryDir), static_cast<float>(sinT), 0.0f,
                       static_cast<float>(-std::sqrt(std::max(0.0, 1.0 - sinT * sinT))));
    glProgramUniform1ui(p, at(uMaxEvents),
                        static_cast<GLuint>(std::max<uint32_t>(1, term.maxEvents)));
    // p = 1 (or below 2^-32) plays no weight roulette: a threshold no weight goes below
    glProgramUniform1f(p, at(uRouletteWeight),
                       weightRoulette ? static_cast<float>(term.rouletteWeight) : -1.0f);
    glProgramUniform1ui(p, at(uSurviveWeight), surviveWeight);
    glProgramUniform1f(p, at(uWeightGain),
                       weightRoulette ? static_cast<float>(kFixedOne / surviveWeight) : 1.0f);
    // the first guess of a radius's bin (the edges decide)
    const std::vector<double> e = b.rEdges();
    int spacing = 0;
    double guess0 = 0, guessScale = b.rBins / (b.rMaxMm - b.rStartMm);
    if (b.spacing == RadialSpacing::Log && b.rBins > 1) {
        if (b.rStartMm > 0) {
            spacing = 1;
            guess0 = b.rStartMm;
            guessScale = b.rBins / std::log(b.rMaxMm / b.rStartMm);
        } else {
            spacing = 2;
            guess0 = e[1];
            guessScale = (b.rBins - 1) / std::log(b.rMaxMm / e[1]);
        }
    }
    glProgramUniform1ui(p, at(uRBins), static_cast<GLuint>(b.rBins));
    glProgramUniform1i(p, at(uRSpacing), spacing);
    glProgramUniform1f(p, at(uRGuess0), static_cast<float>(guess0));
    glProgramUniform1f(p, at(uRGuessScale), static_cast<float>(guessScale));
    glProgramUniform1ui(p, at(uThetaSBins), static_cast<GLuint>(b.thetaSBins));
    glProgramUniform1ui(p, at(uDirCos), static_cast<GLuint>(b.dirCosBins));
    glProgramUniform1ui(p, at(uDirPhi), static_cast<GLuint>(b.dirPhiBins));
    const uint64_t binSlots = uint64_t(b.spatialBins()) * m_batches;
    const uint64_t dirSlots = b.dirBins() > 1 ? binSlots * uint64_t(b.dirBins()) : 0;
    glProgramUniform1ui(p, at(uBatches), m_batches);
    glProgramUniform1ui(p, at(uDirBase), static_cast<GLuint>(binSlots));
    glProgramUniform1ui(p, at(uExtraBase), static_cast<GLuint>(binSlots + dirSlots));
    glProgramUniform1f(p, at(uTallyScale), static_cast<float>(std::ldexp(1.0, -m_scaleExp)));
    glProgramUniform1f(p, at(uRouletteDistance), static_cast<float>(kRouletteMfp / sigmaT));
    glProgramUniform1ui(p, at(uEventBudget), m_eventBudget);
}

uint64_t GpuBssrdfEstimator::step(uint64_t maxPaths) {
    const uint64_t todo =
        std::min(maxPaths, m_settings.paths - std::min(m_settings.paths, m_tally.paths));
    if (todo == 0) return m_tally.paths;
    core::Stopwatch clock;
    const GLuint p = m_program.id();
    try {
        gl::ScopedStageTimer timer("BSSRDF estimate (GPU)");
        setUniforms();
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, m_edges.id());
        for (uint64_t done = 0; done < todo;) {
            const uint64_t n = std::min(m_work.maxPathsPerRun(), todo - done);
            m_work.run(p, m_tally.paths, n, m_shaderFile);
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

void GpuBssrdfEstimator::publish() {
    const BssrdfBins& b = m_settings.bins;
    const std::vector<u128>& sum = m_work.sum();
    const std::vector<u128>& sumSq = m_work.sumSq();
    const int k = m_scaleExp;
    const int frac = 32 - k, fracSq = 32 - 2 * k; // units 2^-32 of values times 2^-k
    const uint64_t n = m_tally.paths, batches = m_batches;
    BssrdfTally& t = m_tally;
    // One bin or cell: Σ over its batches exactly; Σ² per path (one batch) or from the batch
    // sums (gpu_bssrdf.h).
    auto fill = [&](size_t firstSlot, ExactSum& s, ExactSum& s2) {
        u128 total = 0;
        for (size_t j = 0; j < batches; ++j)
            total += sum[firstSlot + j];
        s = exactOf(total, frac);
        if (batches == 1) {
            s2 = exactOf(sumSq[firstSlot], fracSq);
            return;
        }
        s2 = ExactSum{};
        if (n == 0) return;
        const long double unit = std::ldexp(1.0L, -frac);
        const long double N = static_cast<long double>(n);
        const long double mean = static_cast<long double>(total) * unit / N;
        long double dev = 0, nb2 = 0;
        for (size_t j = 0; j < batches; ++j) {
            const long double nb = static_cast<long double>(batchPaths(n, j, batches));
            const long double d = static_cast<long double>(sum[firstSlot + j]) * unit - nb * mean;
            dev += d * d;
            nb2 += nb * nb;
        }
        const long double denom = N - nb2 / N; // > 0 once two batches hold paths
        const long double var = denom > 0 ? dev / denom : 0;
        s2.add(static_cast<double>(N * mean * mean + (N - 1) * var));
    };
    const size_t nS = static_cast<size_t>(b.spatialBins()), nD = static_cast<size_t>(b.dirBins());
    for (size_t i = 0; i < nS; ++i)
        fill(i * batches, t.binSum[i], t.binSumSq[i]);
    const size_t dirBase = nS * batches;
    for (size_t i = 0; i < t.dirSum.size(); ++i)
        fill(dirBase + i * batches, t.dirSum[i], t.dirSumSq[i]);
    const size_t x = dirBase + (nD > 1 ? nS * nD * batches : 0);
    auto moments = [&](size_t slot, ExactSum& s, ExactSum& s2) {
        s = exactOf(sum[slot], frac);
        s2 = exactOf(sumSq[slot], fracSq);
    };
    moments(x, t.exitSum, t.exitSumSq);
    moments(x + 1, t.absSum, t.absSumSq);
    moments(x + 4, t.truncSum, t.truncSumSq);
    // a path's roulette loss (and its gap D) is either positive or negative: Σ² adds up
    t.rouletteSum = exactOf(static_cast<i128>(sum[x + 2]) - static_cast<i128>(sum[x + 3]), frac);
    t.rouletteSumSq = exactOf(sumSq[x + 2] + sumSq[x + 3], fracSq);
    t.energySum = exactOf(static_cast<i128>(sum[x + 6]) - static_cast<i128>(sum[x + 7]), frac);
    t.energySumSq = exactOf(sumSq[x + 6] + sumSq[x + 7], fracSq);
    t.truncatedPaths = static_cast<uint64_t>(sum[x + 5] >> 32); // 1 per path, unscaled
    t.events = exactOf(static_cast<u128>(m_work.events()), 0);
}

BssrdfTable estimateTableGpu(GpuBssrdfEstimator& gpu, const Medium& m, const EstimateSettings& s,
                             const std::function<void(uint64_t)>& progress,
                             const std::atomic<bool>* cancel) {
    validate(m);
    validate(s);
    BssrdfTable t;
    t.medium = m;
    t.settings = s;
    t.settings.splitting.levels = 0; // the GL walk does not split: the table says what it traced
    t.settings.exits.samples = 0;    // and tallies the actual exits
    t.chunks = {{0, chunkCount(s)}};
    uint64_t before = 0;
    bool stopped = false;
    for (size_t a = 0; a < s.thetaIDeg.size() && !stopped; ++a) {
        gpu.reset(m, s, a);
        // one chunk per step: a cancelled run keeps a prefix of whole chunks, and stops within
        // one chunk's time
        while (!gpu.finished()) {
            if (cancel && cancel->load()) {
                stopped = true;
                break;
            }
            gpu.step(kChunkPaths);
            if (progress) progress(before + gpu.pathsDone());
        }
        t.tallies.push_back(gpu.tally());
        before += gpu.pathsDone();
    }
    if (stopped) {
        if (t.tallies.size() != 1 || s.thetaIDeg.size() != 1)
            throw core::Error("estimate", 0,
                              "interrupted while tracing theta_i " +
                                  core::formatNumber(s.thetaIDeg[t.tallies.size() - 1]) +
                                  ": no consistent partial table (angles are traced one after "
                                  "another)");
        const uint64_t paths = t.tallies.front().paths;
        if (paths < s.paths) t.chunks = {{0, paths / kChunkPaths}};
    }
    return t;
}

} // namespace pathtrace
