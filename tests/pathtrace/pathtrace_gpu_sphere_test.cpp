// GPU lit-sphere tracer (shaders/pathtrace_sphere.comp) on a headless context:
//   - against the CPU tracer traceLitSphere pixel by pixel and channel by channel (z-scores
//     with a Bonferroni correction), and its total exited power;
//   - bitwise determinism for any step sizes and event budgets;
//   - hot reload: a broken shader names its file and line and the old program keeps working.
#include "../support/gl_fixture.h"
#include "core/statistics.h"
#include "pathtrace/gpu_sphere.h"
#include "pathtrace/sphere_tracer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using pathtrace::GpuSphereTracer;
using pathtrace::Image;
using pathtrace::LitSphereSetup;
using pathtrace::Medium;

fs::path sphereShader() {
    return testsupport::sourceRoot() / "shaders/pathtrace_sphere.comp";
}

// A throwaway copy of shaders/ (for edits).
fs::path shaderRoot(const std::string& tag) {
    const fs::path root =
        fs::temp_directory_path() / ("bw_ptsph_" + tag + "_" + std::to_string(::getpid()));
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

using core::normalUpperQuantile;

// Red: the reference medium; green: forward scattering; blue: more absorbing, other index.
std::array<Medium, 3> testMedia() {
    return {Medium{0.05, 1.0, 0.0, 1.3}, Medium{0.05, 1.0, 0.5, 1.3}, Medium{0.3, 1.0, 0.0, 1.5}};
}

LitSphereSetup testSetup(uint64_t spp) {
    LitSphereSetup s;
    s.radiusMm = 5.0;
    s.lightDir[0] = 0.3;
    s.lightDir[1] = 0.4;
    s.lightDir[2] = 0.87;
    s.width = s.height = 16;
    s.samplesPerPixel = spp;
    s.seed = 12345;
    return s;
}

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool bitwiseEqual(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.samples == b.samples &&
           a.mean == b.mean && a.variance == b.variance;
}

} // namespace

TEST(PathtraceGpuSphere, AgreesWithCpuTracerPerPixel) {
    testsupport::context();
    const auto media = testMedia();
    LitSphereSetup s = testSetup(6000);
    auto t0 = std::chrono::steady_clock::now();
    pathtrace::ImageStats stats;
    const Image cpu = pathtrace::traceLitSphere(media, s, {}, nullptr, {}, &stats);
    const double cpuSeconds = secondsSince(t0);

    s.seed = 777; // an independent sample
    GpuSphereTracer tracer(sphereShader());
    tracer.reset(media, s);
    t0 = std::chrono::steady_clock::now();
    while (!tracer.finished())
        tracer.step(uint64_t(1) << 20);
    const double gpuSeconds = secondsSince(t0);
    const Image gpu = tracer.image();
    ASSERT_EQ(tracer.pathsDone(), pathtrace::litSpherePaths(s));
    ASSERT_EQ(gpu.samples, cpu.samples);
    std::printf("[ timing ] %llu paths/channel: CPU %.2f s, GPU %.2f s (%.3g paths/s over 3 "
                "channels, %.3g collisions)\n",
                static_cast<unsigned long long>(tracer.pathsDone()), cpuSeconds, gpuSeconds,
                3.0 * static_cast<double>(tracer.pathsDone()) / gpuSeconds,
                static_cast<double>(tracer.events()));

    const size_t n = static_cast<size_t>(s.width * s.height);
    size_t tests = 0;
    for (size_t p = 0; p < n; ++p)
        if (stats.pixels.footprint[p] > 0) tests += 3;
    ASSERT_GT(tests, 300u);
    const double zMax = normalUpperQuantile(1e-3 / (2.0 * static_cast<double>(tests + 3)));
    double worst = 0;
    int lit = 0;
    for (size_t p = 0; p < n; ++p) {
        for (size_t c = 0; c < 3; ++c) {
            const size_t k = 3 * p + c;
            if (!(stats.pixels.footprint[p] > 0)) {
                EXPECT_EQ(gpu.mean[k], 0.0f);
                EXPECT_EQ(gpu.variance[k], 0.0f);
                continue;
            }
            const double var = double(gpu.variance[k]) + double(cpu.variance[k]);
            if (var == 0) {
                EXPECT_EQ(gpu.mean[k], cpu.mean[k]) << "pixel " << p << " channel " << c;
                continue;
            }
            if (cpu.mean[k] > 0.05f) ++lit;
            const double z = (double(gpu.mean[k]) - double(cpu.mean[k])) / std::sqrt(var);
            worst = std::max(worst, std::fabs(z));
            EXPECT_LT(std::fabs(z), zMax) << "pixel " << p << " channel " << c << ": GPU "
                                          << gpu.mean[k] << " CPU " << cpu.mean[k];
        }
    }
    EXPECT_GT(lit, 100); // the test has something to compare
    std::array<double, 3> err{};
    const auto exited = tracer.exitedPower(&err);
    for (size_t c = 0; c < 3; ++c) {
        const auto& cs = stats.channel[c];
        const double z = (exited[c] - cs.exited) /
                         std::sqrt(err[c] * err[c] + cs.exitedStderr * cs.exitedStderr);
        worst = std::max(worst, std::fabs(z));
        EXPECT_LT(std::fabs(z), zMax)
            << "exited power, channel " << c << ": GPU " << exited[c] << " CPU " << cs.exited;
        EXPECT_GT(exited[c], 0.1 * cs.incident); // a sanity scale: much of the light comes out
    }
    std::printf("[ stats  ] %zu pixel tests + 3 totals, worst |z| %.2f, Bonferroni bound %.2f; "
                "exited power GPU %.4f %.4f %.4f, CPU %.4f %.4f %.4f W\n",
                tests, worst, zMax, exited[0], exited[1], exited[2], stats.channel[0].exited,
                stats.channel[1].exited, stats.channel[2].exited);
}

