// rel_err (core/relative_error.h) against closed forms: a constant relative offset, a relative
// error linear in ln r (e = k ln(b/a)/√3 on any grid), the noise correction (a model equal to
// the truth scores 0 in expectation, and the stated standard error is the observed spread).
#include "core/relative_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

// Uniform bins of width (to - 0)/n from 0: the slab tracer's grid.
std::vector<double> uniformEdges(double rMax, int n) {
    std::vector<double> e(size_t(n) + 1);
    for (int i = 0; i <= n; ++i)
        e[size_t(i)] = rMax * i / n;
    return e;
}

// Exact bin averages ∫ f r dr / ∫ r dr of f(r) = r^-2 (the reference) and the nodes' average of
// the model f(r)(1 + k ln(r/a)).
struct Profiles {
    std::vector<double> ref, se, model;
};
Profiles linearInLog(const std::vector<double>& edges, double a, double k) {
    Profiles p;
    for (size_t i = 0; i + 1 < edges.size(); ++i) {
        const double lo = edges[i], hi = edges[i + 1];
        p.ref.push_back(lo > 0 ? std::log(hi / lo) / (0.5 * (hi * hi - lo * lo)) : 1e9);
        p.se.push_back(0);
        const core::BinNodes n = core::areaAverageNodes(lo, hi);
        double m = 0;
        for (int j = 0; j < 4; ++j)
            m += n.w[size_t(j)] * (1 + k * std::log(n.r[size_t(j)] / a)) /
                 (n.r[size_t(j)] * n.r[size_t(j)]);
        p.model.push_back(m);
    }
    return p;
}

} // namespace

TEST(RelativeError, ConstantOffsetIsItsSize) {
    const std::vector<double> edges = uniformEdges(4.5, 90);
    std::vector<double> ref(90), se(90, 0.0), model(90);
    for (size_t i = 0; i < 90; ++i) {
        ref[i] = std::exp(-double(i) / 10);
        model[i] = 0.93 * ref[i];
    }
    const core::RelativeError e = core::radialRelativeError(edges, ref, se, model, 0.1, 4.0);
    ASSERT_TRUE(e.valid()) << e.problem;
    EXPECT_NEAR(e.value, 0.07, 1e-12);
    EXPECT_EQ(e.se, 0.0);
}

TEST(RelativeError, LinearInLogRadiusMatchesTheClosedFormOnEveryGrid) {
    // (M/R − 1) = k ln(r/a) on [a, b]: e² = k² ln²(b/a) / 3
    const double a = 0.1, b = 4.0, k = 0.05, exact = k * std::log(b / a) / std::sqrt(3.0);
    for (int bins : {90, 180, 450, 1000}) {
        const std::vector<double> edges = uniformEdges(4.5, bins);
        const Profiles p = linearInLog(edges, a, k);
        const core::RelativeError e = core::radialRelativeError(edges, p.ref, p.se, p.model, a, b);
        ASSERT_TRUE(e.valid()) << e.problem;
        // bins of 0.05 (half the lower bound) are coarse in ln r near a: within 2 %
        EXPECT_NEAR(e.value, exact, (bins >= 450 ? 0.002 : 0.02) * exact) << bins << " bins";
    }
    // the lower bound moved by one fine bin: the integral over the shorter range,
    // e² = k² (L³ − l³) / (3(L − l)) with L = ln(b/a), l = ln(a'/a)
    const std::vector<double> edges = uniformEdges(4.5, 450);
    const Profiles p = linearInLog(edges, a, k);
    const double L = std::log(b / a), l = std::log((a + 0.01) / a);
    const double moved = k * std::sqrt((L * L * L - l * l * l) / (3 * (L - l)));
    EXPECT_NEAR(core::radialRelativeError(edges, p.ref, p.se, p.model, a + 0.01, b).value, moved,
                0.002 * moved);
}

