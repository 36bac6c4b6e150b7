// bench pathtrace: throughput and time-to-1 % of the volumetric path tracers.
#include "bench/bench.h"
#include "bench/mcml_peer.h"

#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/gpu_bssrdf.h"
#include "pathtrace/gpu_slab.h"
#include "pathtrace/pathtrace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace app {
namespace {

// Paths a run should trace to last about `seconds` at `rate` paths/s (at least 1e4).
uint64_t pathsFor(double rate, double seconds) {
    return uint64_t(std::max(1e4, rate * seconds));
}

// Single-core CPU run of about `seconds` (a short calibration run sets the path count).
pathtrace::SlabResult cpuRun(const pathtrace::Medium& m, pathtrace::SlabSettings s,
                             double seconds) {
    s.threads = 1;
    s.paths = 20000;
    const auto probe = pathtrace::runSlab(m, s);
    s.paths = pathsFor(double(probe.paths) / std::max(probe.seconds, 1e-6), seconds);
    return pathtrace::runSlab(m, s);
}

// A warm-up of a few paths (compile, first dispatch), then the step size for a timed run of
// about `seconds`: an eighth of what the warm-up's rate would trace in that time (at least
// 1024 paths, at most a full round), so that a run ends near its time on a slow device too.
template <class Tracer> uint64_t warmUp(Tracer& gpu, double seconds) {
    gpu.step(1024);
    const uint64_t before = gpu.pathsDone();
    const double t0 = gpu.seconds();
    gpu.step(1024);
    const double rate = double(gpu.pathsDone() - before) / std::max(gpu.seconds() - t0, 1e-6);
    return std::clamp<uint64_t>(uint64_t(rate * seconds / 8), 1024, Tracer::kMaxPathsPerRound);
}

double gpuRate(pathtrace::GpuSlabTracer& gpu, const pathtrace::Medium& m, pathtrace::SlabSettings s,
               double seconds) {
    s.paths = uint64_t(1) << 40;
    gpu.reset(m, s);
    const uint64_t stepPaths = warmUp(gpu, seconds);
    const uint64_t before = gpu.pathsDone();
    const double t0 = gpu.seconds();
    while (gpu.seconds() - t0 < seconds)
        gpu.step(stepPaths);
    return double(gpu.pathsDone() - before) / std::max(gpu.seconds() - t0, 1e-9);
}

// The mean of the relative standard errors `rel` over the 11 bins around bin b (±5 bins: one
// bin alone would make the figure as noisy as its own error estimate).
double meanAround(const std::vector<double>& rel, int b) {
    double sum = 0;
    int n = 0;
    for (int i = std::max(0, b - 5); i <= std::min(int(rel.size()) - 1, b + 5); ++i) {
        sum += rel[size_t(i)];
        ++n;
    }
    return n ? sum / n : INFINITY;
}

// Time for this single-core run to reach 1 % relative standard error at r (mean of the ±5 bins
// around it; the variance per path is what a run measures; time scales with 1/variance).
double timeTo1Percent(const pathtrace::SlabResult& r, const pathtrace::SlabSettings& s,
                      double rMm) {
    const int b = pathtrace::binOf(rMm, s);
    if (b < 0) return INFINITY;
    std::vector<double> rel(r.rd.size());
    for (size_t i = 0; i < rel.size(); ++i)
        rel[i] = r.rd[i] > 0 ? r.rdStderr[i] / r.rd[i] : INFINITY;
    const double mean = meanAround(rel, b);
    return r.seconds * (mean / 0.01) * (mean / 0.01);
}

// The GL tracer's run of about `seconds` (after a warm-up) as a result with standard
// errors and its wall time.
pathtrace::SlabResult gpuRun(pathtrace::GpuSlabTracer& gpu, const pathtrace::Medium& m,
                             pathtrace::SlabSettings s, double seconds) {
    s.paths = uint64_t(1) << 40;
    gpu.reset(m, s);
    const uint64_t stepPaths = warmUp(gpu, seconds);
    gpu.reset(m, s);
    while (gpu.seconds() < seconds)
        gpu.step(stepPaths);
    pathtrace::SlabResult r = pathtrace::finalize(gpu.tally(), s);
    r.seconds = gpu.seconds();
    return r;
}

// Efficiency per radial range: 1/(relative variance per path × seconds per path) = 10^4 /
// t(1 %), the geometric mean over the bins of each range of r/l_d ([0, 1), [1, 2), [2, 3),
// [3, 4]), as "E0-1 E1-2 E2-3 E3-4" in 1/s. What a roulette or estimator choice is weighed by.
std::string efficiencyByRange(const pathtrace::SlabResult& r, const pathtrace::SlabSettings& s,
                              double ld) {
    std::string out;
    for (int k = 0; k < 4; ++k) {
        double logSum = 0;
        int n = 0;
        for (int b = 0; b < s.bins; ++b) {
            const double rc = (b + 0.5) * s.rMaxMm / s.bins;
            if (rc < k * ld || rc >= (k + 1) * ld) continue;
            const double rel = r.rdStderr[size_t(b)] / r.rd[size_t(b)];
            if (!(r.rd[size_t(b)] > 0) || !(rel > 0)) continue;
            logSum += std::log(1.0 / (rel * rel * r.seconds));
            ++n;
        }
        char b[32];
        std::snprintf(b, sizeof b, " %9.3g", n ? std::exp(logSum / n) : NAN);
        out += b;
    }
    return out;
}

// Single-core connections run (pathtrace/bssrdf_estimate.h, θi = 0, one θs bin) on the radial
// bins `b` for about `seconds`; returns the time to 1 % relative standard error in each bin of
// `bins` (all from the same run) and the paths per second.
std::pair<std::vector<double>, double> connectionsTo1Percent(const pathtrace::Medium& m,
                                                             const pathtrace::BssrdfBins& b,
                                                             const std::vector<int>& bins,
                                                             double seconds) {
    pathtrace::EstimateSettings e;
    e.bins = b;
    e.threads = 1;
    e.estimator = pathtrace::BssrdfEstimator::Connections;
    auto run = [&](uint64_t paths, double& sec) {
        e.paths = paths;
        core::Stopwatch clock;
        const auto t = pathtrace::estimateChunks(m, e, 0, 0, pathtrace::chunkCount(e));
        sec = clock.ms() / 1000.0;
        return pathtrace::finalize(t, e.bins, 0, m);
    };
    double sec = 0;
    run(2000, sec);
    const uint64_t paths = pathsFor(2000 / std::max(sec, 1e-6), seconds);
    const auto r = run(paths, sec);
    std::vector<double> times;
    for (int ir : bins) {
        const double rel = r.RStderr[size_t(ir)] / r.R[size_t(ir)];
        times.push_back(r.R[size_t(ir)] > 0 ? sec * (rel / 0.01) * (rel / 0.01) : INFINITY);
    }
    return {times, double(paths) / sec};
}

// The oblique-incidence estimate (bssrdf_estimate.h) of `e` for about `seconds`: paths/s on
// one CPU core, and on the GL walk when `gpu` is given (else NaN).
std::pair<double, double> estimateRates(const pathtrace::Medium& m, pathtrace::EstimateSettings e,
                                        pathtrace::GpuBssrdfEstimator* gpu, double seconds) {
    e.threads = 1;
    auto cpuRun = [&](uint64_t paths) {
        e.paths = paths;
        core::Stopwatch clock;
        pathtrace::estimateChunks(m, e, 0, 0, pathtrace::chunkCount(e));
        return double(paths) / std::max(clock.ms() / 1000.0, 1e-6);
    };
    const double cpu = cpuRun(pathsFor(cpuRun(2000), seconds));
    if (!gpu) return {cpu, NAN};
    e.paths = uint64_t(1) << 40;
    gpu->reset(m, e);
    const uint64_t stepPaths = warmUp(*gpu, seconds);
    const uint64_t before = gpu->pathsDone();
    const double t0 = gpu->seconds();
    while (gpu->seconds() - t0 < seconds)
        gpu->step(stepPaths);
    return {cpu, double(gpu->pathsDone() - before) / std::max(gpu->seconds() - t0, 1e-9)};
}

} // namespace