TEST(PathtraceGpuSphere, SameSeedSameImageForAnyStepsAndBudgets) {
    testsupport::context();
    const auto media = testMedia();
    const LitSphereSetup s = testSetup(40); // ~7 000 paths per channel
    GpuSphereTracer a(sphereShader());
    a.reset(media, s);
    a.step(a.targetPaths());
    ASSERT_TRUE(a.finished());
    const Image ref = a.image();
    const auto refExited = a.exitedPower();

    GpuSphereTracer b(sphereShader());
    b.setEventBudget(37); // many suspensions
    b.reset(media, s);
    while (!b.finished())
        b.step(777);
    EXPECT_TRUE(bitwiseEqual(ref, b.image()));
    EXPECT_EQ(refExited, b.exitedPower());

    // reset starts over: a second run on the same tracer is the same again
    a.setEventBudget(GpuSphereTracer::kMaxEventBudget);
    a.reset(media, s);
    while (!a.finished())
        a.step(2000);
    EXPECT_TRUE(bitwiseEqual(ref, a.image()));

    // another seed is another image
    LitSphereSetup s2 = s;
    s2.seed = s.seed + 1;
    a.reset(media, s2);
    a.step(a.targetPaths());
    EXPECT_FALSE(bitwiseEqual(ref, a.image()));
}

TEST(PathtraceGpuSphere, BrokenShaderNamesFileAndLineAndKeepsTheProgram) {
    testsupport::context();
    const fs::path root = shaderRoot("reload");
    const fs::path file = root / "shaders/pathtrace_sphere.comp";
    const std::string good = testsupport::readText(file);
    const auto media = testMedia();
    const LitSphereSetup s = testSetup(10);
    GpuSphereTracer tracer(file);
    tracer.reset(media, s);
    tracer.step(tracer.targetPaths());
    const Image before = tracer.image();

    const std::string needle = "p.events += 1u;";
    const int line = testsupport::lineOf(good, needle);
    writeText(file, testsupport::replaced(good, needle, "p.events += 1u + undefinedThing;"));
    try {
        tracer.reload();
        ADD_FAILURE() << "reload accepted a broken shader";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/pathtrace_sphere.comp");
        EXPECT_EQ(e.line(), line);
        EXPECT_NE(std::string(e.what()).find(
                      "shaders/pathtrace_sphere.comp:" + std::to_string(line) + ":"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(e.message().find("undefinedThing"), std::string::npos) << e.message();
    }
    // the previous program keeps its tally and still runs
    EXPECT_TRUE(bitwiseEqual(before, tracer.image()));
    tracer.reset(media, s);
    tracer.step(tracer.targetPaths());
    EXPECT_TRUE(bitwiseEqual(before, tracer.image()));

    // fixed again: reload succeeds and starts over
    writeText(file, good);
    tracer.reload();
    EXPECT_EQ(tracer.pathsDone(), 0u);
    tracer.step(tracer.targetPaths());
    EXPECT_TRUE(bitwiseEqual(before, tracer.image()));
    fs::remove_all(root);
}
