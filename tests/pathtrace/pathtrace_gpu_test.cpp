// GPU slab tracer (shaders/pathtrace_slab.comp) on a headless context:
//   - its building blocks against references: Philox4x32-10 known answers (Random123), HG
//     sampling (chi-square against the CDF), the direction frame, Fresnel against fresnel.h;
//   - the whole tracer against an independent closed form (Chandrasekhar's total reflectance
//     of a half-space, index matched, isotropic scattering) and against the CPU tracer bin by
//     bin (z-scores with a Bonferroni correction);
//   - exactness: the per-path accounting identity summed over all paths (no path lost, also
//     past llvmpipe's 65535-iteration loop limit and through heavy weights), bitwise
//     determinism for any step sizes and event budgets;
//   - hot reload: a broken shader names its file and line and the old program keeps working.
#include "../support/gl_fixture.h"
#include "core/statistics.h"
#include "pathtrace/fresnel.h"
#include "pathtrace/gpu_slab.h"
#include "pathtrace/pathtrace.h"
#include "pathtrace/sampling.h"
#include "shader/program.h"
#include "stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using pathtrace::GpuSlabTracer;
using pathtrace::Medium;
using pathtrace::SlabSettings;
using pathtrace::SlabTally;

fs::path slabShader() {
    return testsupport::sourceRoot() / "shaders/pathtrace_slab.comp";
}

// A throwaway copy of shaders/ (for edits and test shaders).
fs::path shaderRoot(const std::string& tag) {
    const fs::path root =
        fs::temp_directory_path() / ("bw_ptgpu_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    testsupport::removeAtExit(root);
    fs::copy(testsupport::sourceRoot() / "shaders", root / "shaders", fs::copy_options::recursive);
    return root;
}

void writeText(const fs::path& p, const std::string& text) {
    std::ofstream out(p, std::ios::binary);
    out << text;
}

// Runs a one-workgroup test shader over a uint buffer (in and out) and returns the buffer.
std::vector<uint32_t> runTestShader(const fs::path& file, std::vector<uint32_t> data,
                                    GLuint groups = 1) {
    shader::Record record;
    gl::Program prog = shader::build(shader::Sources::forFile(file),
                                     {{GL_COMPUTE_SHADER, file.filename().string()}}, record);
    gl::Buffer buf = gl::createBuffer(data.size() * 4, data.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf.id());
    glUseProgram(prog.id());
    glDispatchCompute(groups, 1, 1);
    glUseProgram(0);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(buf.id(), 0, static_cast<GLsizeiptr>(data.size() * 4), data.data());
    return data;
}

using core::normalUpperQuantile;

// Σ over all paths of (reflected + absorbed + roulette loss + specular) minus the path count:
// zero up to float rounding per path when no weight went missing.
double accountingError(const SlabTally& t) {
    const double n = static_cast<double>(t.paths);
    return (t.rdSum + t.absSum + t.truncSum + t.rouletteSum + n * t.specular - n) / n;
}

bool bitwiseEqual(const SlabTally& a, const SlabTally& b) {
    return a.paths == b.paths && a.binSum == b.binSum && a.binSumSq == b.binSumSq &&
           a.rdSum == b.rdSum && a.rdSumSq == b.rdSumSq && a.absSum == b.absSum &&
           a.absSumSq == b.absSumSq && a.rouletteSum == b.rouletteSum && a.truncSum == b.truncSum &&
           a.truncatedPaths == b.truncatedPaths && a.rouletteSumSq == b.rouletteSumSq &&
           a.specular == b.specular && a.events == b.events;
}

SlabTally traceGpu(const Medium& m, const SlabSettings& s, uint64_t stepSize = 0,
                   uint32_t budget = GpuSlabTracer::kDefaultEventBudget) {
    GpuSlabTracer tracer(slabShader());
    tracer.setEventBudget(budget);
    tracer.reset(m, s);
    while (!tracer.finished())
        tracer.step(stepSize ? stepSize : s.paths);
    return tracer.tally();
}

} // namespace

