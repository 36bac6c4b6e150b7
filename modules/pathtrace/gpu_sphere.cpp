// GPU lit-sphere tracer host side (see gpu_sphere.h): uniforms, dispatches, exact readback of
// the fixed-point tallies of shaders/common/pathtrace_tally.glsl, the image.
#include "pathtrace/gpu_sphere.h"

#include "core/core.h"
#include "pathtrace/gpu_shader.h"
#include "pathtrace/sphere_tracer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace pathtrace {

namespace {

using u128 = unsigned __int128;

// Must match shaders/pathtrace_sphere.comp and common/pathtrace_tally.glsl.
constexpr GLuint kAccBinding = 0, kHeavyBinding = 1, kQueueBinding = 2, kInBinding = 3,
                 kOutBinding = 4;
constexpr uint64_t kLocalSize = 64;
constexpr uint64_t kHeavyPerItem = 2;       // pixel, exited
constexpr uint64_t kSuspendedWords = 20;    // 5 uvec4 per suspended path
constexpr uint64_t kQueueWords = 5;         // next, inTaken, outCount, events lo/hi
constexpr uint64_t kItemsPerInvocation = 4; // invocations launched per item of work
constexpr uint64_t kMaxGroups = 1024;       // at most 65536 invocations per dispatch
constexpr uint64_t kMaxInvocations = kMaxGroups * kLocalSize;
constexpr uint64_t kMaxItemsPerRound = 3 * GpuSphereTracer::kMaxPathsPerRound;
// Items ending in one dispatch: at most the round's new items plus the suspended ones.
constexpr uint64_t kHeavyCapacity = kHeavyPerItem * (kMaxItemsPerRound + kMaxInvocations);
constexpr double kFixedOne = 4294967296.0;     // 2^32: the tallies' unit is 2^-32
constexpr double kMaxHeavy = 35184372088832.0; // 2^45: beyond it a square could overflow u128

enum Uniform {
    uSeed,
    uFirstPath,
    uItemCount,
    uInCount,
    uEventBudget,
    uSigmaT,
    uAbsorbFraction,
    uG,
    uEta,
    uRadius,
    uLight,
    uE1,
    uE2,
    uExtent,
    uPixelSize,
    uImageSize,
    uRouletteAfter,
    uRouletteWeight,
    uSurviveWeight,
    uWeightGain,
    uCount
};
constexpr const char* kUniformNames[uCount] = {"Seed",
                                               "FirstPath",
                                               "ItemCount",
                                               "InCount",
                                               "EventBudget",
                                               "SigmaT",
                                               "AbsorbFraction",
                                               "G",
                                               "Eta",
                                               "Radius",
                                               "Light",
                                               "E1",
                                               "E2",
                                               "Extent",
                                               "PixelSize",
                                               "ImageSize",
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

// Mean and standard error of the mean of scale·x from Σx, Σx² over n samples.
void meanStderr(double sum, double sumSq, uint64_t n, double scale, double& mean, double& err) {
    if (n == 0) {
        mean = 0;
        err = std::numeric_limits<double>::infinity();
        return;
    }
    const double N = static_cast<double>(n);
    const double m = sum / N;
    mean = scale * m;
    if (n < 2) {
        err = sum == 0 && sumSq == 0 ? 0 : std::numeric_limits<double>::infinity();
        return;
    }
    const double var = std::max(0.0, sumSq / N - m * m) / (N - 1.0);
    err = std::fabs(scale) * std::sqrt(var);
}

} // namespace

GpuSphereTracer::GpuSphereTracer(std::filesystem::path shaderFile)
    : m_shaderFile(std::move(shaderFile)) {
    reload();
    reset(m_media, LitSphereSetup{});
}

GpuSphereTracer::~GpuSphereTracer() = default;

void GpuSphereTracer::reload() {
    GpuShaderSource source = loadGpuShader(m_shaderFile);
    gl::Program program = buildGpuShader(source); // throws core::Error; nothing changed yet
    std::vector<int> loc(uCount);
    for (int i = 0; i < uCount; ++i)
        loc[static_cast<size_t>(i)] = gl::uniformLocation(program, kUniformNames[i]);
    m_program = std::move(program);
    m_loc = std::move(loc);
    clearSums();
}

void GpuSphereTracer::reset(const std::array<Medium, 3>& media, const LitSphereSetup& setup,
                            const TraceOptions& options) {
    static const char* names[3] = {"medium (red)", "medium (green)", "medium (blue)"};
    for (size_t c = 0; c < 3; ++c)
        validate(media[c], names[c]);
    validate(setup);
    validate(options);
    const uint64_t target = litSpherePaths(setup);
    PixelGeometry pixels = sphereFootprints(setup);
    m_media = media;
    m_setup = setup;
    m_options = options;
    m_target = target;
    m_pixels = std::move(pixels);
    const size_t slots = 3 * (m_pixels.footprint.size() + 1);
    m_acc = gl::createBuffer(slots * 4 * sizeof(uint32_t), nullptr);
    if (!m_heavy) m_heavy = gl::createBuffer(8 + kHeavyCapacity * 8, nullptr);
    if (!m_queue) m_queue = gl::createBuffer(kQueueWords * sizeof(uint32_t), nullptr);
    for (auto& list : m_suspended)
        if (!list) list = gl::createBuffer(kMaxInvocations * kSuspendedWords * 4, nullptr);
    clearSums();
}

void GpuSphereTracer::clearSums() {
    const size_t slots = 3 * (m_pixels.footprint.size() + 1);
    m_sum.assign(slots, 0);
    m_sumSq.assign(slots, 0);
    m_paths = 0;
    m_events = 0;
    m_seconds = 0;
    if (m_acc)
        glClearNamedBufferData(m_acc.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
}

void GpuSphereTracer::setEventBudget(uint32_t events) {
    m_eventBudget = std::clamp<uint32_t>(events, 1, kMaxEventBudget);
}

uint64_t GpuSphereTracer::step(uint64_t maxPathsPerChannel) {
    const uint64_t todo = std::min(maxPathsPerChannel, m_target - std::min(m_target, m_paths));
    if (todo == 0) return m_paths;
    core::Stopwatch clock;
    try {
        gl::ScopedStageTimer timer("lit sphere path tracer (GPU)");
        setUniforms();
        for (uint64_t done = 0; done < todo;) {
            const uint64_t n = std::min(kMaxPathsPerRound, todo - done);
            runRound(m_paths, n);
            m_paths += n;
            done += n;
        }
    } catch (...) {
        clearSums(); // a round cut short leaves sums of a partial path set
        throw;
    }
    m_seconds += clock.ms() * 1e-3;
    return m_paths;
}

void GpuSphereTracer::setUniforms() {
    const GLuint p = m_program.id();
    const auto at = [&](Uniform u) { return m_loc[static_cast<size_t>(u)]; };
    float sigmaT[3], absorb[3], g[3], eta[3];
    for (size_t c = 0; c < 3; ++c) {
        const Medium& m = m_media[c];
        const double st = m.sigmaA + m.sigmaS;
        sigmaT[c] = static_cast<float>(st);
        absorb[c] = static_cast<float>(m.sigmaA / st);
        g[c] = static_cast<float>(m.g);
        eta[c] = static_cast<float>(m.eta);
    }
    const LitSphereSetup& s = m_setup;
    const auto l = unitLight(s);
    // The frame of the plane perpendicular to the light, as traceLitSphere builds it.
    const double helper[3] = {std::fabs(l[0]) < 0.9 ? 1.0 : 0.0, std::fabs(l[0]) < 0.9 ? 0.0 : 1.0,
                              0.0};
    const double k = helper[0] * l[0] + helper[1] * l[1] + helper[2] * l[2];
    double e1[3] = {helper[0] - k * l[0], helper[1] - k * l[1], helper[2] - k * l[2]};
    const double len = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    for (double& v : e1)
        v /= len;
    const double e2[3] = {l[1] * e1[2] - l[2] * e1[1], l[2] * e1[0] - l[0] * e1[2],
                          l[0] * e1[1] - l[1] * e1[0]};
    const OrthoCamera cam(s, s.radiusMm);
    const uint32_t surviveWeight = wordThreshold(m_options.rouletteSurvival);
    const bool weightRoulette = m_options.rouletteSurvival < 1.0 && surviveWeight > 0;
    const auto f = [](double v) { return static_cast<float>(v); };
    glProgramUniform2ui(p, at(uSeed), static_cast<GLuint>(s.seed),
                        static_cast<GLuint>(s.seed >> 32));
    glProgramUniform3f(p, at(uSigmaT), sigmaT[0], sigmaT[1], sigmaT[2]);
    glProgramUniform3f(p, at(uAbsorbFraction), absorb[0], absorb[1], absorb[2]);
    glProgramUniform3f(p, at(uG), g[0], g[1], g[2]);
    glProgramUniform3f(p, at(uEta), eta[0], eta[1], eta[2]);
    glProgramUniform1f(p, at(uRadius), f(s.radiusMm));
    glProgramUniform3f(p, at(uLight), f(l[0]), f(l[1]), f(l[2]));
    glProgramUniform3f(p, at(uE1), f(e1[0]), f(e1[1]), f(e1[2]));
    glProgramUniform3f(p, at(uE2), f(e2[0]), f(e2[1]), f(e2[2]));
    glProgramUniform1f(p, at(uExtent), f(cam.extent));
    glProgramUniform2f(p, at(uPixelSize), f(cam.dx), f(cam.dy));
    glProgramUniform2ui(p, at(uImageSize), static_cast<GLuint>(s.width),
                        static_cast<GLuint>(s.height));
    glProgramUniform1ui(p, at(uRouletteAfter), static_cast<GLuint>(m_options.rouletteAfter));
    glProgramUniform1f(p, at(uRouletteWeight),
                       weightRoulette ? f(m_options.rouletteWeight) : -1.0f);
    glProgramUniform1ui(p, at(uSurviveWeight), surviveWeight);
    glProgramUniform1f(p, at(uWeightGain), weightRoulette ? f(kFixedOne / surviveWeight) : 1.0f);
}

void GpuSphereTracer::runRound(uint64_t first, uint64_t paths) {
    const GLuint p = m_program.id();
    const auto at = [&](Uniform u) { return m_loc[static_cast<size_t>(u)]; };
    const uint64_t count = 3 * paths; // work items: every channel of every path
    glProgramUniform2ui(p, at(uFirstPath), static_cast<GLuint>(first),
                        static_cast<GLuint>(first >> 32));
    glProgramUniform1ui(p, at(uItemCount), static_cast<GLuint>(count));
    glProgramUniform1ui(p, at(uEventBudget), m_eventBudget);
    glClearNamedBufferData(m_queue.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, nullptr);
    uint64_t taken = 0;   // new items started so far
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
        // suspended paths first: at least one invocation per suspended path
        const uint64_t perGroup = kLocalSize * kItemsPerInvocation;
        const uint64_t groups =
            std::clamp<uint64_t>(std::max((inCount + kLocalSize - 1) / kLocalSize,
                                          (inCount + (count - taken) + perGroup - 1) / perGroup),
                                 1, kMaxGroups);
        glUseProgram(p);
        glDispatchCompute(static_cast<GLuint>(groups), 1, 1);
        glUseProgram(0);
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

void GpuSphereTracer::readTallies() {
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
                              " entries): the shader tallied more than 2 values per path");
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
        // v > 16 is a float with ulp >= 2^-19: v·2^32 is an integer (see gpu_slab.cpp)
        m_sum[slot] += static_cast<u128>(v * kFixedOne);
        m_sumSq[slot] += static_cast<u128>(std::nearbyint(v * v * kFixedOne));
    }
}

Image GpuSphereTracer::image() const {
    Image img;
    img.width = m_setup.width;
    img.height = m_setup.height;
    img.samples = m_paths;
    const size_t n = m_pixels.footprint.size();
    img.mean.assign(3 * n, 0.0f);
    img.variance.assign(3 * n, 0.0f);
    const double R = m_setup.radiusMm;
    const double source = std::numbers::pi * R * R;
    for (size_t c = 0; c < 3; ++c) {
        const size_t base = c * (n + 1);
        for (size_t p = 0; p < n; ++p) {
            const double area = m_pixels.footprint[p];
            if (!(area > 0)) continue; // centre ray misses: 0, variance 0
            double mean, err;
            meanStderr(toDouble(m_sum[base + p]), toDouble(m_sumSq[base + p]), m_paths,
                       source / area, mean, err);
            img.mean[3 * p + c] = static_cast<float>(mean);
            img.variance[3 * p + c] = static_cast<float>(err * err);
        }
    }
    return img;
}

std::array<double, 3> GpuSphereTracer::exitedPower(std::array<double, 3>* stderrOut) const {
    const size_t n = m_pixels.footprint.size();
    const double R = m_setup.radiusMm;
    std::array<double, 3> power{};
    for (size_t c = 0; c < 3; ++c) {
        const size_t slot = c * (n + 1) + n;
        double mean, err;
        meanStderr(toDouble(m_sum[slot]), toDouble(m_sumSq[slot]), m_paths,
                   std::numbers::pi * R * R, mean, err);
        power[c] = mean;
        if (stderrOut) (*stderrOut)[c] = err;
    }
    return power;
}

} // namespace pathtrace
