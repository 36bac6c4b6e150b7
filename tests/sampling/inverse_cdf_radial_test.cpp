// sampling/inverse_cdf_radial: a radial distribution from its inverse CDF at knots (a model's
// analytic sampler evaluated on a grid), here the closed-form inverse of a truncated planar
// Gaussian. sample(), pdfArea() and cdf() are one distribution (cdf(sample(u)) = u to 1e-12, the
// pdf integrates exactly to 1 and is the derivative of the cdf), it is the Gaussian's CDF at
// every knot and its density within 1e-3 in the bulk, 10^6 samples pass a chi-square test
// against its own pdf (p > 1e-3), repeated radii are merged, and bad knots are refused.
#include "sampling_support.h"

#include "core/core.h"
#include "pathtrace/rng.h"
#include "sampling/gaussian_lobes.h"
#include "sampling/inverse_cdf_radial.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace sampling;
using namespace samplingtest;

namespace {
constexpr double kV = 2.0, kLoss = 1e-4; // variance (mm²), energy beyond R_m
const double kRm = std::sqrt(2 * kV * std::log(1 / kLoss));

double gaussianCdf(double r) {
    return -std::expm1(-r * r / (2 * kV)) / (1 - kLoss);
}
double gaussianInverse(double u) {
    return std::sqrt(-2 * kV * std::log1p(-u * (1 - kLoss)));
}
std::vector<double> knots(int cells) {
    std::vector<double> r;
    for (int j = 0; j <= cells; ++j)
        r.push_back(std::min(gaussianInverse(double(j) / cells), kRm));
    return r;
}
TabulatedRadial gaussianTable() {
    const std::vector<double> radii = profileGridRadii(10 * std::sqrt(kV), 4096);
    std::vector<double> v;
    for (double r : radii)
        v.push_back(gaussian2d(kV, r));
    return TabulatedRadial(radii, v);
}
} // namespace

TEST(InverseCdfRadial, SamplePdfAndCdfAreOneDistribution) {
    const std::vector<double> k = knots(4096);
    const InverseCdfRadial d(k, kRm, gaussianTable());
    EXPECT_EQ(d.annuli(), 4096u);
    EXPECT_EQ(d.radiusMax(), kRm);
    for (int i = 0; i <= 2000; ++i) {
        const double u = i < 2000 ? i / 2000.0 : 1 - 0x1p-53;
        EXPECT_NEAR(d.cdf(d.sample(u)), u, 1e-12) << u;
    }
    for (size_t j = 0; j < k.size(); j += 97)
        EXPECT_NEAR(d.cdf(k[j]), double(j) / 4096, 1e-12);
    // ∫ pdfRadius dr = 1 exactly: 2πr·const on each annulus, 3-point Gauss–Legendre per annulus
    EXPECT_NEAR(integratePieces([&](double r) { return d.pdfRadius(r); }, 0, kRm, k), 1.0, 1e-12);
    // the pdf is the derivative of the cdf inside each annulus
    for (size_t j = 1; j + 1 < k.size(); j += 131) {
        const double r = 0.5 * (k[j] + k[j + 1]), h = 1e-3 * (k[j + 1] - k[j]);
        EXPECT_NEAR((d.cdf(r + h) - d.cdf(r - h)) / (2 * h) / d.pdfRadius(r), 1.0, 1e-6) << r;
    }
    EXPECT_EQ(d.pdfArea(kRm * (1 + 1e-12)), 0.0);
    EXPECT_EQ(d.pdfArea(-1.0), 0.0);
    EXPECT_TRUE(std::isfinite(d.pdfArea(0.0)));
    // profile and energies come from the table
    EXPECT_NEAR(d.totalEnergy(), 1.0, 1e-5);
    EXPECT_NEAR(d.keptEnergy(), 1 - kLoss, 1e-5);
    EXPECT_NEAR(d.profile(1.0), gaussian2d(kV, 1.0), 1e-6);
}

