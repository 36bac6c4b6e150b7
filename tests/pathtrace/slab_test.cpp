// pathtrace slab tracer (fast checks): per-path energy accounting for many media and both
// estimators, expected energy conservation (z-test), determinism across thread counts and
// against the single-threaded traceSlab, cancellation (completed prefix only), progress on the
// calling thread, finalize's formulas on a hand-made tally, σa = 0.
#include "core/core.h"
#include "pathtrace/pathtrace.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <thread>
#include <vector>

using namespace pathtrace;

namespace {
Medium medium(double albedo, double g, double eta) {
    Medium m;
    m.sigmaS = 1.0;
    m.sigmaA = m.sigmaS * (1 - albedo) / albedo; // α = σs/(σa + σs)
    m.g = g;
    m.eta = eta;
    return m;
}

bool sameBits(const std::vector<double>& a, const std::vector<double>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}
bool sameBits(double a, double b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}
void expectBitwiseEqual(const SlabResult& a, const SlabResult& b) {
    EXPECT_EQ(a.paths, b.paths);
    EXPECT_EQ(a.events, b.events);
    EXPECT_TRUE(sameBits(a.rd, b.rd));
    EXPECT_TRUE(sameBits(a.rdStderr, b.rdStderr));
    EXPECT_TRUE(sameBits(a.totalRd, b.totalRd));
    EXPECT_TRUE(sameBits(a.totalRdStderr, b.totalRdStderr));
    EXPECT_TRUE(sameBits(a.absorbed, b.absorbed));
    EXPECT_TRUE(sameBits(a.absorbedStderr, b.absorbedStderr));
    EXPECT_TRUE(sameBits(a.rouletteNet, b.rouletteNet));
    EXPECT_TRUE(sameBits(a.specular, b.specular));
}
} // namespace

// (a) specular + reflected + absorbed + truncated + rouletteLoss == 1 for every path, to 1e-12;
// every weight stays bounded (≤ 1 here: entry weight ≤ 1, roulette survivors ≤ 0.1/0.5), and a
// path truncated at the event limit ends there with its weight as `truncated`. With radial
// splitting (on by default) a path's copies add up: its exits, and the weights and roulette
// changes of every copy, in the same identity.
TEST(Slab, EnergyAccountingPerPath) {
    int checked = 0, exited = 0, truncatedPaths = 0, splitPaths = 0;
    for (int levels : {0, Splitting{}.levels})
        for (Estimator est : {Estimator::Implicit, Estimator::Analog})
            for (double eta : {1.0, 1.3})
                for (double g : {0.0, 0.9})
                    for (double albedo : {0.5, 0.99, 1.0})
                        for (uint32_t limit : {1u << 20, 20u}) {
                            // σa = 0: l_d is infinite and nothing splits (and such paths are long)
                            if (levels > 0 && albedo == 1.0) continue;
                            const Medium m = medium(albedo, g, eta);
                            SlabSettings s;
                            s.estimator = est;
                            s.termination.maxEvents = limit;
                            s.splitting.levels = levels;
                            s.seed = 77;
                            for (uint64_t i = 0; i < 2000; ++i) {
                                const PathRecord p = tracePath(m, s, i);
                                const double sum = p.specular + p.reflected + p.absorbed +
                                                   p.truncated + p.rouletteLoss;
                                ASSERT_NEAR(sum, 1.0, 1e-12)
                                    << "eta " << eta << " g " << g << " albedo " << albedo
                                    << " path " << i;
                                ASSERT_GE(p.reflected, 0.0);
                                ASSERT_GE(p.absorbed, 0.0);
                                ASSERT_GE(p.events, 1u);
                                ASSERT_LE(p.longestCopy, limit);
                                ASSERT_GE(p.events, p.longestCopy);
                                if (levels == 0) { // one copy: its weights are bounded by 1
                                    ASSERT_EQ(p.events, p.longestCopy);
                                    ASSERT_LE(p.reflected, 1.0);
                                    ASSERT_LE(p.truncated, 1.0);
                                    ASSERT_LE(std::fabs(p.rouletteLoss), 1.0);
                                }
                                if (p.truncated > 0) {
                                    ASSERT_EQ(p.longestCopy, limit);
                                    if (levels == 0) { // one copy: one end
                                        ASSERT_FALSE(p.exited);
                                    }
                                    ++truncatedPaths;
                                }
                                ASSERT_EQ(p.exits.size() > 1, p.exits.size() > 1 && levels > 0);
                                double exitSum = 0;
                                for (const auto& e : p.exits) {
                                    ASSERT_LE(e.second, 1.0); // each copy's weight is bounded
                                    exitSum += e.second;
                                }
                                ASSERT_EQ(exitSum, p.reflected);
                                splitPaths += p.exits.size() > 1;
                                ASSERT_EQ(p.exited, p.exitR >= 0);
                                if (p.exited) {
                                    ASSERT_GT(p.reflected, 0.0);
                                } else {
                                    ASSERT_EQ(p.reflected, 0.0);
                                }
                                if (albedo == 1.0) {
                                    ASSERT_EQ(p.absorbed, 0.0);
                                }
                                if (est == Estimator::Analog && p.absorbed > 0 &&
                                    levels == 0) { // one copy: absorbed, gone
                                    ASSERT_FALSE(p.exited);
                                }
                                exited += p.exited;
                                ++checked;
                            }
                        }
    EXPECT_EQ(checked, 2 * 2 * 2 * (3 + 2) * 2 * 2000);
    EXPECT_GT(splitPaths, 100); // radial splitting was exercised
    EXPECT_GT(exited, checked / 4);
    EXPECT_GT(truncatedPaths, 100); // the event limit was exercised
}

