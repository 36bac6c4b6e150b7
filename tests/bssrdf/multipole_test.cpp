// materials/multipole.bssrdf on the GPU against an independent double-precision evaluation of
// Donner & Jensen 2005's multipole (reflectance of a slab) written here from the paper, with a
// fixed 2 × 2000 image pairs instead of the model's stopping rule, at every preset medium of
// materials/presets.json (all channels) and two more, for slabs 1, 3 and 10 mean free paths
// thick; a thick slab is the classical dipole (dipole.bssrdf); 2π ∫ R r dr of the GPU profile
// is the paper's sum of the poles' fluxes and grows with the thickness.
#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "bssrdf/program_library.h"
#include "material/material.h"
#include "model_reference.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

using model_ref::builtins;
using model_ref::media;
using model_ref::Medium;

constexpr double kPi = std::numbers::pi;

// The multipole at the float inputs the GPU sees.
struct Multipole {
    double alphaP, s, l, zb, d;
    Multipole(const Medium& m, double thickness) {
        const double sa = float(m.sa), ss = float(m.ss), g = float(m.g), eta = float(m.eta);
        const double fdr = -1.44 / (eta * eta) + 0.71 / eta + 0.668 + 0.0636 * eta; // eq. 2.30
        const double A = (1 + fdr) / (1 - fdr);
        const double ssp = ss * (1 - g), stp = sa + ssp;
        alphaP = ssp / stp;
        s = std::sqrt(3 * sa * stp);
        l = 1 / stp;
        zb = 2 * A / (3 * stp);
        d = float(thickness);
    }
    double zr(int i) const { return 2 * i * (d + 2 * zb) + l; }
    double zv(int i) const { return 2 * i * (d + 2 * zb) - l - 2 * zb; }
    double pole(double r, double z) const {
        const double dd = std::sqrt(r * r + z * z);
        return z * (1 + s * dd) * std::exp(-s * dd) / (dd * dd * dd);
    }
    // R(r) with the image pairs i = -n … n; `magnitude` gets the sum of |terms| (float error).
    double profile(double r, int n = 2000, double* magnitude = nullptr) const {
        double sum = 0, mag = 0;
        for (int i = -n; i <= n; ++i) {
            const double a = pole(r, zr(i)), b = pole(r, zv(i));
            sum += a - b;
            mag += std::fabs(a) + std::fabs(b);
        }
        if (magnitude) *magnitude = alphaP / (4 * kPi) * mag;
        return alphaP / (4 * kPi) * sum;
    }
    // 2π ∫ R r dr = α′/2 Σ [sign(z_r) e^(-s|z_r|) − sign(z_v) e^(-s|z_v|)]
    double rdr(int n = 2000) const {
        double sum = 0;
        for (int i = -n; i <= n; ++i)
            sum += std::copysign(std::exp(-s * std::fabs(zr(i))), zr(i)) -
                   std::copysign(std::exp(-s * std::fabs(zv(i))), zv(i));
        return alphaP / 2 * sum;
    }
};

} // namespace

class MultipoleModel : public ::testing::Test {
  protected:
    void SetUp() override {
        testsupport::context();
        m_lib = std::make_unique<bssrdf::ModelLibrary>(
            testsupport::sourceRoot(), std::vector<std::string>{"pencil_profile.comp"});
        m_lib->reload(testsupport::sourceRoot() / "materials" / "multipole.bssrdf");
        m_lib->reload(testsupport::sourceRoot() / "materials" / "dipole.bssrdf");
        m_e = m_lib->find("materials/multipole.bssrdf");
        ASSERT_NE(m_e, nullptr);
        ASSERT_FALSE(m_e->problem) << m_e->problem->text();
    }
    bssrdf::Profile profile(const Medium& m, double thickness, const std::vector<double>& radii) {
        m_e->values["Thickness"] = {float(thickness), 0, 0};
        return bssrdf::evaluateProfile(m_e->programs.at("pencil_profile.comp").id(), *m_e->model,
                                       m_e->values, builtins(m), radii);
    }
    std::unique_ptr<bssrdf::ModelLibrary> m_lib;
    bssrdf::ModelEntry* m_e = nullptr;
};

TEST_F(MultipoleModel, AttributesAndParameter) {
    EXPECT_TRUE(m_e->model->attrs.radial);
    EXPECT_TRUE(m_e->model->attrs.noWi);
    EXPECT_TRUE(m_e->model->attrs.noWo);
    EXPECT_FALSE(m_e->hasInversion()); // R_dr of a slab depends on d σ′t, not on α′ alone
    ASSERT_TRUE(m_e->values.count("Thickness"));
}

