// half_space_reference.h, the deterministic half-space R_d the tracer is validated against,
// checked with things not written with it:
//   - its building blocks: the Gauss–Radau rule (exact to degree 2n − 2, node at 1) and the
//     closed-form azimuthal HG kernel against the Legendre series Σ (2l + 1) gˡ P_l(μ) P_l(μ′)
//     and against a brute-force azimuth quadrature;
//   - η = 1, g = 0: Chandrasekhar's plane albedo 1 − H(1)√(1 − ϖ) (Radiative Transfer, 1950,
//     §IV eq. 48), H from its integral representation
//         ln H(μ) = −(μ/π) ∫0^{π/2} ln(1 − ϖ θ cot θ) / (cos²θ + μ² sin²θ) dθ;
//   - η > 1, g = 0: the same H-functions with the Fresnel boundary added by an integral
//     equation for the upward radiance U just below the surface (the reflection function of
//     the index-matched half-space is (ϖ/2) H(μ) H(μ′) μ′/(μ + μ′), per unit incident flux):
//         U(μ) = (ϖ/2) H(μ) [H(1)(1 − R_sp)/(1 + μ) + ∫0^1 H(μ′) μ′ R(μ′) U(μ′)/(μ + μ′) dμ′],
//         R_d = ∫0^1 μ (1 − R(μ)) U(μ) dμ,
//     solved by fixed-point iteration on Gauss–Legendre nodes (stats.h), with a Fresnel
//     written from Snell's law here;
//   - ϖ = 1: R_d = 1 − R_sp (energy conservation);
//   - ϖ → 0: R_d/ϖ → ((1 − R_sp)/2) ∫0^1 μ (1 − R(μ)) p(−μ)/(1 + μ) dμ (single scattering);
//   - convergence in the number of ordinates, and double against long double;
//   - R_d decreasing in η and increasing in ϖ.
#include "half_space_reference.h"
#include "stats.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace {

double specular(double eta) {
    const double r = (eta - 1) / (eta + 1);
    return r * r;
}

// Fresnel from inside the medium (index η, outside 1) at internal cosine cosI, from Snell's
// law: sin θt = η sin θi.
double fresnelSnell(double cosI, double eta) {
    const double sinT = eta * std::sqrt(std::max(0.0, 1 - cosI * cosI));
    if (sinT >= 1) return 1;
    const double cosT = std::sqrt(1 - sinT * sinT);
    const double rs = (eta * cosI - cosT) / (eta * cosI + cosT);
    const double rp = (cosI - eta * cosT) / (cosI + eta * cosT);
    return (rs * rs + rp * rp) / 2;
}

// Isotropic half-space with a Fresnel boundary from H-functions (see the top comment).
double isotropicFresnelByH(double omega, double eta, int nodesPerRange = 160) {
    const double muc = eta > 1 ? std::sqrt(1 - 1 / (eta * eta)) : 0;
    std::vector<double> mu, w, x, wx;
    if (eta > 1) {
        pttest::gaussLegendre(nodesPerRange, 0, muc, x, wx);
        mu = x;
        w = wx;
    }
    // [μc, 1] with μ = μc + (1 − μc)s²: R has a square-root branch point at μc.
    pttest::gaussLegendre(nodesPerRange, 0, 1, x, wx);
    for (size_t i = 0; i < x.size(); ++i) {
        mu.push_back(muc + (1 - muc) * x[i] * x[i]);
        w.push_back(2 * (1 - muc) * x[i] * wx[i]);
    }
    const size_t n = mu.size();
    std::vector<double> h(n), r(n), b(n), u(n, 0.0), next(n);
    const double h1 = pttest::hByIntegral(omega, 1.0), entry = 1 - specular(eta);
    for (size_t i = 0; i < n; ++i) {
        h[i] = pttest::hByIntegral(omega, mu[i]);
        r[i] = fresnelSnell(mu[i], eta);
        b[i] = omega / 2 * h[i] * h1 * entry / (1 + mu[i]);
    }
    for (int it = 0; it < 100000; ++it) {
        double change = 0;
        for (size_t i = 0; i < n; ++i) {
            double integral = 0;
            for (size_t j = 0; j < n; ++j)
                integral += w[j] * h[j] * mu[j] * r[j] * u[j] / (mu[i] + mu[j]);
            next[i] = b[i] + omega / 2 * h[i] * integral;
            change = std::max(change, std::fabs(next[i] - u[i]));
        }
        u.swap(next);
        if (change < 1e-16) break;
    }
    double rd = 0;
    for (size_t i = 0; i < n; ++i)
        rd += w[i] * mu[i] * (1 - r[i]) * u[i];
    return rd;
}