TEST(Slab, SpecularIsNormalIncidenceFresnel) {
    SlabSettings s;
    const PathRecord p = tracePath(medium(0.9, 0, 1.4), s, 0);
    EXPECT_NEAR(p.specular, (0.4 / 2.4) * (0.4 / 2.4), 1e-16);
    EXPECT_EQ(tracePath(medium(0.9, 0, 1.0), s, 0).specular, 0.0);
}

// Expected energy conservation: E[rouletteLoss] = 0, so specular + R_d + A = 1 within the
// roulette term's standard error (|z| < 4, N = 2·10^5), the run's sums obey the identity, no
// path is truncated at this albedo, and the run's own energy check passes.
TEST(Slab, EnergyConservedInExpectation) {
    for (Estimator est : {Estimator::Implicit, Estimator::Analog}) {
        SlabSettings s;
        s.paths = 200000;
        s.threads = 2;
        s.estimator = est;
        const SlabResult r = runSlab(medium(0.9, 0.9, 1.3), s);
        EXPECT_NEAR(r.specular + r.totalRd + r.absorbed + r.rouletteNet, 1.0, 1e-11);
        EXPECT_EQ(r.truncatedPaths, 0u);
        if (r.rouletteNetStderr > 0) {
            EXPECT_LT(std::fabs(r.rouletteNet) / r.rouletteNetStderr, 4.0);
        }
        EXPECT_EQ(energyProblem(r), "");
        EXPECT_GT(r.totalRd, 0.01);
    }
}

// (c) Determinism: 1, 2 and 3 threads give bitwise the same result as traceSlab on one thread.
TEST(Slab, BitwiseIdenticalForAnyThreadCount) {
    const Medium m = medium(0.95, 0.5, 1.3);
    SlabSettings s;
    s.paths = 5 * kChunkPaths + 777; // a partial last chunk
    s.rMaxMm = 8;
    s.bins = 64;
    s.seed = 2024;
    const SlabResult ref = finalize(traceSlab(m, s, 0, s.paths), s);
    for (int threads : {1, 2, 3}) {
        s.threads = threads;
        SCOPED_TRACE(threads);
        expectBitwiseEqual(runSlab(m, s), ref);
    }
    s.seed = 2025;
    const SlabResult other = runSlab(m, s);
    EXPECT_FALSE(sameBits(other.rd, ref.rd));
    EXPECT_NE(other.totalRd, ref.totalRd);
}