// ---- building blocks ------------------------------------------------------------------------

TEST(PathtraceGpu, PhiloxMatchesRandom123KnownAnswers) {
    testsupport::context();
    const fs::path root = shaderRoot("philox");
    const fs::path file = root / "shaders/philox_test.comp";
    writeText(file, "#version 450\nlayout(local_size_x = 1) in;\n"
                    "#include \"common/pathtrace_rng.glsl\"\n"
                    "layout(std430, binding = 0) buffer B { uvec4 io[]; };\n"
                    "void main() { for (int i = 0; i < 3; ++i)\n"
                    "    io[3 * i + 2] = philox4x32_10(io[3 * i], io[3 * i + 1].xy); }\n");
    // Random123 kat_vectors, philox4x32 10: counter[4] key[2] -> output[4]
    const uint32_t kat[3][10] = {
        {0, 0, 0, 0, 0, 0, 0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8},
        {~0u, ~0u, ~0u, ~0u, ~0u, ~0u, 0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd},
        {0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344, 0xa4093822, 0x299f31d0, 0xd16cfe09,
         0x94fdcceb, 0x5001e420, 0x24126ea1}};
    std::vector<uint32_t> io(36, 0);
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 6; ++k)
            io[12 * i + k] = kat[i][k];
    io = runTestShader(file, io);
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 4; ++k)
            EXPECT_EQ(io[12 * i + 8 + k], kat[i][6 + k]) << "vector " << i << " word " << k;
    fs::remove_all(root);
}

TEST(PathtraceGpu, HgSamplingChiSquare) {
    testsupport::context();
    const fs::path root = shaderRoot("hg");
    const fs::path file = root / "shaders/hg_test.comp";
    // 64 invocations × 16384 samples of cos θ into 100 bins over [-1, 1]; io[0] holds g
    writeText(file, "#version 450\nlayout(local_size_x = 64) in;\n"
                    "#include \"common/pathtrace_rng.glsl\"\n"
                    "#include \"common/pathtrace_scatter.glsl\"\n"
                    "layout(std430, binding = 0) buffer B { uint io[]; };\n"
                    "void main() {\n"
                    "    float g = uintBitsToFloat(io[0]);\n"
                    "    Rng r = rngInit(uvec2(7u, 0u), uvec2(gl_LocalInvocationIndex, 0u), 1u);\n"
                    "    for (int i = 0; i < 16384; ++i) {\n"
                    "        float c = sampleHgCos(g, rngUniform(r));\n"
                    "        atomicAdd(io[1 + min(uint((c + 1.0) * 50.0), 99u)], 1u);\n"
                    "    }\n"
                    "}\n");
    const double n = 64.0 * 16384.0;
    for (float g : {0.0f, 0.5f, -0.7f, 0.95f, 1e-4f}) {
        std::vector<uint32_t> io(101, 0);
        std::memcpy(io.data(), &g, 4);
        io = runTestShader(file, io);
        std::vector<double> observed(100), expected(100);
        for (int b = 0; b < 100; ++b) {
            observed[b] = io[1 + b];
            expected[b] = n * (pathtrace::hgCdfCos(g, -1.0 + 0.02 * (b + 1)) -
                               pathtrace::hgCdfCos(g, -1.0 + 0.02 * b));
        }
        const pttest::ChiSquare chi = pttest::chiSquare(observed, expected);
        EXPECT_GT(chi.pValue, 1e-3 / 5) << "g " << g << " chi2 " << chi.stat << " dof " << chi.dof;
    }
    fs::remove_all(root);
}