TEST(RelativeError, NoiseOfTheReferenceIsRemovedAndTheStandardErrorIsItsSpread) {
    // 200 bins of reference with 4 % noise each; the model is the truth, then the truth + 3 %
    std::mt19937_64 rng(7);
    std::normal_distribution<double> z;
    const int trials = 400, n = 200;
    for (double offset : {0.0, 0.03}) {
        double sum = 0, sumSq = 0, seSum = 0, e2Sum = 0;
        for (int t = 0; t < trials; ++t) {
            std::vector<core::ErrorBin> bins(static_cast<size_t>(n));
            for (int i = 0; i < n; ++i) {
                const double truth = std::exp(-0.02 * i), s = 0.04 * truth;
                bins[size_t(i)] = {1.0, truth * (1 + offset), truth + s * z(rng), s, {}};
            }
            const core::RelativeError e = core::relativeError(bins);
            ASSERT_TRUE(e.valid());
            sum += e.value;
            sumSq += e.value * e.value;
            seSum += e.se;
            // the unclamped e² is unbiased: recompute it from the definition
            double e2 = 0;
            for (const auto& bin : bins) {
                const double x = bin.model / bin.ref, c = bin.refSe / bin.ref;
                e2 += ((x - 1) * (x - 1) - c * c * (3 * x * x - 2 * x)) / n;
            }
            e2Sum += e2;
        }
        const double mean = sum / trials, sd = std::sqrt(sumSq / trials - mean * mean);
        // the noise-corrected e² averages to offset² (its uncorrected mean would be
        // offset² + 0.04² = 16e-4 above 0 for the truth)
        EXPECT_NEAR(e2Sum / trials, offset * offset, 1e-4) << offset;
        if (offset > 0) {
            EXPECT_NEAR(mean, offset, 4 * sd / std::sqrt(double(trials)));
            // the stated standard error is the observed spread within 15 %
            EXPECT_NEAR(seSum / trials / sd, 1.0, 0.15);
        } else {
            EXPECT_LT(mean, 0.01);         // against 0.04 uncorrected
            EXPECT_GT(seSum / trials, sd); // at 0, where e is not Gaussian: conservative
        }
    }
}

// With batch means the linear part's variance is the batches' spread, so the bins' covariance
// counts: 40 bins whose batches all move together (one path lifting every bin) give √40 times
// the independent-bins error; bins whose batches move against each other in pairs cancel in
// the sum, leaving only the χ² part. Exact arithmetic on constructed batches (32, ±5 %).
TEST(RelativeError, BatchMeansCarryTheBinsCovariance) {
    const size_t n = 40, B = 32;
    const std::vector<double> fraction(B, 1.0 / B);
    auto bins = [&](bool together) {
        std::vector<core::ErrorBin> out(n);
        for (size_t i = 0; i < n; ++i) {
            const double truth = std::exp(-0.05 * double(i));
            core::ErrorBin& b = out[i];
            b.weight = 1;
            b.model = 1.1 * truth;
            b.ref = truth;
            // batch j: +5 % for even j, −5 % for odd (the mean stays `truth`); the bins move
            // together, or bin pairs (2k, 2k+1) against each other
            for (size_t j = 0; j < B; ++j) {
                const double sign = (j % 2 ? -1.0 : 1.0) * (together || i % 2 == 0 ? 1.0 : -1.0);
                b.batch.push_back(truth * (1 + 0.05 * sign));
            }
            b.refSe = 0.05 * truth / std::sqrt(double(B - 1)); // each bin's own spread
        }
        return out;
    };
    const core::RelativeError independent = core::relativeError(bins(true));
    const core::RelativeError together = core::relativeError(bins(true), fraction);
    const core::RelativeError against = core::relativeError(bins(false), fraction);
    EXPECT_DOUBLE_EQ(together.value, independent.value); // the errors, not the value
    EXPECT_NEAR(together.se / independent.se, std::sqrt(double(n)), 0.05 * std::sqrt(double(n)));
    EXPECT_LT(against.se, 0.2 * independent.se);
    // batches missing from a bin, or fewer than two: the independent-bins figure
    std::vector<core::ErrorBin> partial = bins(true);
    partial[3].batch.clear();
    EXPECT_DOUBLE_EQ(core::relativeError(partial, fraction).se, independent.se);
    EXPECT_DOUBLE_EQ(core::relativeError(bins(true), {1.0}).se, independent.se);
}

