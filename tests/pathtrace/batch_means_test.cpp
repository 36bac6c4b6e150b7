// Batch means of the slab walk (pathtrace.h, kBatches) and rel_err's standard error from them
// (core/relative_error.h). rel_err sums over bins; with actual exits a path leaves through one
// bin, so the bins are negatively correlated (one path's exit is another bin's absence) and the
// independent-bins formula overstates the error; with expected-value exits a path adds to
// many bins, they are positively correlated and the formula understates it. The batches' spread
// counts the covariance either way. Checked against what the standard error means: the spread of
// rel_err over independent runs (different seeds) of the same reference, for a fixed model 8 %
// above the truth (so the linear term, where the covariance enters, dominates), with actual
// exits and with 2 and 8 expected-value exit samples. Each reference has 40 000 paths: with the
// escape cone's directions (g 0 here) and 2 samples, references of 20 000 paths on these 360 fine
// bins spread 1.43x their batch figure, and 80 000 paths 1.02x; the gap is the part of rel_err
// that is quadratic in each bin's noise, which the linear error leaves out and which falls
// faster than it as the paths grow.
#include "core/relative_error.h"
#include "pathtrace/pathtrace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace batchmeans {

using namespace pathtrace;

Medium medium() {
    return Medium{0.1, 1.0, 0.0, 1.3}; // l_d = 1.74 mm: short paths
}

double ld() {
    const Medium m = medium();
    return 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS));
}

// The scoring grid (pipeline/scoring.cpp: 360 bins over 4.5 l_d) and the default splitting;
// with 8 samples the expected-value exits score every collision within 5 mfp.
SlabSettings settings(uint64_t seed, uint64_t paths, int exitSamples) {
    SlabSettings s;
    s.rMaxMm = 4.5 * ld();
    s.bins = 360;
    s.exits.depthMfp = exitSamples > 2 ? 5.0 : 2.0;
    s.paths = paths;
    s.seed = seed;
    s.exits.samples = exitSamples;
    return s;
}

std::vector<double> edgesOf(const SlabSettings& s) {
    std::vector<double> e;
    for (int i = 0; i <= s.bins; ++i)
        e.push_back(s.rMaxMm * i / s.bins);
    return e;
}

struct Spread {
    double sd = 0, batchSe = 0, independentSe = 0; // over the runs: sd of e, mean reported se
};

// rel_err of `model` against `runs` references of `paths` paths each.
Spread spreadOf(const std::vector<double>& model, int runs, uint64_t paths, int exitSamples) {
    std::vector<double> e;
    Spread out;
    for (int k = 0; k < runs; ++k) {
        const SlabSettings s = settings(100 + uint64_t(k), paths, exitSamples);
        const SlabResult r = runSlab(medium(), s);
        EXPECT_FALSE(r.rdBatches.empty());
        const auto edges = edgesOf(s);
        const core::RelativeError b = core::radialRelativeError(edges, r.rd, r.rdStderr, model,
                                                                0.1 * ld(), 4 * ld(), r.rdBatches);
        const core::RelativeError i =
            core::radialRelativeError(edges, r.rd, r.rdStderr, model, 0.1 * ld(), 4 * ld());
        EXPECT_TRUE(b.valid() && i.valid()) << b.problem << i.problem;
        EXPECT_EQ(b.value, i.value); // the batches change the error bar only
        e.push_back(b.value);
        out.batchSe += b.se / runs;
        out.independentSe += i.se / runs;
    }
    double mean = 0, ss = 0;
    for (double x : e)
        mean += x / runs;
    for (double x : e)
        ss += (x - mean) * (x - mean);
    out.sd = std::sqrt(ss / (runs - 1));
    return out;
}

TEST(BatchMeans, AreThePathsOfEachBatchAndAverageToTheMean) {
    const SlabSettings s = settings(7, 5000, 2);
    const SlabResult r = runSlab(medium(), s);
    ASSERT_EQ(r.rdBatches.fraction.size(), kBatches);
    double total = 0;
    for (double f : r.rdBatches.fraction)
        total += f;
    EXPECT_NEAR(total, 1.0, 1e-12);
    EXPECT_DOUBLE_EQ(r.rdBatches.fraction[0], 157.0 / 5000); // 5000 = 32·156 + 8
    EXPECT_DOUBLE_EQ(r.rdBatches.fraction[31], 156.0 / 5000);
    for (size_t i = 0; i < r.rd.size(); ++i) {
        double m = 0;
        for (size_t b = 0; b < kBatches; ++b)
            m += r.rdBatches.fraction[b] * r.rdBatches.mean[b][i];
        EXPECT_NEAR(m, r.rd[i], 1e-12 * r.rd[0]) << i;
    }
    // the same for any thread count (paths are batched by index)
    SlabSettings one = s;
    one.threads = 1;
    EXPECT_EQ(runSlab(medium(), one).rdBatches.mean, r.rdBatches.mean);
    // fewer paths than 2 per batch: no batch means (the bins are then taken as independent)
    EXPECT_TRUE(runSlab(medium(), settings(7, 40, 0)).rdBatches.empty());
}

TEST(BatchMeans, RelErrStandardErrorMatchesTheSpreadOfIndependentRuns) {
    // the "model": a long run, 8 % high
    SlabResult truth = runSlab(medium(), settings(1, 400000, 2));
    std::vector<double> model;
    for (double x : truth.rd)
        model.push_back(1.08 * x);
    const int runs = 24; // the sd of the runs' sd is 1/√(2·23) = 15 % of it: ±3 of those
    const double band = 3 * std::sqrt(1.0 / (2.0 * (runs - 1)));
    for (const int samples : {0, 2, 8}) {
        SCOPED_TRACE("exit samples " + std::to_string(samples));
        const Spread s = spreadOf(model, runs, 40000, samples);
        std::printf("exit samples %d: spread of rel_err %.3g; reported se from batches %.3g "
                    "(spread/se %.2f), as independent bins %.3g (%.2f)\n",
                    samples, s.sd, s.batchSe, s.sd / s.batchSe, s.independentSe,
                    s.sd / s.independentSe);
        EXPECT_LT(std::fabs(s.sd / s.batchSe - 1.0), band) << "spread / batch se";
        // a path that scores many bins makes them positively correlated: the independent-bins
        // formula then understates the error (measured: spread 1.5× its figure, 1.0× the
        // batches')
        if (samples == 8) {
            EXPECT_GT(s.batchSe, 1.25 * s.independentSe);
        }
    }
}

} // namespace batchmeans