TEST(PathtraceGpu, DeflectKeepsUnitLengthAndPolarAngle) {
    testsupport::context();
    const fs::path root = shaderRoot("frame");
    const fs::path file = root / "shaders/frame_test.comp";
    // per invocation: a direction (incl. ±z exactly), a cos θ and φ; out: |d'| − 1, d'·d − cos θ
    writeText(file,
              "#version 450\nlayout(local_size_x = 64) in;\n"
              "#include \"common/pathtrace_rng.glsl\"\n"
              "#include \"common/pathtrace_scatter.glsl\"\n"
              "layout(std430, binding = 0) buffer B { float io[]; };\n"
              "void main() {\n"
              "    uint i = gl_LocalInvocationIndex;\n"
              "    Rng r = rngInit(uvec2(3u, 0u), uvec2(i, 0u), 2u);\n"
              "    vec3 d = i == 0u ? vec3(0, 0, 1) : i == 1u ? vec3(0, 0, -1)\n"
              "        : normalize(vec3(rngUniform(r), rngUniform(r), rngUniform(r)) - 0.5);\n"
              "    float c = 2.0 * rngUniform(r) - 1.0;\n"
              "    vec3 e = deflect(d, c, 2.0 * PT_PI * rngUniform(r));\n"
              "    io[2u * i] = length(e) - 1.0;\n"
              "    io[2u * i + 1u] = dot(e, d) - c;\n"
              "}\n");
    std::vector<uint32_t> io(128, 0);
    io = runTestShader(file, io);
    for (int i = 0; i < 64; ++i) {
        float len, dot;
        std::memcpy(&len, &io[2 * i], 4);
        std::memcpy(&dot, &io[2 * i + 1], 4);
        EXPECT_LT(std::fabs(len), 1e-6f) << i;
        EXPECT_LT(std::fabs(dot), 1e-5f) << i;
    }
    fs::remove_all(root);
}

TEST(PathtraceGpu, FresnelMatchesCpu) {
    testsupport::context();
    const fs::path root = shaderRoot("fresnel");
    const fs::path file = root / "shaders/fresnel_test.comp";
    // io[0] = eta; io[1 + i] = R at cos θ = (i + 1) / 256 from inside
    writeText(file, "#version 450\nlayout(local_size_x = 256) in;\n"
                    "#include \"common/pathtrace_scatter.glsl\"\n"
                    "layout(std430, binding = 0) buffer B { float io[]; };\n"
                    "void main() { uint i = gl_LocalInvocationIndex;\n"
                    "    io[1u + i] = fresnelExit(float(i + 1u) / 256.0, io[0]); }\n");
    for (float eta : {1.3f, 1.0f, 0.8f, 1.5f}) {
        std::vector<uint32_t> io(257, 0);
        std::memcpy(io.data(), &eta, 4);
        io = runTestShader(file, io);
        for (int i = 0; i < 256; ++i) {
            float r;
            std::memcpy(&r, &io[1 + i], 4);
            const double ref = pathtrace::fresnelDielectric((i + 1) / 256.0, 1.0 / eta);
            EXPECT_NEAR(r, ref, 2e-6) << "eta " << eta << " cos " << (i + 1) / 256.0;
        }
    }
    fs::remove_all(root);
}

// ---- the tracer ---------------------------------------------------------------------------