// The profile at r σ′t = 0.01 … 10 and at 1 and 3 diffusion lengths, for slabs 1, 3 and 10
// mean free paths thick. Float error: each pole carries a few ulp plus (3 + 2x) ulp of its
// exponential e^(-x), x = σtr d; the poles that make up Σ|poles| have x of order 1, so ~10 ulp
// each, and the float sum adds a few ulp of its running sums: 2e-6 (~16 ulp) of Σ|poles|, plus
// 1e-4 of the value. The first term matters only far out in slabs thinner than the diffusion
// length, where the images cancel the dipole to far below its terms (measured there: 2.7e-7
// of Σ|poles|); R below that floor is float noise.
TEST_F(MultipoleModel, GpuMatchesAnIndependentDoubleEvaluation) {
    for (const Medium& m : media()) {
        for (double mfp : {1.0, 3.0, 10.0}) {
            SCOPED_TRACE(m.name + " thickness " + std::to_string(mfp) + " mfp");
            const double stp = float(m.sa) + float(m.ss) * (1 - float(m.g));
            const Multipole mp(m, mfp / stp);
            std::vector<double> radii;
            for (double x : {0.01, 0.1, 1.0, 3.0, 10.0})
                radii.push_back(double(float(x / stp)));
            if (mp.s > 0)
                for (double x : {1.0, 3.0})
                    radii.push_back(double(float(x / mp.s)));
            const auto got = profile(m, mfp / stp, radii);
            for (size_t i = 0; i < radii.size(); ++i) {
                double magnitude = 0;
                const double want = mp.profile(radii[i], 2000, &magnitude);
                EXPECT_NEAR(got.value[i].x, want, 1e-4 * std::fabs(want) + 2e-6 * magnitude)
                    << "r = " << radii[i] << " mm, sum of |poles| " << magnitude;
            }
        }
    }
}

// A slab much thicker than the diffusion length reflects like the semi-infinite medium: the
// GPU profile equals dipole.bssrdf's (same terms, the images 2d away are below e^(-2 s d)).
TEST_F(MultipoleModel, ThickSlabIsTheClassicalDipole) {
    bssrdf::ModelEntry* dipole = m_lib->find("materials/dipole.bssrdf");
    ASSERT_NE(dipole, nullptr);
    for (const Medium& m :
         {Medium{"skin1 R", 0.032, 0.74, 0, 1.3}, Medium{"", 0.05, 5.0, 0.8, 1.5}}) {
        const double ld = 1 / std::sqrt(3 * m.sa * (m.sa + m.ss * (1 - m.g)));
        std::vector<double> radii;
        for (double x : {0.01, 0.1, 0.5, 1.0, 2.0, 4.0})
            radii.push_back(x * ld);
        const auto slab = profile(m, 40 * ld, radii);
        const auto semi =
            bssrdf::evaluateProfile(dipole->programs.at("pencil_profile.comp").id(), *dipole->model,
                                    dipole->values, builtins(m), radii);
        for (size_t i = 0; i < radii.size(); ++i)
            EXPECT_NEAR(slab.value[i].x, semi.value[i].x, 1e-5 * semi.value[i].x) << m.name;
    }
}

// 2π ∫ R r dr of the GPU profile (Simpson in ln r, 4001 points from 1e-4 l to 60 l_d + 100 l,
// plus 2π r0² R(r0)/2 below r0 where R is flat) equals the sum of the poles' fluxes, for the
// media with absorption (see the model file for σa = 0), and it grows with the thickness
// towards the semi-infinite eq. 3.2. Float: the values carry <= 1e-5 (above): 2e-5.
TEST_F(MultipoleModel, ProfileIntegratesToThePolesFluxes) {
    for (const Medium& m : media()) {
        if (m.sa == 0) continue;
        double previous = 0;
        for (double mfp : {1.0, 3.0, 10.0}) {
            SCOPED_TRACE(m.name + " thickness " + std::to_string(mfp) + " mfp");
            const double stp = float(m.sa) + float(m.ss) * (1 - float(m.g));
            const Multipole mp(m, mfp / stp);
            const double u0 = std::log(1e-4 * mp.l), u1 = std::log(60 / mp.s + 100 * mp.l);
            const int n = 4000;
            std::vector<double> radii;
            for (int i = 0; i <= n; ++i)
                radii.push_back(std::exp(u0 + (u1 - u0) * i / n));
            const auto got = profile(m, mfp / stp, radii);
            double sum = 0;
            for (int i = 0; i <= n; ++i) {
                const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
                sum += w * got.value[i].x * radii[i] * radii[i];
            }
            sum *= 2 * kPi * (u1 - u0) / n / 3;
            sum += kPi * radii[0] * radii[0] * got.value[0].x;
            EXPECT_NEAR(sum, mp.rdr(), 2e-5 * mp.rdr());
            EXPECT_GT(mp.rdr(), previous);
            previous = mp.rdr();
        }
        // the semi-infinite classical dipole's R_dr (thesis eq. 3.2) bounds the slab's
        const double alphaP = Multipole(m, 1).alphaP, T = std::sqrt(3 * (1 - alphaP));
        const double eta = float(m.eta);
        const double fdr = -1.44 / (eta * eta) + 0.71 / eta + 0.668 + 0.0636 * eta;
        const double A = (1 + fdr) / (1 - fdr);
        EXPECT_LT(previous,
                  alphaP / 2 * (1 + std::exp(-4.0 / 3.0 * A * T)) * std::exp(-T) * (1 + 1e-6));
    }
}

// Far out in thin slabs the float sum of the images falls below its rounding floor; the model
// clamps it to 0, so the pencil profile of every preset in the default 1 mm slab is >= 0 and
// finite out to 5 diffusion lengths (the pencil plot's default range).
TEST_F(MultipoleModel, ProfileIsNeverNegative) {
    for (const Medium& m : media()) {
        SCOPED_TRACE(m.name);
        const double ld = m.sa > 0 ? 1 / std::sqrt(3 * m.sa * (m.sa + m.ss * (1 - m.g))) : 100;
        const auto got = profile(m, 1.0, bssrdf::radiusGrid(5 * ld, 512));
        for (const auto& v : got.value) {
            ASSERT_TRUE(std::isfinite(v.x));
            ASSERT_GE(v.x, 0.0);
        }
    }
}
