// GPU BSSRDF estimate (pathtrace/gpu_bssrdf.h, shaders/bssrdf_walk.comp) on a headless context:
//   - against the CPU walk (bssrdf_walk.cpp) bin by bin: R per spatial bin and S per direction
//     cell, total R_d and absorbed, by z-tests with a Bonferroni correction (family-wise alpha
//     1e-3) at θi 0° and 60°, g 0 and 0.8, for the connections and implicit estimators (and
//     analog once), uniform and logarithmic radial bins; the slice's energy check;
//   - the batch-means standard errors of the connections against the CPU's per-path ones;
//   - scattering orders: single + multiple = all; long paths past llvmpipe's loop limit;
//   - bitwise determinism for any step sizes and iteration budgets;
//   - hot reload: a broken shader names its file and line and the old program keeps working.
#include "../support/gl_fixture.h"
#include "core/statistics.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/gpu_bssrdf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <unistd.h>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace pathtrace;

fs::path walkShader() {
    return testsupport::sourceRoot() / "shaders/bssrdf_walk.comp";
}

BssrdfTally traceGpu(const Medium& m, const EstimateSettings& s, size_t angle = 0,
                     uint64_t stepSize = 0,
                     uint32_t budget = GpuBssrdfEstimator::kDefaultEventBudget) {
    GpuBssrdfEstimator gpu(walkShader());
    gpu.setEventBudget(budget);
    gpu.reset(m, s, angle);
    while (!gpu.finished())
        gpu.step(stepSize ? stepSize : s.paths);
    return gpu.tally();
}

BssrdfTally traceCpu(const Medium& m, const EstimateSettings& s, size_t angle = 0) {
    return estimateChunks(m, s, angle, 0, chunkCount(s));
}

// Small bins for llvmpipe: 6 radial × 3 θs bins, 2 × 2 direction cells.
EstimateSettings smallSettings(BssrdfEstimator e, double thetaI, bool logBins) {
    EstimateSettings s;
    s.thetaIDeg = {thetaI};
    s.bins.rBins = 6;
    s.bins.rMaxMm = 3.0;
    s.bins.thetaSBins = 3;
    s.bins.dirCosBins = 2;
    s.bins.dirPhiBins = 2;
    if (logBins) {
        s.bins.spacing = RadialSpacing::Log;
        s.bins.rMinMm = 0.2;
    }
    s.paths = 20000;
    s.seed = 11;
    s.threads = 2;
    s.estimator = e;
    return s;
}

// One comparison of a GPU and a CPU estimate with their standard errors.
struct Compared {
    std::string what;
    double gpu, gpuErr, cpu, cpuErr;
};

// Effective number of paths behind a CPU bin, (Σx)²/Σx²: the normal approximation needs many.
double effectivePaths(const detail::ExactSum& s, const detail::ExactSum& s2) {
    const double a = s.value(), b = s2.value();
    return b > 0 ? a * a / b : 0.0;
}

struct Case {
    BssrdfEstimator estimator;
    double thetaI, g;
    bool logBins;
};