// Index-matched half-space, isotropic scattering, albedo ϖ = 0.9, normal pencil beam: total
// diffuse reflectance R = 1 − H(1)√(1 − ϖ) (Chandrasekhar, Radiative Transfer, 1960), H from
// 1/H(μ) = √(1 − ϖ) + (ϖ/2) ∫₀¹ μ' H(μ') / (μ + μ') dμ' by fixed-point iteration.
TEST(PathtraceGpu, ChandrasekharTotalReflectance) {
    testsupport::context();
    const double albedo = 0.9;
    std::vector<double> mu, wt;
    pttest::gaussLegendre(64, 0.0, 1.0, mu, wt);
    std::vector<double> h(mu.size(), 1.0);
    auto hOf = [&](double m) {
        double integral = 0;
        for (size_t j = 0; j < mu.size(); ++j)
            integral += wt[j] * mu[j] * h[j] / (m + mu[j]);
        return 1.0 / (std::sqrt(1.0 - albedo) + 0.5 * albedo * integral);
    };
    for (int it = 0; it < 500; ++it) {
        std::vector<double> next(mu.size());
        for (size_t j = 0; j < mu.size(); ++j)
            next[j] = hOf(mu[j]);
        h = next;
    }
    const double exact = 1.0 - hOf(1.0) * std::sqrt(1.0 - albedo);
    EXPECT_NEAR(exact, 0.41495, 1e-4); // H(1) = 1.8501 for ϖ = 0.9 (Chandrasekhar's table)

    for (auto estimator : {pathtrace::Estimator::Implicit, pathtrace::Estimator::Analog}) {
        Medium m{0.1, 0.9, 0.0, 1.0};
        SlabSettings s;
        s.bins = 50;
        s.rMaxMm = 10;
        s.paths = 400000;
        s.seed = 11;
        s.estimator = estimator;
        const pathtrace::SlabResult r = pathtrace::finalize(traceGpu(m, s), s);
        const double z = (r.totalRd - exact) / r.totalRdStderr;
        EXPECT_LT(std::fabs(z), 3.3)
            << "Rd " << r.totalRd << " ± " << r.totalRdStderr << " vs " << exact;
        EXPECT_EQ(r.specular, 0.0);
    }
}

TEST(PathtraceGpu, AgreesWithCpuBinByBin) {
    testsupport::context();
    const Medium m{0.05, 1.0, 0.5, 1.3};
    SlabSettings s;
    s.bins = 60;
    s.rMaxMm = 6.0;
    s.paths = 200000;
    s.seed = 5;
    core::Stopwatch clock;
    const SlabTally gpuTally = traceGpu(m, s);
    const double gpuSeconds = clock.ms() * 1e-3;
    const pathtrace::SlabResult gpu = pathtrace::finalize(gpuTally, s);
    s.seed = 6; // independent of the GPU's streams anyway (PCG32 vs Philox)
    const pathtrace::SlabResult cpu = pathtrace::runSlab(m, s);
    std::printf("[ info ] %llu paths: GPU %.2f s, CPU %.2f s\n",
                static_cast<unsigned long long>(s.paths), gpuSeconds, cpu.seconds);

    const double zMax = normalUpperQuantile(0.01 / (2.0 * s.bins));
    int compared = 0;
    double worst = 0;
    for (size_t i = 0; i < static_cast<size_t>(s.bins); ++i) {
        // enough contributions on both sides for a normal approximation: effective sample size
        // (Σw)²/Σw² of at least 30
        const double nGpu = gpuTally.binSum[i] * gpuTally.binSum[i] / gpuTally.binSumSq[i];
        if (!(nGpu >= 30) || !(cpu.rdStderr[i] > 0)) continue;
        ++compared;
        const double z = (gpu.rd[i] - cpu.rd[i]) / std::hypot(gpu.rdStderr[i], cpu.rdStderr[i]);
        worst = std::max(worst, std::fabs(z));
        EXPECT_LT(std::fabs(z), zMax)
            << "bin " << i << " r " << gpu.rMid[i] << ": GPU " << gpu.rd[i] << " ± "
            << gpu.rdStderr[i] << ", CPU " << cpu.rd[i] << " ± " << cpu.rdStderr[i];
    }
    EXPECT_GE(compared, 50);
    std::printf("[ info ] %d bins compared, max |z| %.2f (limit %.2f)\n", compared, worst, zMax);

    const double zRd =
        (gpu.totalRd - cpu.totalRd) / std::hypot(gpu.totalRdStderr, cpu.totalRdStderr);
    const double zAbs =
        (gpu.absorbed - cpu.absorbed) / std::hypot(gpu.absorbedStderr, cpu.absorbedStderr);
    EXPECT_LT(std::fabs(zRd), 3.3) << gpu.totalRd << " vs " << cpu.totalRd;
    EXPECT_LT(std::fabs(zAbs), 3.3) << gpu.absorbed << " vs " << cpu.absorbed;
    EXPECT_LT(std::fabs(gpu.rouletteNet / gpu.rouletteNetStderr), 3.3);
    EXPECT_DOUBLE_EQ(gpu.specular, cpu.specular);
    EXPECT_LT(std::fabs(accountingError(gpuTally)), 1e-6);
}

