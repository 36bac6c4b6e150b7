// pathtrace/sampling.h: HG sampling by chi-square against its pdf (p-value threshold 1e-3 per
// g, 10^6 samples, 100 bins in cos θ), the CDF used for the expected counts against direct
// quadrature of the pdf, the direction frame (unit length, requested polar angle, uniform
// azimuth), the uniform-sphere sampler and the free-flight distance.
#include "pathtrace/sampling.h"
#include "stats.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace pathtrace;

namespace {
double simpson(double g, double a, double b) {
    const double m = 0.5 * (a + b);
    return (b - a) / 6 * (hgPdfCos(g, a) + 4 * hgPdfCos(g, m) + hgPdfCos(g, b));
}
double adaptive(double g, double a, double b, double whole, double tol, int depth) {
    const double m = 0.5 * (a + b), l = simpson(g, a, m), r = simpson(g, m, b);
    if (depth > 50 || std::fabs(l + r - whole) < 15 * tol) return l + r + (l + r - whole) / 15;
    return adaptive(g, a, m, l, tol / 2, depth + 1) + adaptive(g, m, b, r, tol / 2, depth + 1);
}
// ∫_{-1}^{c} pdf by adaptive Simpson (independent of hgCdfCos).
double cdfByQuadrature(double g, double c) {
    return adaptive(g, -1, c, simpson(g, -1, c), 1e-13, 0);
}
} // namespace

TEST(Sampling, HgCdfMatchesQuadratureOfPdf) {
    for (double g : {0.0, 0.3, -0.7, 0.95, 1e-9})
        for (double c : {-1.0, -0.5, 0.0, 0.4, 0.9, 0.99, 1.0})
            EXPECT_NEAR(hgCdfCos(g, c), cdfByQuadrature(g, c), 1e-9) << "g " << g << " c " << c;
}

TEST(Sampling, HgInversionIsTheCdfInverse) {
    for (double g : {0.0, 1e-12, 1e-6, 0.3, -0.7, 0.95, -0.999})
        for (double xi : {0.0, 1e-9, 0.1, 0.5, 0.77, 0.999999}) {
            const double c = sampleHgCos(g, xi);
            EXPECT_GE(c, -1.0);
            EXPECT_LE(c, 1.0);
            EXPECT_NEAR(hgCdfCos(g, c), xi, 1e-9) << "g " << g << " xi " << xi;
        }
    EXPECT_EQ(sampleHgCos(0.0, 0.25), -0.5); // g = 0: cos θ = 2ξ − 1 exactly
    EXPECT_EQ(sampleHgCos(0.5, 0.0), -1.0);
}

// Chi-square, 100 equal bins in cos θ, expected counts from the exact CDF, 10^6 samples.
// Threshold p > 1e-3 (a correct sampler fails with probability 1e-3 per g and seed).
TEST(Sampling, HgChiSquare) {
    const int bins = 100, n = 1000000;
    for (double g : {0.0, 0.3, -0.7, 0.95}) {
        Pcg32 rng = Pcg32::forPath(11, uint64_t(1000 * (g + 1)));
        std::vector<double> obs(bins, 0), exp(bins);
        for (int i = 0; i < n; ++i) {
            const double c = sampleHgCos(g, rng.uniform32());
            obs[std::min(bins - 1, int((c + 1) * 0.5 * bins))] += 1;
        }
        for (int b = 0; b < bins; ++b)
            exp[b] =
                n * (hgCdfCos(g, -1 + 2.0 * (b + 1) / bins) - hgCdfCos(g, -1 + 2.0 * b / bins));
        const auto chi = pttest::chiSquare(obs, exp);
        EXPECT_GT(chi.pValue, 1e-3) << "g " << g << " chi2 " << chi.stat << " dof " << chi.dof;
        EXPECT_GE(chi.dof, 90);
    }
}

TEST(Sampling, HgChiSquareDetectsAWrongG) {
    // Power check: samples for g = 0.3 tested against g = 0.31 must be rejected.
    const int bins = 100, n = 1000000;
    Pcg32 rng = Pcg32::forPath(12, 0);
    std::vector<double> obs(bins, 0), exp(bins);
    for (int i = 0; i < n; ++i)
        obs[std::min(bins - 1, int((sampleHgCos(0.3, rng.uniform32()) + 1) * 0.5 * bins))] += 1;
    for (int b = 0; b < bins; ++b)
        exp[b] =
            n * (hgCdfCos(0.31, -1 + 2.0 * (b + 1) / bins) - hgCdfCos(0.31, -1 + 2.0 * b / bins));
    EXPECT_LT(pttest::chiSquare(obs, exp).pValue, 1e-6);
}