void agreeWithCpu(const Case& c) {
    testsupport::context();
    const Medium m{0.3, 1.0, c.g, 1.3};
    EstimateSettings s = smallSettings(c.estimator, c.thetaI, c.logBins);
    // the histograms need more paths for as many populated cells (and cost less per path)
    s.paths = c.estimator == BssrdfEstimator::Connections ? 40000
              : c.estimator == BssrdfEstimator::Implicit  ? 200000
                                                          : 400000;
    core::Stopwatch clock;
    const BssrdfTally gt = traceGpu(m, s);
    const double gpuSeconds = clock.ms() * 1e-3;
    EstimateSettings cs = s;
    cs.seed = 12; // the streams differ anyway (PCG32 vs Philox)
    clock = core::Stopwatch();
    const BssrdfTally ct = traceCpu(m, cs);
    const double cpuSeconds = clock.ms() * 1e-3;
    const BssrdfSlice g = finalize(gt, s.bins, c.thetaI, m);
    const BssrdfSlice k = finalize(ct, s.bins, c.thetaI, m);
    ASSERT_EQ(g.paths, s.paths);
    EXPECT_EQ(energyProblem(g, s.orders), "");
    EXPECT_EQ(g.specular, k.specular);

    std::vector<Compared> cmp;
    for (size_t i = 0; i < g.R.size(); ++i)
        if (effectivePaths(ct.binSum[i], ct.binSumSq[i]) >= 30 && g.RStderr[i] > 0)
            cmp.push_back(
                {"R bin " + std::to_string(i), g.R[i], g.RStderr[i], k.R[i], k.RStderr[i]});
    const size_t rCompared = cmp.size();
    for (size_t i = 0; i < g.S.size(); ++i)
        if (effectivePaths(ct.dirSum[i], ct.dirSumSq[i]) >= 30 && g.SStderr[i] > 0)
            cmp.push_back(
                {"S cell " + std::to_string(i), g.S[i], g.SStderr[i], k.S[i], k.SStderr[i]});
    const size_t sCompared = cmp.size() - rCompared;
    cmp.push_back({"total R_d", g.totalRd, g.totalRdStderr, k.totalRd, k.totalRdStderr});
    cmp.push_back({"absorbed", g.absorbed, g.absorbedStderr, k.absorbed, k.absorbedStderr});
    EXPECT_GE(rCompared, 15u);
    EXPECT_GE(sCompared, 36u);

    const double zMax = core::normalUpperQuantile(1e-3 / (2.0 * double(cmp.size())));
    double worst = 0;
    for (const Compared& x : cmp) {
        const double z = (x.gpu - x.cpu) / std::hypot(x.gpuErr, x.cpuErr);
        worst = std::max(worst, std::fabs(z));
        EXPECT_LT(std::fabs(z), zMax) << x.what << ": GPU " << x.gpu << " ± " << x.gpuErr
                                      << ", CPU " << x.cpu << " ± " << x.cpuErr;
    }
    std::printf("[ info ] %zu R bins, %zu S cells: max |z| %.2f (limit %.2f); GPU %.2f s, CPU "
                "%.2f s\n",
                rCompared, sCompared, worst, zMax, gpuSeconds, cpuSeconds);
}

} // namespace

TEST(BssrdfGpu, ConnectionsAgreeWithCpuAtNormalIncidence) {
    agreeWithCpu({BssrdfEstimator::Connections, 0.0, 0.0, false});
}
TEST(BssrdfGpu, ConnectionsAgreeWithCpuAtSixtyDegreesForwardScattering) {
    agreeWithCpu({BssrdfEstimator::Connections, 60.0, 0.8, true});
}
TEST(BssrdfGpu, ConnectionsAgreeWithCpuAtSixtyDegreesIsotropic) {
    agreeWithCpu({BssrdfEstimator::Connections, 60.0, 0.0, false});
}
TEST(BssrdfGpu, ConnectionsAgreeWithCpuAtNormalIncidenceForwardScattering) {
    agreeWithCpu({BssrdfEstimator::Connections, 0.0, 0.8, true});
}
TEST(BssrdfGpu, ImplicitAgreesWithCpuAtNormalIncidence) {
    agreeWithCpu({BssrdfEstimator::Implicit, 0.0, 0.0, false});
}
TEST(BssrdfGpu, ImplicitAgreesWithCpuAtSixtyDegreesForwardScattering) {
    agreeWithCpu({BssrdfEstimator::Implicit, 60.0, 0.8, true});
}
TEST(BssrdfGpu, ImplicitAgreesWithCpuAtSixtyDegreesIsotropic) {
    agreeWithCpu({BssrdfEstimator::Implicit, 60.0, 0.0, false});
}
TEST(BssrdfGpu, ImplicitAgreesWithCpuAtNormalIncidenceForwardScattering) {
    agreeWithCpu({BssrdfEstimator::Implicit, 0.0, 0.8, true});
}
TEST(BssrdfGpu, AnalogAgreesWithCpuAtSixtyDegrees) {
    agreeWithCpu({BssrdfEstimator::Analog, 60.0, 0.8, false});
}