// Past llvmpipe's loop limit: without absorption, some paths run for more events than one
// invocation may loop (65535) and a few reach the event limit (10^5 here); they are suspended
// and resumed across dispatches, so no weight goes missing: what did not leave is truncated,
// exactly as many paths as the CPU tracer truncates in expectation.
TEST(PathtraceGpu, LongPathsAreNotLost) {
    testsupport::context();
    const Medium m{0.0, 1.0, 0.0, 1.0};
    SlabSettings s;
    s.bins = 10;
    s.paths = 4000;
    s.termination.maxEvents = 100000;
    const SlabTally t = traceGpu(m, s);
    EXPECT_EQ(t.paths, s.paths);
    EXPECT_GT(t.events, 4000u * 200u); // the heavy tail of return times is there
    EXPECT_EQ(t.absSum, 0.0);
    EXPECT_LT(std::fabs(accountingError(t)), 1e-9); // w stays 1: sums are exact
    EXPECT_GT(t.truncatedPaths, 0u);
    EXPECT_EQ(t.truncSum, static_cast<double>(t.truncatedPaths)); // each with weight 1
}

// A weight roulette with survivors of weight up to 0.9/0.01 = 90, beyond the atomic tallies'
// range (16): they travel through the heavy-weight list.
TEST(PathtraceGpu, HeavyWeightsAreTalliedExactly) {
    testsupport::context();
    const Medium m{0.1, 1.0, 0.0, 1.3};
    SlabSettings s;
    s.bins = 20;
    s.paths = 100000;
    s.termination.rouletteWeight = 0.9;
    s.termination.rouletteSurvival = 0.01;
    GpuSlabTracer tracer(slabShader());
    tracer.reset(m, s);
    tracer.step(s.paths);
    const SlabTally& t = tracer.tally();
    EXPECT_GT(tracer.heavyTallies(), 10u);
    EXPECT_LT(std::fabs(accountingError(t)), 1e-6);
    std::printf("[ info ] %llu heavy values, accounting error %.2g\n",
                static_cast<unsigned long long>(tracer.heavyTallies()), accountingError(t));
}

TEST(PathtraceGpu, DeterministicForAnyStepsAndBudgets) {
    testsupport::context();
    const Medium m{0.02, 1.0, 0.3, 1.4};
    SlabSettings s;
    s.bins = 40;
    s.rMaxMm = 5;
    s.paths = 50000;
    s.seed = 99;
    const SlabTally a = traceGpu(m, s);
    const SlabTally b = traceGpu(m, s);
    EXPECT_TRUE(bitwiseEqual(a, b)) << "same seed, same calls";
    const SlabTally c = traceGpu(m, s, 7777, 37); // other dispatch cuts, paths suspended often
    EXPECT_TRUE(bitwiseEqual(a, c)) << "other step sizes and event budget";
    s.seed = 100;
    const SlabTally d = traceGpu(m, s);
    EXPECT_NE(a.rdSum, d.rdSum) << "another seed, other paths";
}