int benchPathtrace(const std::filesystem::path& root, double seconds,
                   const std::filesystem::path& mcml) {
    std::unique_ptr<gl::Context> ctx;
    std::unique_ptr<pathtrace::GpuSlabTracer> gpu;
    std::unique_ptr<pathtrace::GpuBssrdfEstimator> gpuWalk;
    try {
        ctx = gl::createHeadlessContext(false);
        gpu = std::make_unique<pathtrace::GpuSlabTracer>(root / "shaders/pathtrace_slab.comp");
        gpuWalk =
            std::make_unique<pathtrace::GpuBssrdfEstimator>(root / "shaders/bssrdf_walk.comp");
        std::printf("GPU tracer on: %s\n", ctx->renderer().c_str());
    } catch (const core::Error& e) {
        std::printf("GPU tracer unavailable: %s\n", e.what());
    }
    std::printf("\nslab cases (sigma_t = 1/mm, 100 bins over 10 mm), %.1f s per run\n", seconds);
    std::printf("%-5s %-5s %-7s %14s %14s %10s\n", "eta", "g", "albedo", "CPU paths/s/core",
                "GPU paths/s", "GPU/CPU");
    for (double eta : {1.0, 1.3})
        for (double g : {0.0, 0.8})
            for (double albedo : {0.5, 0.99}) {
                pathtrace::Medium m{1.0 - albedo, albedo, g, eta};
                pathtrace::SlabSettings s;
                s.rMaxMm = 10;
                s.bins = 100;
                const auto cpu = cpuRun(m, s, seconds);
                const double cpuRate = double(cpu.paths) / cpu.seconds;
                const double gRate = gpu ? gpuRate(*gpu, m, s, seconds) : NAN;
                std::printf("%-5.2g %-5.2g %-7.3g %14.0f %14.0f %10.2f\n", eta, g, albedo, cpuRate,
                            gRate, gRate / cpuRate);
            }

    // The whole BSSRDF at oblique incidence: the GL walk against one CPU core, both measured
    // here in this run.
    std::printf("\nestimate at theta_i 45 deg (sigma_a 0.01/mm, sigma_s 1/mm, g 0.8, eta 1.3; "
                "20 x 6 bins over 5 mm, 2x2 direction cells), %.1f s per run\n",
                seconds);
    std::printf("%-12s %16s %14s %10s\n", "estimator", "CPU paths/s/core", "GPU paths/s",
                "GPU/CPU");
    for (auto est :
         {pathtrace::BssrdfEstimator::Implicit, pathtrace::BssrdfEstimator::Connections}) {
        pathtrace::EstimateSettings e;
        e.thetaIDeg = {45.0};
        e.bins.rBins = 20;
        e.bins.rMaxMm = 5.0;
        e.bins.thetaSBins = 6;
        e.bins.dirCosBins = e.bins.dirPhiBins = 2;
        e.estimator = est;
        const auto [cpuRate, gRate] =
            estimateRates({0.01, 1.0, 0.8, 1.3}, e, gpuWalk.get(), seconds);
        std::printf("%-12s %16.0f %14.0f %10.2f\n", core::nameOf(est), cpuRate, gRate,
                    gRate / cpuRate);
    }

    // Time to 1 % in the 0.15 mm bin at l_d and 4 l_d, one core, every estimator of this
    // build measured here in this run; ratios are against the analog estimator of the same run
    // (no figure measured elsewhere is printed).
    struct Case {
        const char* name;
        pathtrace::Medium m;
    };
    const Case cases[] = {
        {"eta 1.3, sigma_a 0.01/mm, sigma_s 1/mm, g 0", {0.01, 1.0, 0.0, 1.3}},
        {"marble red: eta 1.3, sigma_a 0.0021/mm, sigma_s 2.19/mm, g 0", {0.0021, 2.19, 0.0, 1.3}}};
    for (const Case& c : cases) {
        const double ld = 1.0 / std::sqrt(3 * c.m.sigmaA * (c.m.sigmaA + c.m.sigmaS * (1 - c.m.g)));
        pathtrace::SlabSettings s;
        s.rMaxMm = 4 * ld + 1.0;
        s.bins = int(std::ceil(s.rMaxMm / 0.15));
        s.rMaxMm = 0.15 * s.bins; // 0.15 mm bins beyond 4 l_d
        std::printf(
            "\n%s, 0.15 mm bins, l_d = %.3f mm; CPU lines: one core, GL lines: the GL device\n",
            c.name, ld);
        std::printf("%-10s %12s %14s %14s %12s %12s %10s\n", "estimator", "paths/s", "t(1%) @ l_d",
                    "t(1%) @ 4 l_d", "vs analog @1", "vs analog @4", "ns/event");
        double analogAt1 = NAN, analogAt4 = NAN, implicitAt1 = NAN, implicitAt4 = NAN;
        std::vector<std::string> efficiency; // per estimator line, printed below the table
        // CPU lines: analog (Algorithm 1 as printed) and with the default radial splitting
        // (pathtrace.h, Splitting), then with expected-value exits too (ExpectedExits,
        // kExpectedExitSamples); implicit the same three ways (`split-ev` is the default walk); and
        // MCML's own roulette (w < 10^-4, survival 0.1) on our walk: MCML's estimator, so its
        // variance per path is MCML's.
        struct Line {
            const char* name;
            pathtrace::Estimator est;
            int levels, exitSamples;
            double rouletteWeight, rouletteSurvival;
        };
        const pathtrace::Termination term;
        const int split = pathtrace::Splitting{}.levels, ev = pathtrace::kExpectedExitSamples;
        const double rw = term.rouletteWeight, rs = term.rouletteSurvival;
        const Line lines[] = {{"analog", pathtrace::Estimator::Analog, 0, 0, rw, rs},
                              {"an-split", pathtrace::Estimator::Analog, split, 0, rw, rs},
                              {"an-ev", pathtrace::Estimator::Analog, split, ev, rw, rs},
                              {"implicit", pathtrace::Estimator::Implicit, 0, 0, rw, rs},
                              {"split", pathtrace::Estimator::Implicit, split, 0, rw, rs},
                              {"split-ev", pathtrace::Estimator::Implicit, split, ev, rw, rs},
                              {"mcml-rr", pathtrace::Estimator::Implicit, 0, 0, 1e-4, 0.1}};
        std::vector<std::pair<std::string, std::pair<double, double>>> cpuTimes;
        for (const Line& line : lines) {
            s.estimator = line.est;
            s.splitting.levels = line.levels;
            s.exits.samples = line.exitSamples;
            s.termination.rouletteWeight = line.rouletteWeight;
            s.termination.rouletteSurvival = line.rouletteSurvival;
            const auto r = cpuRun(c.m, s, seconds * 4);
            const double t1 = timeTo1Percent(r, s, ld), t4 = timeTo1Percent(r, s, 4 * ld);
            if (std::string(line.name) == "analog") analogAt1 = t1, analogAt4 = t4;
            if (std::string(line.name) == "implicit") implicitAt1 = t1, implicitAt4 = t4;
            std::printf("%-10s %12.0f %13.2fs %13.2fs %11.2fx %11.2fx %10.1f\n", line.name,
                        double(r.paths) / r.seconds, t1, t4, analogAt1 / t1, analogAt4 / t4,
                        1e9 * r.seconds / double(std::max<uint64_t>(r.events, 1)));
            efficiency.push_back(std::string("CPU ") + line.name + ":" +
                                 efficiencyByRange(r, s, ld));
            cpuTimes.push_back({line.name, {t1, t4}});
        }
        s.splitting = {};
        s.exits = {};
        s.termination = term;
        // The GL tracer on the same case, whichever device the context has (on llvmpipe: the
        // CPU's cores through the GL compute path), against the CPU's one core above.
        // "GL shared" / "GL global": implicit with the exits summed per workgroup in shared
        // memory / added to the global tally one by one (the same sums bitwise; the default
        // takes shared where the driver plans dispatches on the GPU: gpu_slab.h).
        struct GlLine {
            const char* name;
            pathtrace::Estimator est;
            int shared; // -1: the default
        };
        const GlLine glLines[] = {{"GL analog", pathtrace::Estimator::Analog, -1},
                                  {"GL implicit", pathtrace::Estimator::Implicit, -1},
                                  {"GL shared", pathtrace::Estimator::Implicit, 1},
                                  {"GL global", pathtrace::Estimator::Implicit, 0}};
        const bool sharedDefault = gpu && gpu->sharedTalliesCompiled();
        if (gpu)
            for (const GlLine& line : glLines) {
                s.estimator = line.est;
                gpu->setSharedTallies(line.shared < 0 ? sharedDefault : line.shared == 1);
                const auto r = gpuRun(*gpu, c.m, s, seconds * 4);
                gpu->setSharedTallies(sharedDefault);
                const double t1 = timeTo1Percent(r, s, ld), t4 = timeTo1Percent(r, s, 4 * ld);
                std::printf("%-10s %12.0f %13.3gs %13.3gs %11.2fx %11.2fx %10s\n", line.name,
                            double(r.paths) / r.seconds, t1, t4, analogAt1 / t1, analogAt4 / t4,
                            "");
                efficiency.push_back(std::string(line.name) + ":" + efficiencyByRange(r, s, ld));
            }
        // Connections on exactly the histogram's bin at each radius (a one-bin table: what a
        // user asks for when a radius matters), and on the whole profile of 0.15 mm bins.
        double c1 = NAN, c4 = NAN, rate = NAN;
        for (double at : {ld, 4 * ld}) {
            const int b = pathtrace::binOf(at, s);
            pathtrace::BssrdfBins one;
            one.rBins = 1;
            one.thetaSBins = 1;
            one.rStartMm = 0.15 * b;
            one.rMaxMm = 0.15 * (b + 1);
            const auto [t, r] = connectionsTo1Percent(c.m, one, {0}, seconds * 4);
            (at == ld ? c1 : c4) = t[0];
            rate = r;
        }
        std::printf("%-10s %12.0f %13.1fs %13.1fs %11.2fx %11.2fx   (one bin; %.2fx, %.2fx vs "
                    "implicit; targets 3x, 5x)\n",
                    "connect-1", rate, c1, c4, analogAt1 / c1, analogAt4 / c4, implicitAt1 / c1,
                    implicitAt4 / c4);
        pathtrace::BssrdfBins all;
        all.rBins = s.bins;
        all.rMaxMm = s.rMaxMm;
        all.thetaSBins = 1;
        const int b1 = pathtrace::binOf(ld, s), b4 = pathtrace::binOf(4 * ld, s);
        const auto [f, fr] = connectionsTo1Percent(c.m, all, {b1, b4}, seconds * 4);
        const double f1 = f[0], f4 = f[1];
        std::printf("%-10s %12.0f %13.1fs %13.1fs %11.2fx %11.2fx   (all %d bins; %.2fx, %.2fx "
                    "vs implicit)\n",
                    "connect-all", fr, f1, f4, analogAt1 / f1, analogAt4 / f4, s.bins,
                    implicitAt1 / f1, implicitAt4 / f4);
        if (!mcml.empty() && &c == &cases[0]) {
            McmlCase mc;
            mc.bins = std::max(400, int(std::ceil(4 * ld / mc.binMm)) + 10);
            std::printf("running MCML (%s): %lld photons in %d runs of one process ...\n",
                        mcml.string().c_str(), mc.photonsPerBatch * mc.batches, mc.batches);
            std::fflush(stdout);
            const McmlPeer p = runMcmlPeer(mcml, c.m, mc);
            std::vector<double> rel(p.relVar.size()); // relative standard errors of its run
            for (size_t i = 0; i < rel.size(); ++i)
                rel[i] = std::sqrt(p.relVar[i] / p.photons);
            auto t = [&](double r) {
                const double mean = meanAround(rel, int(r / mc.binMm));
                return p.seconds * (mean / 0.01) * (mean / 0.01);
            };
            const double m1 = t(ld), m4 = t(4 * ld);
            std::printf("%-10s %12.0f %13.2fs %13.2fs   (MCML 1.2.2 here, one core; its variance "
                        "per photon from %d independent runs)\n",
                        "MCML", p.photonsPerSecond, m1, m4, mc.batches);
            std::printf("MCML's time to 1 %% over ours (targets 20x at l_d, 10x at 4 l_d):");
            for (const auto& [name, times] : cpuTimes)
                std::printf("  %s %.2fx, %.2fx;", name.c_str(), m1 / times.first,
                            m4 / times.second);
            std::printf("\n");
        }
        std::printf("efficiency 1/(rel. variance x s) = 1e4/t(1%%), geometric mean over the bins "
                    "of r/l_d in [0,1) [1,2) [2,3) [3,4):\n");
        for (const std::string& line : efficiency)
            std::printf("  %-16s%s\n", line.substr(0, line.find(':') + 1).c_str(),
                        line.substr(line.find(':') + 1).c_str());
    }
    std::printf("\nwhat limits it: one free flight per event costs a log (distance), a sqrt and "
                "sin/cos (HG direction and azimuth), plus a Fresnel evaluation per boundary hit; "
                "the implicit estimator takes more events per path in exchange for far fewer "
                "paths in the tail bins. Connections (seed 001) cost one connection per bin per "
                "collision, so connect-1 estimates the two radii of the bench by one-bin tables, "
                "and connect-all shows the price of the whole profile at once.\n");
    return 0;
}

} // namespace app
