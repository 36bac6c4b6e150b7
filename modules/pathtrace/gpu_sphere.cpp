// GPU lit-sphere tracer host side (see gpu_sphere.h): uniforms, dispatches, exact readback of
// the fixed-point tallies of shaders/common/pathtrace_tally.glsl, the image.
#include "pathtrace/gpu_sphere.h"

#include "core/core.h"
#include "pathtrace/detail/mean_stderr.h"
#include "pathtrace/sphere_tracer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace pathtrace {
using detail::meanStderr;

namespace {

using detail::kFixedOne;
using detail::toDouble;
using detail::wordThreshold;

// Must match shaders/pathtrace_sphere.comp and common/pathtrace_tally.glsl.
constexpr uint64_t kHeavyPerItem = 2; // pixel, exited
constexpr uint64_t kMaxItemsPerRound = 3 * GpuSphereTracer::kMaxPathsPerRound;

// The program's uniforms, by name (a namespace of their own: each tracer has its table).
namespace sphere_uniforms {
enum Uniform {
    uSeed,
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
    uMaxEvents,
    uRouletteWeight,
    uSurviveWeight,
    uWeightGain,
    uCount
};
constexpr const char* kUniformNames[uCount] = {
    "Seed",      "EventBudget", "SigmaT",         "AbsorbFraction",
    "G",         "Eta",         "Radius",         "Light",
    "E1",        "E2",          "Extent",         "PixelSize",
    "ImageSize", "MaxEvents",   "RouletteWeight", "SurviveWeight",
    "WeightGain"};
} // namespace sphere_uniforms

} // namespace

GpuSphereTracer::GpuSphereTracer(std::filesystem::path shaderFile)
    : m_shaderFile(std::move(shaderFile)),
      m_work(kHeavyPerItem, kMaxItemsPerRound, 3, detail::TallyReads::EndOfRun) {
    reload();
    reset(m_media, LitSphereSetup{});
}

GpuSphereTracer::~GpuSphereTracer() = default;

void GpuSphereTracer::reload() {
    using namespace sphere_uniforms;
    detail::buildTracerProgram(m_shaderFile, m_shader, kUniformNames, m_program, m_loc);
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
    // the tallies: 3 slots of 16 bytes a pixel and two more (gpu_work_queue.cpp)
    gl::requireStorageBlock(48 * (uint64_t(setup.width) * uint64_t(setup.height) + 2),
                            "lit sphere setup", "pixels", 48);
    PixelGeometry pixels = sphereFootprints(setup);
    m_media = media;
    m_setup = setup;
    m_options = options;
    m_target = target;
    m_pixels = std::move(pixels);
    m_work.allocate(3 * (m_pixels.footprint.size() + 2));
    clearSums();
}

void GpuSphereTracer::clearSums() {
    m_work.clear(3 * (m_pixels.footprint.size() + 2));
    m_paths = 0;
    m_seconds = 0;
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
            const uint64_t n = std::min(m_work.maxPathsPerRun(), todo - done);
            runPaths(m_paths, n);
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
    using namespace sphere_uniforms;
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
    const Termination& term = m_options.termination;
    const uint32_t surviveWeight = wordThreshold(term.rouletteSurvival);
    const bool weightRoulette = term.rouletteSurvival < 1.0 && surviveWeight > 0;
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
    glProgramUniform1ui(p, at(uMaxEvents), static_cast<GLuint>(term.maxEvents));
    glProgramUniform1f(p, at(uRouletteWeight), weightRoulette ? f(term.rouletteWeight) : -1.0f);
    glProgramUniform1ui(p, at(uSurviveWeight), surviveWeight);
    glProgramUniform1f(p, at(uWeightGain), weightRoulette ? f(kFixedOne / surviveWeight) : 1.0f);
}

void GpuSphereTracer::runPaths(uint64_t first, uint64_t paths) {
    using namespace sphere_uniforms;
    const GLuint p = m_program.id();
    const auto at = [&](Uniform u) { return m_loc[static_cast<size_t>(u)]; };
    glProgramUniform1ui(p, at(uEventBudget), m_eventBudget);
    // work items: every channel of every path
    m_work.run(p, first, paths, m_shaderFile);
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
        const size_t base = c * (n + 2);
        for (size_t p = 0; p < n; ++p) {
            const double area = m_pixels.footprint[p];
            if (!(area > 0)) continue; // centre ray misses: 0, variance 0
            double mean, err;
            meanStderr(toDouble(m_work.sum()[base + p]), toDouble(m_work.sumSq()[base + p]),
                       m_paths, source / area, mean, err);
            img.mean[3 * p + c] = static_cast<float>(mean);
            img.variance[3 * p + c] = static_cast<float>(err * err);
        }
    }
    return img;
}

std::array<double, 3> GpuSphereTracer::slotPower(size_t offset,
                                                 std::array<double, 3>* stderrOut) const {
    const size_t n = m_pixels.footprint.size();
    const double R = m_setup.radiusMm;
    std::array<double, 3> power{};
    for (size_t c = 0; c < 3; ++c) {
        const size_t slot = c * (n + 2) + n + offset;
        double mean, err;
        meanStderr(toDouble(m_work.sum()[slot]), toDouble(m_work.sumSq()[slot]), m_paths,
                   std::numbers::pi * R * R, mean, err);
        power[c] = mean;
        if (stderrOut) (*stderrOut)[c] = err;
    }
    return power;
}

std::array<double, 3> GpuSphereTracer::exitedPower(std::array<double, 3>* stderrOut) const {
    return slotPower(0, stderrOut);
}

std::array<double, 3> GpuSphereTracer::truncatedPower(std::array<double, 3>* stderrOut) const {
    return slotPower(1, stderrOut);
}

} // namespace pathtrace
