// sampling/gaussian_lobes: single planar Gaussians and the six-Gaussian skin fit of d'Eon &
// Luebke 2007 (GPU Gems 3, ch. 14; variances in mm², the same normalised 2D Gaussian
// convention). The pdf integrates to 1 (composite Gauss–Legendre, 4000 pieces on a quadratic
// grid: 1e-10), R_m gives up exactly eps of the energy, the analytic inverse CDF matches
// numerical inversion of the quadrature CDF (1e-9 relative), the lobe mixture is proportional
// to R, and 10^6 samples per channel pass a chi-square test (p > 1e-3/3 per channel).
#include "sampling_support.h"

#include "pathtrace/rng.h"
#include "sampling/gaussian_lobes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sampling;
using namespace samplingtest;

namespace {
const double kVariances[6] = {0.0064, 0.0484, 0.187, 0.567, 1.99, 7.41};
const double kWeights[6][3] = {{0.233, 0.455, 0.649}, {0.100, 0.336, 0.344}, {0.118, 0.198, 0.0},
                               {0.113, 0.007, 0.007}, {0.358, 0.004, 0.0},   {0.078, 0.0, 0.0}};
std::vector<GaussianLobe> skinLobes(int c) {
    std::vector<GaussianLobe> l;
    for (int k = 0; k < 6; ++k)
        l.push_back({kWeights[k][c], kVariances[k]});
    return l;
}
std::vector<double> quadraticGrid(double rMax, int n = 4000) {
    std::vector<double> g;
    for (int k = 1; k < n; ++k)
        g.push_back(rMax * std::pow(double(k) / n, 2));
    return g;
}
double integrate(const std::function<double(double)>& f, double lo, double hi, double rMax) {
    return integratePieces(f, lo, hi, quadraticGrid(rMax));
}
} // namespace

TEST(GaussianLobes, PdfIntegratesToOne) {
    std::vector<GaussianLobes> cases;
    for (double v : {1e-4, 1.0, 50.0})
        cases.emplace_back(std::vector<GaussianLobe>{{2.5, v}});
    for (int c = 0; c < 3; ++c)
        cases.emplace_back(skinLobes(c), 1e-3, c);
    for (const auto& d : cases) {
        const double rm = d.radiusMax();
        EXPECT_NEAR(integrate([&](double r) { return d.pdfRadius(r); }, 0, rm, rm), 1.0, 1e-10)
            << "R_m " << rm;
        EXPECT_EQ(d.pdfArea(rm * (1 + 1e-12)), 0.0);
    }
}

TEST(GaussianLobes, RadiusMaxKeepsAllButEps) {
    for (double eps : {1e-2, 1e-3, 1e-6})
        for (int c = 0; c < 3; ++c) {
            const GaussianLobes d(skinLobes(c), eps, c);
            double w = 0, beyond = 0;
            for (const auto& l : d.lobes()) {
                w += l.weight;
                beyond += l.weight * std::exp(-d.radiusMax() * d.radiusMax() / (2 * l.variance));
            }
            EXPECT_NEAR(beyond / w, eps, 1e-12 * eps + 1e-15);
            EXPECT_NEAR(d.totalEnergy(), w, 1e-15);
            EXPECT_NEAR(d.keptEnergy() / w, 1 - eps, 1e-12);
            // and by quadrature of the profile itself
            const double rm = d.radiusMax();
            const double kept = integrate(
                [&](double r) { return 2 * std::numbers::pi * r * d.profile(r); }, 0, rm, rm);
            EXPECT_NEAR(kept / d.keptEnergy(), 1.0, 1e-10);
        }
    // one lobe: R_m = √(2v ln(1/eps)) in closed form
    const GaussianLobes one({{1.0, 0.5}}, 1e-3);
    EXPECT_NEAR(one.radiusMax(), std::sqrt(2 * 0.5 * std::log(1e3)), 1e-12);
}

TEST(GaussianLobes, AnalyticInverseMatchesNumericalInversion) {
    for (int c = 0; c < 3; ++c) {
        const GaussianLobes d(skinLobes(c), 1e-3, c);
        const double rm = d.radiusMax();
        for (size_t k = 0; k < d.lobes().size(); ++k) {
            const double v = d.lobes()[k].variance;
            const auto density = [&](double r) { return r * std::exp(-r * r / (2 * v)); };
            const double whole = integrate(density, 0, rm, rm);
            for (double u : {1e-7, 0.01, 0.25, 0.5, 0.9, 0.999999}) {
                double lo = 0, hi = rm; // bisection on the quadrature CDF
                for (int i = 0; i < 80; ++i) {
                    const double mid = 0.5 * (lo + hi);
                    (integrate(density, 0, mid, rm) / whole < u ? lo : hi) = mid;
                }
                const double numeric = 0.5 * (lo + hi);
                EXPECT_NEAR(d.sampleLobe(k, u), numeric, 1e-9 * numeric)
                    << "channel " << c << " lobe " << k << " u " << u;
                EXPECT_NEAR(d.lobeCdf(k, numeric), u, 1e-9);
            }
        }
    }
}

TEST(GaussianLobes, MixtureIsProportionalToTheProfile) {
    for (int c = 0; c < 3; ++c) {
        const GaussianLobes d(skinLobes(c), 1e-3, c);
        double q = 0;
        for (size_t k = 0; k < d.lobes().size(); ++k) {
            q += d.lobeProbability(k);
            if (d.lobes()[k].weight == 0) {
                EXPECT_EQ(d.lobeProbability(k), 0.0);
            }
        }
        EXPECT_NEAR(q, 1.0, 1e-15);
        for (double f : {0.0, 1e-3, 0.1, 0.5, 0.999}) {
            const double r = f * d.radiusMax();
            EXPECT_NEAR(d.pdfArea(r) * d.keptEnergy() / d.profile(r), 1.0, 1e-13);
            // the combined pdf is Σ q_k pdf_k (balance heuristic over the lobes)
            double mix = 0;
            for (size_t k = 0; k < d.lobes().size(); ++k)
                if (d.lobeProbability(k) > 0)
                    mix +=
                        d.lobeProbability(k) * gaussian2d(d.lobes()[k].variance, r) /
                        (-std::expm1(-d.radiusMax() * d.radiusMax() / (2 * d.lobes()[k].variance)));
            EXPECT_NEAR(mix / d.pdfArea(r), 1.0, 1e-13);
        }
    }
}

TEST(GaussianLobes, ChiSquare) {
    const int n = 1000000, bins = 200;
    for (int c = 0; c < 3; ++c) {
        const GaussianLobes d(skinLobes(c), 1e-3, c);
        const double rm = d.radiusMax();
        pathtrace::Pcg32 rng = pathtrace::Pcg32::forPath(200 + c, 0);
        std::vector<double> obs(bins, 0), exp(bins, 0);
        for (int i = 0; i < n; ++i)
            obs[std::min(bins - 1, int(std::sqrt(d.sample(rng.uniform()) / rm) * bins))] += 1;
        for (int b = 0; b < bins; ++b)
            exp[b] = n * integrate([&](double r) { return d.pdfRadius(r); },
                                   rm * std::pow(double(b) / bins, 2),
                                   rm * std::pow((b + 1.0) / bins, 2), rm);
        const auto chi = pttest::chiSquare(obs, exp);
        EXPECT_GT(chi.pValue, 1e-3 / 3)
            << "channel " << c << " chi2 " << chi.stat << " dof " << chi.dof;
        EXPECT_GE(chi.dof, 100);
    }
}