TEST(Sampling, RotateKeepsUnitLengthAndPolarAngle) {
    Pcg32 rng = Pcg32::forPath(3, 3);
    const Dir fixed[] = {{0, 0, -1}, {0, 0, 1}, {1, 0, 0}, {0.6, 0, 0.8}, {0, -0.8, -0.6}};
    for (const Dir& u : fixed)
        for (int i = 0; i < 2000; ++i) {
            const double c = 2 * rng.uniform() - 1;
            double cp, sp;
            sampleAzimuth(rng, cp, sp);
            const Dir v = rotateDir(u, c, cp, sp);
            EXPECT_NEAR(v.x * v.x + v.y * v.y + v.z * v.z, 1.0, 1e-14);
            EXPECT_NEAR(v.x * u.x + v.y * u.y + v.z * u.z, c, 1e-14);
        }
    // The pole case keeps the sign of cos θ relative to u (u = −z, backward scattering → +z).
    const Dir back = rotateDir({0, 0, -1}, -0.5, 1, 0);
    EXPECT_NEAR(back.z, 0.5, 1e-15);
}

TEST(Sampling, ScatteredAzimuthIsUniform) {
    // Azimuth of scatterHg's output about u, in a frame (e1, e2, u): 36 bins, p > 1e-3.
    const Dir u{0.48, -0.6, 0.64};
    const double n1 = std::sqrt(0.6 * 0.6 + 0.48 * 0.48);
    const Dir e1{0.6 / n1, 0.48 / n1, 0.0}; // ⟂ u
    const Dir e2{u.y * e1.z - u.z * e1.y, u.z * e1.x - u.x * e1.z, u.x * e1.y - u.y * e1.x};
    Pcg32 rng = Pcg32::forPath(4, 4);
    const int bins = 36, n = 360000;
    std::vector<double> obs(bins, 0), exp(bins, double(n) / bins), cosObs(50, 0), cosExp(50);
    for (int i = 0; i < n; ++i) {
        const Dir v = scatterHg(u, 0.6, rng);
        const double a = v.x * e1.x + v.y * e1.y + v.z * e1.z;
        const double b = v.x * e2.x + v.y * e2.y + v.z * e2.z;
        const double phi = std::atan2(b, a) + std::numbers::pi;
        obs[std::min(bins - 1, int(phi / (2 * std::numbers::pi) * bins))] += 1;
        const double c = v.x * u.x + v.y * u.y + v.z * u.z;
        cosObs[std::min(49, int((c + 1) * 25))] += 1;
    }
    for (int b = 0; b < 50; ++b)
        cosExp[b] = n * (hgCdfCos(0.6, -1 + (b + 1) / 25.0) - hgCdfCos(0.6, -1 + b / 25.0));
    EXPECT_GT(pttest::chiSquare(obs, exp).pValue, 1e-3);
    EXPECT_GT(pttest::chiSquare(cosObs, cosExp).pValue, 1e-3);
}

TEST(Sampling, SphereIsUniform) {
    // z uniform in [−1, 1] and azimuth uniform (Archimedes): 50 × 36 cells, p > 1e-3.
    Pcg32 rng = Pcg32::forPath(5, 5);
    const int nz = 50, nphi = 36, n = 1800000;
    std::vector<double> obs(nz * nphi, 0), exp(nz * nphi, double(n) / (nz * nphi));
    for (int i = 0; i < n; ++i) {
        const Dir v = sampleSphere(rng);
        ASSERT_NEAR(v.x * v.x + v.y * v.y + v.z * v.z, 1.0, 1e-14);
        const double phi = std::atan2(v.y, v.x) + std::numbers::pi;
        const int iz = std::min(nz - 1, int((v.z + 1) * 0.5 * nz));
        const int ip = std::min(nphi - 1, int(phi / (2 * std::numbers::pi) * nphi));
        obs[iz * nphi + ip] += 1;
    }
    EXPECT_GT(pttest::chiSquare(obs, exp).pValue, 1e-3);
}

TEST(Sampling, DistanceIsExponential) {
    // P(s > t) = e^{−σt t}: e^{−σt s} must be uniform; 100 bins, p > 1e-3; and mean 1/σt.
    Pcg32 rng = Pcg32::forPath(6, 6);
    const double sigmaT = 2.5;
    const int bins = 100, n = 1000000;
    std::vector<double> obs(bins, 0), exp(bins, double(n) / bins);
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        const double s = sampleDistance(sigmaT, rng.uniform());
        ASSERT_TRUE(s >= 0 && std::isfinite(s));
        sum += s;
        obs[std::min(bins - 1, int(std::exp(-sigmaT * s) * bins))] += 1;
    }
    EXPECT_GT(pttest::chiSquare(obs, exp).pValue, 1e-3);
    // mean: stderr (1/σt)/√n; |z| < 4
    EXPECT_LT(std::fabs(sum / n - 1 / sigmaT) / (1 / sigmaT / std::sqrt(double(n))), 4.0);
    EXPECT_EQ(sampleDistance(sigmaT, 0.0), 0.0);
}