TEST(PathtraceGpu, DispatchesHandOverOnTheGpuAndTheHostReadsOncePerBatch) {
    testsupport::context();
    using Queue = pathtrace::detail::GpuWorkQueue;
    const Queue::Planning measured = Queue::planning(); // this driver's choice, restored below
    const Medium m{0.02, 1.0, 0.3, 1.4};
    SlabSettings s;
    s.bins = 40;
    s.rMaxMm = 5;
    s.paths = 70000; // two rounds of 2^16 paths, the last one partial
    SlabTally planned[2];
    for (Queue::Planning planning : {Queue::Planning::Gpu, Queue::Planning::Host}) {
        SCOPED_TRACE(planning == Queue::Planning::Gpu ? "planned on the GPU" : "on the host");
        Queue::setPlanning(planning);
        GpuSlabTracer tracer(slabShader());
        tracer.setEventBudget(37); // paths suspended many times: many dispatches per round
        tracer.reset(m, s);
        const auto& q = tracer.workQueue(); // counts since construction: the step's differences
        const uint64_t rounds0 = q.rounds(), dispatches0 = q.dispatches(),
                       queueReads0 = q.queueReads(), tallyReads0 = q.tallyReads();
        tracer.step(s.paths);
        const uint64_t dispatches = q.dispatches() - dispatches0;
        EXPECT_EQ(q.rounds() - rounds0, 2u); // planned on the GPU, one after another
        EXPECT_GE(dispatches, 20u);
        if (planning == Queue::Planning::Gpu) // batches of 1, 2, 4, 8, then 16 dispatches
            EXPECT_LE(q.queueReads() - queueReads0, 6 + dispatches / 16);
        else // the host reads the planner's group count after every dispatch
            EXPECT_EQ(q.queueReads() - queueReads0, dispatches);
        EXPECT_EQ(q.tallyReads() - tallyReads0, 1u); // once for the whole step
        planned[planning == Queue::Planning::Gpu ? 0 : 1] = tracer.tally();
    }
    Queue::setPlanning(measured);
    EXPECT_TRUE(bitwiseEqual(planned[0], planned[1]));
    // the same paths in steps that cut rounds anywhere, with the default budget
    EXPECT_TRUE(bitwiseEqual(planned[0], traceGpu(m, s, 30001)));
}

TEST(PathtraceGpu, WorkgroupSharedTalliesGiveTheSameSumsAsGlobalOnes) {
    testsupport::context();
    const Medium m{0.02, 1.0, 0.3, 1.4};
    SlabSettings s;
    s.rMaxMm = 5;
    s.paths = 30000;
    for (int bins : {40, 506, 507}) { // 506 + 6 slots fill shared memory; 507 do not fit
        SCOPED_TRACE(bins);
        s.bins = bins;
        SlabTally t[2];
        for (int shared = 0; shared < 2; ++shared) {
            GpuSlabTracer tracer(slabShader());
            tracer.setSharedTallies(shared == 1);
            tracer.reset(m, s);
            EXPECT_EQ(tracer.sharedTallies(), shared == 1 && bins <= 506);
            tracer.step(s.paths);
            t[shared] = tracer.tally();
        }
        EXPECT_TRUE(bitwiseEqual(t[0], t[1]));
        EXPECT_LT(std::abs(accountingError(t[1])), 1e-6);
    }
}

TEST(PathtraceGpu, StepStopsAtThePathCountAndResetStartsOver) {
    testsupport::context();
    GpuSlabTracer tracer(slabShader());
    SlabSettings s;
    s.bins = 8;
    s.paths = 3000;
    tracer.reset(Medium{}, s);
    EXPECT_EQ(tracer.step(1000), 1000u);
    EXPECT_EQ(tracer.step(5000), 3000u);
    EXPECT_TRUE(tracer.finished());
    EXPECT_EQ(tracer.step(5000), 3000u);
    const SlabTally first = tracer.tally();
    tracer.reset(Medium{}, s);
    EXPECT_EQ(tracer.pathsDone(), 0u);
    tracer.step(3000);
    EXPECT_TRUE(bitwiseEqual(first, tracer.tally()));
    SlabSettings bad = s;
    bad.bins = 0;
    EXPECT_THROW(tracer.reset(Medium{}, bad), core::Error);
}

// ---- hot reload ---------------------------------------------------------------------------