TEST(InverseCdfRadial, FollowsTheAnalyticSamplerInTheBulk) {
    const InverseCdfRadial d(knots(65536), kRm, gaussianTable());
    for (double u = 0.01; u < 0.99; u += 0.01) {
        const double r = gaussianInverse(u);
        EXPECT_NEAR(d.sample(u) / r, 1.0, 1e-6) << u;
        EXPECT_NEAR(d.cdf(r), gaussianCdf(r), 1e-8) << u; // linear in r² between knots
        const double want = gaussian2d(kV, r) / (1 - kLoss);
        EXPECT_NEAR(d.pdfArea(r) / want, 1.0, 1e-3) << u;
    }
}

TEST(InverseCdfRadial, ChiSquare) {
    const InverseCdfRadial d(knots(4096), kRm, gaussianTable());
    const int n = 1000000, bins = 200;
    pathtrace::Pcg32 rng = pathtrace::Pcg32::forPath(311, 0);
    std::vector<double> obs(bins, 0), exp(bins, 0);
    for (int i = 0; i < n; ++i)
        obs[std::min(bins - 1, int(std::sqrt(d.sample(rng.uniform()) / kRm) * bins))] += 1;
    for (int b = 0; b < bins; ++b)
        exp[b] = n * (d.cdf(kRm * std::pow((b + 1.0) / bins, 2)) -
                      d.cdf(kRm * std::pow(double(b) / bins, 2)));
    const auto chi = pttest::chiSquare(obs, exp);
    EXPECT_GT(chi.pValue, 1e-3) << "chi2 " << chi.stat << " dof " << chi.dof;
    EXPECT_GE(chi.dof, 100);
}

TEST(InverseCdfRadial, RepeatedRadiiAreMerged) {
    // ξ = 0, 1/4, 1/2, 3/4, 1 at r = 0, 1, 1, 2, 2: annuli [0, 1] (ξ 0 … 1/4), [1, 2] (1/4 … 1)
    const InverseCdfRadial d({0, 1, 1, 2, 2}, 2.5, gaussianTable());
    EXPECT_EQ(d.annuli(), 2u);
    EXPECT_NEAR(d.cdf(1.0), 0.25, 1e-15);
    EXPECT_NEAR(d.pdfArea(0.5), 0.25 / std::numbers::pi, 1e-15);
    EXPECT_NEAR(d.pdfArea(1.5), 0.75 / (3 * std::numbers::pi), 1e-15);
    for (double u : {0.0, 0.1, 0.3, 0.6, 0.9, 1.0})
        EXPECT_NEAR(d.cdf(d.sample(u)), u, 1e-14) << u;
    EXPECT_EQ(d.sample(1.0), 2.0);
    EXPECT_EQ(d.pdfArea(2.2), 0.0); // between ρ_J and R_m
}

TEST(InverseCdfRadial, BadKnotsAreRefused) {
    const TabulatedRadial t = gaussianTable();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NE(errorOf([&] { InverseCdfRadial({0.0}, 1, t, 1, "s"); }).find("at least 2"),
              std::string::npos);
    EXPECT_NE(errorOf([&] {
                  InverseCdfRadial({0, nan, 1}, 1, t, 1, "s");
              }).find("s: channel 1: radius 1 must be finite and >= 0"),
              std::string::npos);
    EXPECT_NE(errorOf([&] {
                  InverseCdfRadial({0, -1, 1}, 1, t);
              }).find("radius 1 must be"),
              std::string::npos);
    EXPECT_NE(errorOf([&] {
                  InverseCdfRadial({0, 1, 2}, 1.5, t);
              }).find("R_m (1.5)"),
              std::string::npos);
    EXPECT_NE(errorOf([&] {
                  InverseCdfRadial({1, 1, 1}, 1, t);
              }).find("every radius is 1"),
              std::string::npos);
}