TEST(Slab, TraceSlabIsTheSumOfItsPaths) {
    const Medium m = medium(0.8, 0.3, 1.3);
    SlabSettings s;
    s.bins = 16;
    s.rMaxMm = 4;
    const uint64_t first = 1000, count = 300;
    const SlabTally t = traceSlab(m, s, first, count);
    SlabTally u = makeTally(s);
    for (uint64_t i = first; i < first + count; ++i)
        accumulate(u, tracePath(m, s, i), s, i);
    EXPECT_EQ(t.paths, count);
    EXPECT_TRUE(sameBits(t.binSum, u.binSum));
    ASSERT_EQ(t.batchSum.size(), kBatches * 16u);
    EXPECT_TRUE(sameBits(t.batchSum, u.batchSum)); // path i's terms in batch i mod kBatches
    EXPECT_EQ(t.batchPaths, u.batchPaths);
    EXPECT_TRUE(sameBits(t.binSumSq, u.binSumSq));
    EXPECT_TRUE(sameBits(t.rdSum, u.rdSum));
    EXPECT_TRUE(sameBits(t.absSum, u.absSum));
    EXPECT_EQ(t.events, u.events);

    // merge: the same sums in another order (equal to rounding)
    SlabTally a = traceSlab(m, s, 0, 700), b = traceSlab(m, s, 700, 500),
              all = traceSlab(m, s, 0, 1200);
    a.merge(b);
    EXPECT_EQ(a.paths, all.paths);
    EXPECT_EQ(a.events, all.events);
    EXPECT_NEAR(a.rdSum, all.rdSum, 1e-12 * all.rdSum);
    EXPECT_NEAR(a.absSumSq, all.absSumSq, 1e-12 * all.absSumSq);
    for (size_t i = 0; i < all.binSum.size(); ++i)
        EXPECT_NEAR(a.binSum[i], all.binSum[i], 1e-12 * (1 + all.binSum[i]));
    SlabTally wrong;
    wrong.binSum.assign(3, 0);
    wrong.binSumSq.assign(3, 0);
    wrong.paths = 1;
    EXPECT_THROW(a.merge(wrong), core::Error);
}

TEST(Slab, CancelKeepsTheCompletedPrefix) {
    const Medium m = medium(0.99, 0.0, 1.3);
    SlabSettings s;
    s.paths = 2000000000ull; // far more than can finish before the first progress report
    s.threads = 2;
    std::atomic<bool> cancel{false};
    const auto caller = std::this_thread::get_id();
    int calls = 0;
    bool otherThread = false;
    const SlabResult r = runSlab(
        m, s,
        [&](uint64_t) {
            ++calls;
            otherThread |= std::this_thread::get_id() != caller;
            cancel = true;
        },
        &cancel);
    EXPECT_GE(calls, 1);
    EXPECT_FALSE(otherThread);
    EXPECT_LT(r.paths, s.paths);
    EXPECT_EQ(r.paths % kChunkPaths, 0u);
    // The prefix is exactly what one thread computes for those paths.
    if (r.paths > 0) expectBitwiseEqual(r, finalize(traceSlab(m, s, 0, r.paths), s));

    std::atomic<bool> before{true};
    const SlabResult none = runSlab(m, s, {}, &before);
    EXPECT_EQ(none.paths, 0u);
    EXPECT_EQ(none.totalRd, 0.0);
    EXPECT_TRUE(std::isinf(none.totalRdStderr));
}

TEST(Slab, ProgressRunsOnTheCallingThreadAndEndsWithTheTotal) {
    SlabSettings s;
    s.paths = 3 * kChunkPaths;
    s.threads = 2;
    const auto caller = std::this_thread::get_id();
    std::vector<uint64_t> seen;
    bool otherThread = false;
    runSlab(medium(0.9, 0, 1.3), s, [&](uint64_t done) {
        seen.push_back(done);
        otherThread |= std::this_thread::get_id() != caller;
    });
    ASSERT_FALSE(seen.empty());
    EXPECT_FALSE(otherThread);
    EXPECT_EQ(seen.back(), s.paths);
    for (size_t i = 1; i < seen.size(); ++i)
        EXPECT_LE(seen[i - 1], seen[i]);
}