// The batch-means standard errors of the connections estimate the same per-path variance as
// the CPU's per-path second moments: their ratio is near 1 bin by bin (each GPU error has
// B − 1 = 127 degrees of freedom: relative spread 6 %). Per-contribution squares in their
// place would come out well below.
TEST(BssrdfGpu, BatchMeansErrorsMatchPerPathErrors) {
    testsupport::context();
    const Medium m{0.3, 1.0, 0.5, 1.3};
    EstimateSettings s = smallSettings(BssrdfEstimator::Connections, 30.0, false);
    s.bins.dirCosBins = s.bins.dirPhiBins = 1;
    s.paths = 40000;
    GpuBssrdfEstimator gpu(walkShader());
    gpu.reset(m, s);
    EXPECT_EQ(gpu.batches(), GpuBssrdfEstimator::kMaxBatches);
    gpu.step(s.paths);
    const BssrdfSlice g = finalize(gpu.tally(), s.bins, 30.0, m);
    const BssrdfSlice k = finalize(traceCpu(m, s), s.bins, 30.0, m);
    std::vector<double> ratios;
    for (size_t i = 0; i < g.R.size(); ++i) {
        ASSERT_GT(k.RStderr[i], 0) << "bin " << i;
        ratios.push_back(g.RStderr[i] / k.RStderr[i]);
        EXPECT_GT(ratios.back(), 0.7) << "bin " << i;
        EXPECT_LT(ratios.back(), 1.4) << "bin " << i;
    }
    std::sort(ratios.begin(), ratios.end());
    const double median = ratios[ratios.size() / 2];
    EXPECT_GT(median, 0.9);
    EXPECT_LT(median, 1.1);
    std::printf("[ info ] GPU/CPU standard error: min %.3f median %.3f max %.3f\n", ratios.front(),
                median, ratios.back());
}

// Single and multiple scattering are disjoint parts of all orders: the flux into one disc
// (one bin, so its standard error is the batch-means one) adds up, by a z-test.
TEST(BssrdfGpu, SingleAndMultipleOrdersAddUpToAll) {
    testsupport::context();
    const Medium m{0.3, 1.0, 0.5, 1.3};
    EstimateSettings s = smallSettings(BssrdfEstimator::Connections, 45.0, false);
    s.bins.rBins = s.bins.thetaSBins = s.bins.dirCosBins = s.bins.dirPhiBins = 1;
    s.bins.rMaxMm = 2.0;
    s.paths = 40000;
    auto disc = [&](ScatterOrders o, double& err) {
        EstimateSettings x = s;
        x.orders = o;
        x.seed = 20 + uint64_t(o); // independent estimates
        const BssrdfSlice sl = finalize(traceGpu(m, x), x.bins, 45.0, m);
        EXPECT_EQ(energyProblem(sl, o), "") << int(o);
        err = sl.RStderr[0];
        return sl.R[0];
    };
    double eAll = 0, eSingle = 0, eMulti = 0;
    const double all = disc(ScatterOrders::All, eAll);
    const double single = disc(ScatterOrders::SingleOnly, eSingle);
    const double multi = disc(ScatterOrders::MultipleOnly, eMulti);
    EXPECT_GT(single, 0.0);
    EXPECT_GT(multi, single);
    const double err = std::sqrt(eAll * eAll + eSingle * eSingle + eMulti * eMulti);
    const double z = (single + multi - all) / err;
    EXPECT_LT(std::fabs(z), core::normalUpperQuantile(1e-3 / 2))
        << single << " + " << multi << " vs " << all << " ± " << err;
    std::printf("[ info ] R of the disc: single %.5f + multiple %.5f vs all %.5f: z = %.2f\n",
                single, multi, all, z);
}