TEST(PathtraceGpu, BrokenShaderNamesFileAndLineAndKeepsTheProgram) {
    testsupport::context();
    const fs::path root = shaderRoot("reload");
    const fs::path file = root / "shaders/pathtrace_slab.comp";
    const fs::path scatter = root / "shaders/common/pathtrace_scatter.glsl";
    const std::string good = testsupport::readText(file);
    const std::string goodScatter = testsupport::readText(scatter);
    SlabSettings s;
    s.bins = 16;
    s.paths = 5000;
    GpuSlabTracer tracer(file);
    tracer.reset(Medium{}, s);
    tracer.step(s.paths);
    const SlabTally before = tracer.tally();

    // an error in the shader itself
    const std::string needle = "p.events += 1u;";
    const int line = testsupport::lineOf(good, needle);
    writeText(file, testsupport::replaced(good, needle, "p.events += 1u + undefinedThing;"));
    try {
        tracer.reload();
        ADD_FAILURE() << "reload accepted a broken shader";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/pathtrace_slab.comp");
        EXPECT_EQ(e.line(), line);
        EXPECT_NE(
            std::string(e.what()).find("shaders/pathtrace_slab.comp:" + std::to_string(line) + ":"),
            std::string::npos)
            << e.what();
        EXPECT_NE(e.message().find("undefinedThing"), std::string::npos) << e.message();
    }
    // the previous program still runs, with the tally it had
    EXPECT_TRUE(bitwiseEqual(before, tracer.tally()));
    tracer.reset(Medium{}, s);
    tracer.step(s.paths);
    EXPECT_TRUE(bitwiseEqual(before, tracer.tally()));

    // an error in a shared file is reported against that file
    writeText(file, good);
    const std::string scatterNeedle = "float sinT2 = eta * eta";
    const int scatterLine = testsupport::lineOf(goodScatter, scatterNeedle);
    writeText(scatter,
              testsupport::replaced(goodScatter, scatterNeedle, "float sinT2 = eta * eta +"));
    try {
        tracer.reload();
        ADD_FAILURE() << "reload accepted a broken include";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/common/pathtrace_scatter.glsl") << e.what();
        // a syntax error may be reported on the line that completes the bad expression
        EXPECT_GE(e.line(), scatterLine) << e.what();
        EXPECT_LE(e.line(), scatterLine + 1) << e.what();
    }

    // a missing include names the #include line
    writeText(scatter, goodScatter);
    const std::string include = "#include \"common/pathtrace_tally.glsl\"";
    writeText(file, testsupport::replaced(good, include, "#include \"common/missing.glsl\""));
    try {
        tracer.reload();
        ADD_FAILURE() << "reload accepted a missing include";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/pathtrace_slab.comp");
        EXPECT_EQ(e.line(), testsupport::lineOf(good, include));
    }

    // fixed: reload succeeds and starts over
    writeText(file, good);
    tracer.reload();
    EXPECT_EQ(tracer.pathsDone(), 0u);
    tracer.step(s.paths);
    EXPECT_TRUE(bitwiseEqual(before, tracer.tally()));
    fs::remove_all(root);
}

// Not a timing assertion (tests never assert wall-clock times): prints the throughput of the
// reference case on this machine's GL implementation and checks its accounting.
TEST(PathtraceGpu, ReferenceCaseThroughput) {
    testsupport::context();
    const Medium m{0.01, 1.0, 0.0, 1.3};
    SlabSettings s;
    s.bins = 100;
    s.rMaxMm = 15.0; // 0.15 mm bins
    s.paths = 200000;
    GpuSlabTracer tracer(slabShader());
    tracer.reset(m, s);
    tracer.step(s.paths);
    const SlabTally& t = tracer.tally();
    std::printf("[ info ] %s: %llu paths in %.2f s = %.0f paths/s, %.1f events/path\n",
                testsupport::context().renderer().c_str(), static_cast<unsigned long long>(t.paths),
                tracer.seconds(), static_cast<double>(t.paths) / tracer.seconds(),
                static_cast<double>(t.events) / static_cast<double>(t.paths));
    EXPECT_LT(std::fabs(accountingError(t)), 1e-6);
}
