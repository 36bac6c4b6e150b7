// The hybrid method's pieces on the CPU (texspace/hybrid.h, seed 004 §3.3): the weighting
// function (W_l + W_g = 1, W_l(R_p) = ½, C¹ at R_p, W_l(0) ≈ 1), R_p against the thesis's
// Fig. 3.4 (skim milk red, the classical dipole: 2.4141 mm), R_p = 0 when the importance never
// reaches the bound, and the ring filter: L·C + 1 taps whose quadrature of R·W_l over a plane
// converges to the exact integral as the rings grow.
#include "texspace/hybrid.h"

#include "../support/dipole_closed_form.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using Dipole = testsupport::ClassicalDipole;

// A profile table of three dipoles on the renderer's grid (render/profile_table.h).
render::ProfileTable table(const Dipole d[3], float rMax) {
    render::ProfileTable t;
    t.rMax = rMax;
    for (int k = 0; k < render::kProfileEntries; ++k) {
        const double r = render::profileRadius(rMax, k, render::kProfileEntries);
        t.values.emplace_back(d[0](r), d[1](r), d[2](r));
    }
    return t;
}

} // namespace

TEST(HybridWeight, SplitsOneAtRpAndIsSmooth) {
    const double rp = 2.4, k = 1.5;
    EXPECT_DOUBLE_EQ(texspace::localWeight(rp, rp, k), 0.5);
    EXPECT_NEAR(texspace::localWeight(0, rp, k), 1 - 0.5 * std::exp(-rp * k), 1e-15);
    EXPECT_GT(texspace::localWeight(0, rp, k), 0.98);
    EXPECT_LT(texspace::localWeight(10, rp, k), 1e-3);
    const double h = 1e-6;
    const double left =
        (texspace::localWeight(rp, rp, k) - texspace::localWeight(rp - h, rp, k)) / h;
    const double right =
        (texspace::localWeight(rp + h, rp, k) - texspace::localWeight(rp, rp, k)) / h;
    EXPECT_NEAR(left, -0.5 * k, 1e-5);
    EXPECT_NEAR(right, -0.5 * k, 1e-5);
    for (double r = 0; r < 20; r += 0.37) {
        const double w = texspace::localWeight(r, rp, k);
        EXPECT_GE(w, 0.0);
        EXPECT_LE(w, 1.0);
    }
}

// Fig. 3.4: R_p = 2.4141 for skim milk's red channel with lower bound 0.1 and the classical
// dipole. Jensen et al. 2001's table gives skim milk σ_a = 0.0014, σ′_s = 0.70 /mm (the caption
// prints 0.0024, which gives 2.375); the thesis read R_p off a tabulated function, so it is
// compared within 0.005 mm (this table's own crossing is 2.4163).
TEST(HybridRp, SkimMilkRedMatchesTheThesis) {
    const Dipole d[3] = {{0.0014, 0.70, 1.3}, {0.0025, 1.22, 1.3}, {0.0142, 1.90, 1.3}};
    const glm::vec3 rp = texspace::findRp(table(d, 200.0f), 0.1);
    std::printf("R_p skim milk: %.4f %.4f %.4f mm\n", rp.x, rp.y, rp.z);
    EXPECT_NEAR(rp.x, 2.4141, 0.005);
    EXPECT_GT(rp.y, 0.0f);
    // the green and blue channels scatter more: their importance falls below the bound sooner
    EXPECT_LT(rp.z, rp.x);
    // a bound above the importance's maximum: no crossing
    const glm::vec3 none = texspace::findRp(table(d, 200.0f), 10.0);
    EXPECT_EQ(none, glm::vec3(0.0f));
}

TEST(HybridRingFilter, CoversTheDiskAndItsQuadratureConverges) {
    const Dipole d[3] = {{0.0014, 0.70, 1.3}, {0.0025, 1.22, 1.3}, {0.0142, 1.90, 1.3}};
    const render::ProfileTable t = table(d, 100.0f);
    const glm::vec3 rp = texspace::findRp(t, 0.1);
    const double k = 1.5;
    double previous = 1e30;
    for (auto [rings, per] : {std::pair{4, 4}, std::pair{16, 8}, std::pair{64, 16}}) {
        const std::vector<texspace::RingTap> taps = texspace::ringFilter(t, rp, k, rings, per);
        ASSERT_EQ(taps.size(), size_t(rings * per + 1));
        for (const auto& tap : taps)
            ASSERT_GT(tap.areaMm2, 0.0f);
        // ∫ R·W_l dA over the plane, per channel: the filter against a fine quadrature
        double worst = 0;
        for (int c = 0; c < 3; ++c) {
            double exact = 0;
            const int n = 2000000;
            for (int i = 0; i < n; ++i) {
                const double r = 100.0 * (i + 0.5) / n;
                exact += d[c](r) * texspace::localWeight(r, rp[c], k) * 2 * M_PI * r * 100.0 / n;
            }
            double sum = 0;
            for (const auto& tap : taps) {
                const double r = std::hypot(double(tap.offsetMm.x), double(tap.offsetMm.y));
                sum += d[c](r) * texspace::localWeight(r, rp[c], k) * tap.areaMm2;
            }
            worst = std::max(worst, std::abs(sum / exact - 1));
        }
        std::printf("ring filter %d x %d + 1: worst relative error %.4f\n", rings, per, worst);
        EXPECT_LT(worst, previous);
        previous = worst;
    }
    EXPECT_LT(previous, 0.01);
}