// HG phase function normalised to (1/4π)∫ p dΩ = 1.
double hg(double g, double cosTheta) {
    return (1 - g * g) / std::pow(1 + g * g - 2 * g * cosTheta, 1.5);
}

double secondsOf(auto&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

TEST(HalfSpaceReference, RadauRuleAndAzimuthalKernel) {
    for (int n : {1, 2, 5, 17, 64}) {
        std::vector<double> x, w;
        pttest::halfspace::gaussRadauRule(n, x, w);
        EXPECT_EQ(x.back(), 1.0);
        for (int p = 0; p <= 2 * n - 2; ++p) {
            double m = 0;
            for (int i = 0; i < n; ++i)
                m += w[i] * std::pow(x[i], p);
            EXPECT_NEAR(m, 1.0 / (p + 1), 1e-14) << "n " << n << " degree " << p;
        }
    }
    // Closed form (elliptic E) against the Legendre series and a brute azimuth quadrature.
    std::vector<double> phi, wphi;
    pttest::gaussLegendre(2000, 0, std::numbers::pi, phi, wphi);
    for (double g : {0.0, 0.5, 0.9, 0.95})
        for (double mu : {-0.99, -0.3, 0.0, 0.2, 0.7, 1.0})
            for (double mup : {-1.0, -0.5, 0.1, 0.7, 0.999}) {
                double series = 0, gl = 1;
                for (int l = 0; gl > 1e-19; ++l, gl *= g) {
                    double p0m = 1, p1m = 0, p0n = 1, p1n = 0;
                    for (int k = 1; k <= l; ++k) {
                        const double am = ((2 * k - 1) * mu * p0m - (k - 1) * p1m) / k;
                        const double an = ((2 * k - 1) * mup * p0n - (k - 1) * p1n) / k;
                        p1m = p0m;
                        p0m = am;
                        p1n = p0n;
                        p0n = an;
                    }
                    series += (2 * l + 1) * gl * p0m * p0n;
                    if (g == 0) break;
                }
                double brute = 0;
                const double ss = std::sqrt((1 - mu * mu) * (1 - mup * mup));
                for (size_t i = 0; i < phi.size(); ++i)
                    brute += wphi[i] * hg(g, mu * mup + ss * std::cos(phi[i]));
                brute /= std::numbers::pi;
                const double closed = pttest::halfspace::hgAzimuthal(g, mu, mup);
                EXPECT_NEAR(closed, series, 1e-11 * std::max(1.0, series))
                    << "g " << g << " mu " << mu << " mu' " << mup;
                EXPECT_NEAR(closed, brute, 1e-11 * std::max(1.0, brute))
                    << "g " << g << " mu " << mu << " mu' " << mup;
            }
}

TEST(HalfSpaceReference, IndexMatchedIsotropicIsChandrasekharPlaneAlbedo) {
    // The integral representation against Chandrasekhar's table (5 digits).
    EXPECT_NEAR(pttest::hByIntegral(0.5, 1.0), 1.25126, 1e-5);
    double worst = 0;
    for (double omega : {0.5, 0.9, 0.99, 0.999}) {
        const double expected = 1 - pttest::hByIntegral(omega, 1.0) * std::sqrt(1 - omega);
        const double rd = pttest::halfSpaceDiffuseReflectance(omega, 0.0, 1.0);
        std::printf("eta 1, g 0, albedo %.3f: R_d %.12f, 1 - H(1) sqrt(1 - a) %.12f, diff %+.1e\n",
                    omega, rd, expected, rd - expected);
        EXPECT_NEAR(rd, expected, 1e-10) << omega;
        worst = std::max(worst, std::fabs(rd - expected));
    }
    std::printf("worst |diff| %.1e\n", worst);
}

TEST(HalfSpaceReference, IsotropicFresnelBoundaryMatchesHFunctionEquation) {
    // The test's own reference reduces to the plane albedo at η = 1.
    EXPECT_NEAR(isotropicFresnelByH(0.9, 1.0), 1 - pttest::hByIntegral(0.9, 1.0) * std::sqrt(0.1),
                1e-10);
    double worst = 0;
    for (double eta : {1.3, 1.5})
        for (double omega : {0.5, 0.9, 0.99, 0.999}) {
            const double expected = isotropicFresnelByH(omega, eta);
            const double rd = pttest::halfSpaceDiffuseReflectance(omega, 0.0, eta);
            std::printf("eta %.1f, g 0, albedo %.3f: R_d %.12f, H-function equation %.12f, "
                        "diff %+.1e\n",
                        eta, omega, rd, expected, rd - expected);
            EXPECT_NEAR(rd, expected, 1e-10) << "eta " << eta << " albedo " << omega;
            worst = std::max(worst, std::fabs(rd - expected));
        }
    std::printf("worst |diff| %.1e\n", worst);
}

TEST(HalfSpaceReference, ConservativeHalfSpaceReturnsAllButSpecular) {
    double worst = 0;
    for (double eta : {1.0, 1.3, 1.5, 1.6})
        for (double g : {0.0, 0.5, 0.9}) {
            const double rd = pttest::halfSpaceDiffuseReflectance(1.0, g, eta);
            EXPECT_NEAR(rd, 1 - specular(eta), 1e-12) << "eta " << eta << " g " << g;
            worst = std::max(worst, std::fabs(rd - (1 - specular(eta))));
        }
    std::printf("albedo 1: worst |R_d - (1 - R_sp)| %.1e\n", worst);
    // Continuity at ϖ = 1: 1 − R_sp − R_d grows like √(1 − ϖ).
    const double d1 = 1 - specular(1.5) - pttest::halfSpaceDiffuseReflectance(1 - 1e-12, 0.9, 1.5);
    const double d2 = 1 - specular(1.5) - pttest::halfSpaceDiffuseReflectance(1 - 4e-12, 0.9, 1.5);
    std::printf("1 - R_sp - R_d at 1 - a = 1e-12: %.3e, ratio at 4e-12 %.6f\n", d1, d2 / d1);
    EXPECT_GT(d1, 0);
    EXPECT_NEAR(d2 / d1, 2.0, 1e-3);
}

TEST(HalfSpaceReference, SingleScatteringLimit) {
    const double omega = 1e-7;
    std::vector<double> x, w;
    for (double eta : {1.0, 1.5})
        for (double g : {0.0, 0.9}) {
            // ∫0^1 μ (1 − R(μ)) p(−μ)/(1 + μ) dμ, split at the critical cosine.
            const double muc = eta > 1 ? std::sqrt(1 - 1 / (eta * eta)) : 0;
            double integral = 0;
            const int panels = 200;
            for (int p = 0; p < panels; ++p) {
                // μ = μc + (1 − μc)s², uniform panels in s.
                pttest::gaussLegendre(16, double(p) / panels, double(p + 1) / panels, x, w);
                for (size_t i = 0; i < x.size(); ++i) {
                    const double mu = muc + (1 - muc) * x[i] * x[i];
                    integral += 2 * (1 - muc) * x[i] * w[i] * mu * (1 - fresnelSnell(mu, eta)) *
                                hg(g, -mu) / (1 + mu);
                }
            }
            const double expected = (1 - specular(eta)) / 2 * integral;
            const double slope = pttest::halfSpaceDiffuseReflectance(omega, g, eta) / omega;
            EXPECT_NEAR(slope, expected, 1e-6 * expected) << "eta " << eta << " g " << g;
            std::printf("eta %.1f g %.1f: R_d/a at a = 1e-7 %.10f, single scattering %.10f\n", eta,
                        g, slope, expected);
        }
}

TEST(HalfSpaceReference, ConvergedInOrdinatesAndRounding) {
    struct Case {
        double albedo, g, eta;
    };
    const Case cases[] = {{0.9999, 0.9, 1.5}, {0.9999, 0.9, 1.0}, {0.99, 0.9, 1.6}};
    for (const Case& c : cases) {
        double base = 0, twice = 0;
        const double t =
            secondsOf([&] { base = pttest::halfSpaceDiffuseReflectance(c.albedo, c.g, c.eta); });
        twice = pttest::halfSpaceDiffuseReflectance(c.albedo, c.g, c.eta, 256);
        const double coarse = pttest::halfSpaceDiffuseReflectance(c.albedo, c.g, c.eta, 64);
        std::printf("a %.4f g %.1f eta %.1f: R_d %.12f, 256 nodes %+.1e, 64 nodes %+.1e "
                    "(%.3f s)\n",
                    c.albedo, c.g, c.eta, base, twice - base, coarse - base, t);
        EXPECT_NEAR(base, twice, 1e-10);
        EXPECT_NEAR(base, coarse, 1e-6); // half the nodes are already within the spec
    }
    // Rounding: the same discretisation in long double.
    const double d = pttest::halfSpaceDiffuseReflectance(0.9999, 0.9, 1.5);
    const long double ld =
        pttest::halfspace::diffuseReflectance<long double>(0.9999L, 0.9L, 1.5L, 128);
    std::printf("double - long double: %+.1e\n", double(d - ld));
    EXPECT_NEAR(d, double(ld), 1e-12);
}

TEST(HalfSpaceReference, MonotoneInRefractiveIndexAndAlbedo) {
    const double etas[] = {1.0, 1.3, 1.5, 1.6};
    const double albedos[] = {0.5, 0.9, 0.99, 0.999, 0.9999};
    const double gs[] = {0.0, 0.9};
    double table[2][5][4];
    for (int k = 0; k < 2; ++k) {
        const double g = gs[k];
        std::vector<std::vector<double>> rd;
        for (int i = 0; i < 5; ++i) {
            rd.emplace_back();
            for (int j = 0; j < 4; ++j) {
                table[k][i][j] = pttest::halfSpaceDiffuseReflectance(albedos[i], g, etas[j]);
                rd.back().push_back(table[k][i][j]);
            }
        }
        for (size_t i = 0; i < rd.size(); ++i)
            for (size_t j = 0; j < rd[i].size(); ++j) {
                if (j > 0) {
                    EXPECT_LT(rd[i][j], rd[i][j - 1]) << "g " << g << " a " << albedos[i];
                }
                if (i > 0) {
                    EXPECT_GT(rd[i][j], rd[i - 1][j]) << "g " << g << " eta " << etas[j];
                }
                EXPECT_GT(rd[i][j], 0);
                EXPECT_LT(rd[i][j], 1 - specular(etas[j]));
            }
    }
    // Forward scattering sends light deeper: less comes back at fixed albedo < 1.
    EXPECT_LT(pttest::halfSpaceDiffuseReflectance(0.99, 0.9, 1.3),
              pttest::halfSpaceDiffuseReflectance(0.99, 0.5, 1.3));

    std::printf("R_d (MCML convention, R_sp excluded)\n%8s %5s %5s %16s\n", "albedo", "eta", "g",
                "R_d");
    for (int i = 1; i <= 3; ++i)    // albedo 0.9, 0.99, 0.999
        for (int j = 0; j < 3; ++j) // η 1, 1.3, 1.5
            for (int k = 0; k < 2; ++k)
                std::printf("%8.3f %5.1f %5.1f %16.12f\n", albedos[i], etas[j], gs[k],
                            table[k][i][j]);
}