// Past llvmpipe's loop limit: without absorption and with an index-matched surface, some
// paths run for more collisions (each with 6 + 1 connection samples) than one invocation may
// loop (65535); suspended and resumed across dispatches, none is lost: every path's weight 1
// leaves or is truncated, exactly.
TEST(BssrdfGpu, LongPathsAreNotLost) {
    testsupport::context();
    const Medium m{0.0, 1.0, 0.0, 1.0};
    EstimateSettings s = smallSettings(BssrdfEstimator::Connections, 30.0, false);
    s.bins.dirCosBins = s.bins.dirPhiBins = 1;
    s.paths = 2000;
    s.termination.maxEvents = 100000;
    const BssrdfTally t = traceGpu(m, s);
    EXPECT_EQ(t.paths, s.paths);
    EXPECT_GT(t.events.value(), 2000.0 * 200.0); // the heavy tail of return times is there
    EXPECT_EQ(t.absSum.value(), 0.0);
    EXPECT_GT(t.truncatedPaths, 0u);
    EXPECT_EQ(t.truncSum.value(), double(t.truncatedPaths)); // each with weight 1
    EXPECT_EQ(t.exitSum.value() + t.truncSum.value(), double(s.paths));
    const BssrdfSlice sl = finalize(t, s.bins, 30.0, m);
    EXPECT_LT(std::fabs(sl.energyDiff), 5.0 * sl.energyDiffStderr)
        << sl.energyDiff << " ± " << sl.energyDiffStderr;
}

TEST(BssrdfGpu, DeterministicForAnyStepsAndBudgets) {
    testsupport::context();
    const Medium m{0.2, 1.0, 0.6, 1.4};
    EstimateSettings s = smallSettings(BssrdfEstimator::Connections, 60.0, true);
    s.thetaIDeg = {0.0, 60.0};
    s.paths = 6000;
    const BssrdfTally a = traceGpu(m, s, 1);
    const BssrdfTally b = traceGpu(m, s, 1);
    EXPECT_TRUE(a == b) << "same seed, same calls";
    const BssrdfTally c = traceGpu(m, s, 1, 1777, 29); // other cuts, paths suspended often
    EXPECT_TRUE(a == c) << "other step sizes and iteration budget";
    const BssrdfTally d = traceGpu(m, s, 0);
    EXPECT_FALSE(a.binSum == d.binSum) << "another angle, other streams";
    s.estimator = BssrdfEstimator::Implicit;
    EXPECT_TRUE(traceGpu(m, s, 1, 0, 4096) == traceGpu(m, s, 1, 999, 7));
}

TEST(BssrdfGpu, TalliesAreFoldedOnTheGpuAndReadOncePerRun) {
    testsupport::context();
    using Queue = detail::GpuWorkQueue;
    const Medium m{0.2, 1.0, 0.6, 1.4};
    EstimateSettings s = smallSettings(BssrdfEstimator::Connections, 60.0, true);
    s.paths = 6000;
    BssrdfTally t[2];
    for (int folded = 1; folded >= 0; --folded) {
        SCOPED_TRACE(folded ? "folded on the GPU" : "read after every dispatch");
        Queue::setMaxFoldSlots(folded ? uint64_t(1) << 20 : 0);
        GpuBssrdfEstimator gpu(walkShader());
        gpu.setEventBudget(29); // many dispatches
        gpu.reset(m, s, 0);
        gpu.step(s.paths);
        const Queue& q = gpu.workQueue();
        EXPECT_EQ(q.folds(), folded == 1);
        EXPECT_GE(q.dispatches(), 10u);
        // folded: one read for the run; else one after every dispatch issued (GPU-planned
        // batches may end with dispatches of 0 groups)
        if (folded)
            EXPECT_EQ(q.tallyReads(), 1u);
        else
            EXPECT_GE(q.tallyReads(), q.dispatches());
        t[folded] = gpu.tally();
    }
    Queue::setMaxFoldSlots(uint64_t(1) << 20);
    EXPECT_TRUE(t[0] == t[1]) << "the same 128-bit sums either way";
}