TEST(RelativeError, BinsWithoutPathsAreMergedWithTheirNeighbours) {
    // a model 5 % high everywhere: merged bins keep the ratio, so e stays 0.05 exactly
    const std::vector<double> edges = uniformEdges(4.5, 90);
    std::vector<double> ref(90), se(90, 0.0), model(90);
    for (size_t i = 0; i < 90; ++i) {
        ref[i] = std::exp(-double(i) / 10);
        model[i] = 1.05 * ref[i];
    }
    ref[40] = ref[41] = 0; // no paths at r = 2 to 2.1: merged with the bin at 2.1
    ref[79] = 0;           // the last bin of [0.1, 4]: merged with the one before
    ref[85] = 0;           // outside the range: ignored
    const core::RelativeError e = core::radialRelativeError(edges, ref, se, model, 0.1, 4.0);
    ASSERT_TRUE(e.valid()) << e.problem;
    // the merged bins' ratio is the models' area-weighted mean over the references' (whose empty
    // bins add 0): x over r = 2 to 2.15, y over 3.9 to 4; the rest is 1.05
    auto area = [&](size_t i) { return edges[i + 1] * edges[i + 1] - edges[i] * edges[i]; };
    const double x = (1.05 * (std::exp(-4.0) * area(40) + std::exp(-4.1) * area(41) +
                              std::exp(-4.2) * area(42))) /
                     (std::exp(-4.2) * area(42));
    const double y = (1.05 * (std::exp(-7.8) * area(78) + std::exp(-7.9) * area(79))) /
                     (std::exp(-7.8) * area(78));
    const double L = std::log(40.0);
    const double w3 = std::log(2.15 / 2.0), w2 = std::log(4.0 / 3.9);
    const double expected = std::sqrt(
        ((L - w3 - w2) * 0.05 * 0.05 + w3 * (x - 1) * (x - 1) + w2 * (y - 1) * (y - 1)) / L);
    EXPECT_NEAR(e.value, expected, 1e-12);
    // a range without any paths is the one problem, named by its radii
    std::vector<double> none(90, 0.0);
    const core::RelativeError bad = core::radialRelativeError(edges, none, se, model, 0.1, 4.0);
    EXPECT_FALSE(bad.valid());
    EXPECT_NE(bad.problem.find("no paths"), std::string::npos) << bad.problem;
    EXPECT_NE(bad.problem.find("r = 0.1 to 4"), std::string::npos) << bad.problem;
    EXPECT_TRUE(std::isnan(bad.value));
    model[40] = NAN;
    EXPECT_NE(core::radialRelativeError(edges, ref, se, model, 0.1, 4.0).problem.find("not finite"),
              std::string::npos);
    EXPECT_THROW(core::radialRelativeError(edges, ref, se, {1.0}, 0.1, 4.0), std::exception);
}

TEST(RelativeError, SeriesWeighTheirBinsAndMergeApart) {
    // two profiles 5 % and 20 % off, weights 3 and 1: e² = (3 · 0.05² + 1 · 0.2²) / 4; the second
    // has no paths beyond r = 2, merged within itself only
    const std::vector<double> edges = uniformEdges(4.5, 90);
    core::RadialSeries a, b;
    a.weight = 3;
    b.weight = 1;
    for (size_t i = 0; i < 90; ++i) {
        const double r = std::exp(-double(i) / 10);
        a.ref.push_back(r);
        a.refSe.push_back(0);
        a.model.push_back(1.05 * r);
        b.ref.push_back(i < 40 ? r : 0.0);
        b.refSe.push_back(0);
        b.model.push_back(i < 40 ? 1.2 * r : 0.0);
    }
    const core::RelativeError e = core::radialRelativeError(edges, {a, b}, 0.1, 4.0);
    ASSERT_TRUE(e.valid()) << e.problem;
    EXPECT_NEAR(e.value, std::sqrt((3 * 0.0025 + 1 * 0.04) / 4), 1e-12);
}

TEST(RelativeError, AreaAverageNodesIntegratePolynomialsExactly) {
    for (auto [lo, hi] : {std::pair{0.0, 0.05}, std::pair{0.1, 0.15}, std::pair{3.0, 7.5}}) {
        const core::BinNodes n = core::areaAverageNodes(lo, hi);
        for (int p = 0; p <= 5; ++p) { // ∫ r^p r dr / ∫ r dr, degree p + 1 <= 7
            double q = 0;
            for (int k = 0; k < 4; ++k)
                q += n.w[size_t(k)] * std::pow(n.r[size_t(k)], p);
            const double exact =
                (std::pow(hi, p + 2) - std::pow(lo, p + 2)) / (p + 2) / (0.5 * (hi * hi - lo * lo));
            EXPECT_NEAR(q, exact, 1e-12 * std::max(1.0, exact)) << lo << " " << p;
        }
    }
}