TEST(Slab, FinalizeFormulas) {
    SlabSettings s;
    s.bins = 2;
    s.rMaxMm = 2;
    SlabTally t = makeTally(s);
    t.paths = 4;
    t.binSum = {1.0, 0.5};
    t.binSumSq = {0.5, 0.25};
    t.rdSum = 1.6;
    t.rdSumSq = 0.8;
    t.specular = 0.02;
    const SlabResult r = finalize(t, s);
    const double pi = std::numbers::pi;
    EXPECT_DOUBLE_EQ(r.rMid[0], 0.5);
    EXPECT_DOUBLE_EQ(r.rMid[1], 1.5);
    EXPECT_DOUBLE_EQ(r.rd[0], 0.25 / pi);        // annulus [0, 1): area π
    EXPECT_DOUBLE_EQ(r.rd[1], 0.125 / (3 * pi)); // annulus [1, 2): area 3π
    EXPECT_DOUBLE_EQ(r.rdStderr[0], std::sqrt((0.5 / 4 - 0.0625) / 3) / pi);
    EXPECT_DOUBLE_EQ(r.rdStderr[1], std::sqrt((0.25 / 4 - 0.125 * 0.125) / 3) / (3 * pi));
    EXPECT_DOUBLE_EQ(r.totalRd, 0.4);
    EXPECT_DOUBLE_EQ(r.totalRdStderr, std::sqrt((0.2 - 0.16) / 3));
    EXPECT_EQ(r.specular, 0.02);
    SlabSettings other = s;
    other.bins = 3;
    EXPECT_THROW(finalize(t, other), core::Error);
}

TEST(Slab, BinOf) {
    SlabSettings s;
    s.rMaxMm = 3;
    s.bins = 30;
    EXPECT_EQ(binOf(0.0, s), 0);
    EXPECT_EQ(binOf(0.15, s), 1);
    EXPECT_EQ(binOf(std::nextafter(3.0, 0.0), s), 29);
    EXPECT_EQ(binOf(3.0, s), -1);
    EXPECT_EQ(binOf(1e300, s), -1);
    EXPECT_EQ(binOf(-1.0, s), -1);
    EXPECT_EQ(binOf(std::numeric_limits<double>::quiet_NaN(), s), -1);
}

// (f) σa = 0 is valid: nothing is absorbed, paths end by leaving or at the event limit, whose
// truncated weight is tallied (the identity holds with it) and reported by the energy check
// when it exceeds the error bar.
TEST(Slab, NoAbsorptionRuns) {
    Medium m;
    m.sigmaA = 0;
    m.sigmaS = 2;
    m.eta = 1.3;
    SlabSettings s;
    s.paths = 20000;
    s.threads = 2;
    const SlabResult r = runSlab(m, s);
    EXPECT_EQ(r.paths, s.paths);
    EXPECT_EQ(r.absorbed, 0.0);
    EXPECT_NEAR(r.specular + r.totalRd + r.truncated + r.rouletteNet, 1.0, 1e-9);
    EXPECT_EQ(r.rouletteNet, 0.0); // the weight stays 1 - R_sp: no roulette
    EXPECT_GT(r.totalRd, 0.5);
    // heavy tail of return times: P(N > n) ~ n^-1/2, so some of 20000 paths pass 2^20 events
    EXPECT_GT(r.truncatedPaths, 0u);
    EXPECT_GT(r.truncated, r.totalRdStderr);
    EXPECT_NE(energyProblem(r).find("truncated"), std::string::npos) << energyProblem(r);
    // a lower limit truncates more
    s.termination.maxEvents = 1000;
    const SlabResult low = runSlab(m, s);
    EXPECT_GT(low.truncated, r.truncated);
    EXPECT_NEAR(low.specular + low.totalRd + low.truncated, 1.0, 1e-9);
}

// The energy check's three failures, on a run's result altered by hand: broken accounting, a
// biased roulette (the long-path roulette's signature: mean change many σ from 0), truncated
// weight above the error bar. The untouched result passes.
TEST(Slab, EnergyCheckNamesEachFailure) {
    SlabSettings s;
    s.paths = 20000;
    s.threads = 2;
    const SlabResult r = runSlab(medium(0.9, 0.0, 1.3), s);
    ASSERT_EQ(energyProblem(r), "");
    SlabResult bad = r;
    bad.absorbed += 1e-3;
    EXPECT_NE(energyProblem(bad).find("energy check failed: specular + R_d"), std::string::npos)
        << energyProblem(bad);
    bad = r;
    bad.rouletteNet = 6 * r.rouletteNetStderr;
    bad.totalRd -= bad.rouletteNet - r.rouletteNet; // keep the identity
    EXPECT_NE(energyProblem(bad).find("roulette is biased"), std::string::npos)
        << energyProblem(bad);
    bad = r;
    bad.truncated = 2 * r.totalRdStderr;
    bad.truncatedPaths = 3;
    bad.totalRd -= bad.truncated;
    EXPECT_NE(energyProblem(bad).find("3 paths truncated"), std::string::npos)
        << energyProblem(bad);
}