TEST(BssrdfGpu, StepStopsAtThePathCountAndBadSettingsThrow) {
    testsupport::context();
    GpuBssrdfEstimator gpu(walkShader());
    EstimateSettings s = smallSettings(BssrdfEstimator::Implicit, 30.0, false);
    s.paths = 3000;
    gpu.reset(Medium{}, s);
    EXPECT_EQ(gpu.step(1000), 1000u);
    EXPECT_EQ(gpu.step(5000), 3000u);
    EXPECT_TRUE(gpu.finished());
    EXPECT_EQ(gpu.step(5000), 3000u);
    EXPECT_EQ(gpu.batches(), 1u);
    EstimateSettings bad = s;
    bad.bins.rBins = 0;
    EXPECT_THROW(gpu.reset(Medium{}, bad), core::Error);
    EXPECT_THROW(gpu.reset(Medium{}, s, 1), core::Error); // one angle only
    // connections: 128 batches, fewer for a table whose cells would not fit kMaxSlots, and a
    // clear error when even kMinBatches would not
    EstimateSettings big = s;
    big.estimator = BssrdfEstimator::Connections;
    gpu.reset(Medium{}, big);
    EXPECT_EQ(gpu.batches(), GpuBssrdfEstimator::kMaxBatches);
    big.bins.rBins = 300;
    big.bins.thetaSBins = 20;
    big.bins.dirCosBins = big.bins.dirPhiBins = 4; // 6000 × (1 + 16) cells: 64 batches fit
    gpu.reset(Medium{}, big);
    EXPECT_EQ(gpu.batches(), 64u);
    big.bins.thetaSBins = 200; // 60000 × 17 cells × 16 batches > 2^23 slots
    try {
        gpu.reset(Medium{}, big);
        ADD_FAILURE() << "a table beyond the GPU tally was accepted";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("bins"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("CPU"), std::string::npos) << e.what();
    }
    bad = s;
    bad.termination.rouletteWeight = 0.5;
    bad.termination.rouletteSurvival = 1e-12; // survivors beyond what the tallies hold
    EXPECT_THROW(gpu.reset(Medium{}, bad), core::Error);
}

TEST(BssrdfGpu, BrokenShaderNamesFileAndLineAndKeepsTheProgram) {
    testsupport::context();
    const fs::path root =
        fs::temp_directory_path() / ("bw_bssrdfgpu_reload_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    testsupport::removeAtExit(root);
    fs::copy(testsupport::sourceRoot() / "shaders", root / "shaders", fs::copy_options::recursive);
    const fs::path file = root / "shaders/bssrdf_walk.comp";
    const std::string good = testsupport::readText(file);
    EstimateSettings s = smallSettings(BssrdfEstimator::Connections, 60.0, false);
    s.paths = 3000;
    GpuBssrdfEstimator gpu(file);
    gpu.reset(Medium{}, s);
    gpu.step(s.paths);
    const BssrdfTally before = gpu.tally();

    const std::string needle = "p.events += 1u;";
    const int line = testsupport::lineOf(good, needle);
    {
        std::ofstream out(file, std::ios::binary);
        out << testsupport::replaced(good, needle, "p.events += 1u + undefinedThing;");
    }
    try {
        gpu.reload();
        ADD_FAILURE() << "reload accepted a broken shader";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/bssrdf_walk.comp");
        EXPECT_EQ(e.line(), line);
        EXPECT_NE(e.message().find("undefinedThing"), std::string::npos) << e.message();
    }
    EXPECT_TRUE(before == gpu.tally()); // the tally it had
    gpu.reset(Medium{}, s);             // and the old program still traces the same paths
    gpu.step(s.paths);
    EXPECT_TRUE(before == gpu.tally());

    {
        std::ofstream out(file, std::ios::binary);
        out << good;
    }
    gpu.reload();
    EXPECT_EQ(gpu.pathsDone(), 0u);
    gpu.step(s.paths);
    EXPECT_TRUE(before == gpu.tally());
    fs::remove_all(root);
}
