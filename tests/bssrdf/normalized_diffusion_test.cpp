// materials/normalized_diffusion.bssrdf on the GPU against an independent double-precision
// evaluation of Christensen & Burley 2015 written here from the paper: the profile
// R(r) = A s (e^(-s r/l) + e^(-s r/(3l)))/(8 pi l r) with the paper's three scaling factors
// s(A), at every preset medium of materials/presets.json (all channels) and an anisotropic
// medium; the albedo A = the better dipole's R_dr, here integrated numerically from the better
// dipole's profile (not its closed form); 2 pi int R r dr of the GPU profile = A =
// DiffuseReflectance.
#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "bssrdf/program_library.h"
#include "material/material.h"
#include "model_reference.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>

namespace {

using model_ref::builtins;
using model_ref::fresnelInside;
using model_ref::media;
using model_ref::Medium;
using model_ref::moment;
using model_ref::simpson;

constexpr double kPi = std::numbers::pi;

// The better dipole's total diffuse reflectance at σ′t = 1, as 2π ∫ R(r) r dr of d'Eon 2012's
// profile R = α′(C_φ φ + C_E E), integrated numerically in ln r (Simpson, 40000 intervals
// over ln r from 1e-8 to r_max, h < 1e-3: the integrand is smooth in ln r, error < 1e-10).
double betterDipoleAlbedo(double alphaP, double eta) {
    static std::map<std::pair<double, double>, double> cache;
    if (auto it = cache.find({alphaP, eta}); it != cache.end()) return it->second;
    const double c1 = moment(1, eta), c2 = moment(2, eta);
    const double A = (1 + 3 * c2) / (1 - 2 * c1), cphi = (1 - 2 * c1) / 4, ce = (1 - 3 * c2) / 2;
    const double D = (2 - alphaP) / 3, s = std::sqrt((1 - alphaP) / D), zr = 1, zv = 1 + 4 * A * D;
    auto R = [&](double r) {
        const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
        const double phi = (std::exp(-s * dr) / dr - std::exp(-s * dv) / dv) / (4 * kPi * D);
        const double E = (zr * (1 + s * dr) * std::exp(-s * dr) / (dr * dr * dr) +
                          zv * (1 + s * dv) * std::exp(-s * dv) / (dv * dv * dv)) /
                         (4 * kPi);
        return alphaP * (cphi * phi + ce * E);
    };
    // 2π ∫ R r² d(ln r) from 1e-8 (below, R <= R(0): < π 1e-16 R(0)) to r_max, beyond which
    // R < e^(-60) R(r) r^-2 (s > 0) or, without absorption, R ~ r^-3 leaves < 1e-8.
    const double rMax = s > 0 ? 60 / s + 100 : 1e9;
    auto f = [&](double u) {
        const double r = std::exp(u);
        return 2 * kPi * R(r) * r * r;
    };
    return cache[{alphaP, eta}] = simpson(f, std::log(1e-8), std::log(rMax), 40000);
}

struct Reference {
    double A, s, invD; // albedo, scaling factor, s/l (1/mm)
};

// The paper's s(A) for configuration 0 (searchlight, mfp), 1 (diffuse, mfp), 2 (searchlight,
// dmfp); configurations 3 (mfp) and 4 (dmfp) take s = the parameter S (kFreeS in these tests).
constexpr double kFreeS = 2.75;
double scalingFactor(double A, int configuration) {
    switch (configuration) {
    case 3:
    case 4:
        return double(float(kFreeS));
    case 1:
        return 1.9 - A + 3.5 * (A - 0.8) * (A - 0.8);
    case 2:
        return 3.5 + 100 * std::pow(A - 0.33, 4);
    default:
        return 1.85 - A + 7 * std::pow(std::fabs(A - 0.8), 3);
    }
}

// At the float inputs the GPU sees (R is steep in A for configuration 2 near A = 1).
Reference reference(double sa0, double ss0, double g0, double eta0, int configuration) {
    const double sa = float(sa0), ss = float(ss0), g = float(g0), eta = float(eta0);
    const double ssp = ss * (1 - g), stp = sa + ssp;
    Reference ref;
    ref.A = betterDipoleAlbedo(ssp / stp, eta);
    ref.s = scalingFactor(ref.A, configuration);
    const bool dmfp = configuration == 2 || configuration == 4;
    const double l = dmfp ? 1 / std::sqrt(3 * sa * stp) : 1 / stp;
    ref.invD = ref.s / l;
    return ref;
}

double profile(const Reference& ref, double r) {
    return ref.A * ref.invD * (std::exp(-ref.invD * r) + std::exp(-ref.invD * r / 3)) /
           (8 * kPi * r);
}

} // namespace

class NormalizedDiffusion : public model_ref::ModelTest {
  protected:
    NormalizedDiffusion() : ModelTest("normalized_diffusion.bssrdf") {}
};

TEST_F(NormalizedDiffusion, AttributesAndParameter) {
    EXPECT_TRUE(m_e->model->attrs.radial);
    EXPECT_TRUE(m_e->model->attrs.noWi);
    EXPECT_TRUE(m_e->model->attrs.noWo);
    EXPECT_TRUE(m_e->hasInversion());
    ASSERT_TRUE(m_e->values.count("Configuration"));
    EXPECT_EQ(m_e->values.at("Configuration")[0], 2.0f); // searchlight, diffuse mean free path
    ASSERT_TRUE(m_e->values.count("S"));                 // s of configurations 3 and 4
    EXPECT_EQ(m_e->values.at("S")[0], 1.0f);
}

// The profile at r = (0.01 … 30)·d, d = l/s, for every configuration and medium, against the
// double evaluation at the float inputs the GPU sees. Float error: A carries ~1e-6 relative
// (float R_dr), so do s(A) and 1/d; e^(-r/d) multiplies the relative error of 1/d by
// x = r/d <= 30 (and GLSL's exp adds (3 + 2x) ulp): up to ~3e-5 at 30 d (measured 2.4e-5 on
// llvmpipe); 1e-4 keeps a margin of 4.
TEST_F(NormalizedDiffusion, GpuMatchesAnIndependentDoubleEvaluation) {
    for (int configuration : {0, 1, 2, 3, 4}) {
        m_e->values["Configuration"] = {float(configuration), 0, 0};
        m_e->values["S"] = {float(kFreeS), 0, 0};
        for (const Medium& m : media()) {
            SCOPED_TRACE(m.name + " configuration " + std::to_string(configuration));
            const Reference ref = reference(m.sa, m.ss, m.g, m.eta, configuration);
            if (ref.invD == 0) { // dmfp with σa = 0: l_d infinite, the profile is 0
                auto p = bssrdf::evaluateProfile(m_e->programs.at("pencil_profile.comp").id(),
                                                 *m_e->model, m_e->values, builtins(m), {1.0});
                EXPECT_EQ(p.value[0].x, 0.0);
                continue;
            }
            std::vector<double> radii;
            for (double x : {0.01, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0})
                radii.push_back(double(float(x / ref.invD)));
            const auto got = bssrdf::evaluateProfile(m_e->programs.at("pencil_profile.comp").id(),
                                                     *m_e->model, m_e->values, builtins(m), radii);
            for (size_t i = 0; i < radii.size(); ++i) {
                const double want = profile(ref, radii[i]);
                EXPECT_NEAR(got.value[i].x, want, 1e-4 * want) << "r = " << radii[i] << " mm";
            }
        }
    }
}

// 2π ∫ R r dr of the GPU profile (Simpson in ln r on 4001 points from 1e-5 d to 200 d, plus
// the exact integral of the reference below 1e-5 d, which is ≈ A·1e-5/2) equals A, the
// numerically integrated better-dipole R_dr of the reference; and the model's
// DiffuseReflectance(α′) on the GPU is the same R_dr. Float error: each GPU value carries
// <= 2e-6 relative (above), so does their weighted sum; the closed form of R_dr has no
// cancellation (series near α′ = 1) and is compared at the float α′ it receives: 1e-5.
TEST_F(NormalizedDiffusion, ProfileIntegratesToDiffuseReflectance) {
    for (int configuration : {0, 1, 2, 3, 4}) {
        m_e->values["Configuration"] = {float(configuration), 0, 0};
        m_e->values["S"] = {float(kFreeS), 0, 0};
        for (const Medium& m : media()) {
            SCOPED_TRACE(m.name + " configuration " + std::to_string(configuration));
            const Reference ref = reference(m.sa, m.ss, m.g, m.eta, configuration);
            const double alphaP = float(m.ss * (1 - m.g) / (m.sa + m.ss * (1 - m.g)));
            const auto rdr = bssrdf::evaluateDiffuseReflectance(
                m_e->programs.at("invert_rdr.comp").id(), *m_e->model, m_e->values, builtins(m),
                {glm::dvec3(alphaP)});
            const double want = betterDipoleAlbedo(alphaP, float(m.eta));
            EXPECT_NEAR(rdr[0].x, want, 1e-5 * want) << "alpha' " << alphaP;
            if (ref.invD == 0) continue; // dmfp with σa = 0: no finite profile
            const double d = 1 / ref.invD, u0 = std::log(1e-5 * d), u1 = std::log(200 * d);
            const int n = 4000; // intervals, even
            std::vector<double> radii;
            for (int i = 0; i <= n; ++i)
                radii.push_back(std::exp(u0 + (u1 - u0) * i / n));
            const auto got = bssrdf::evaluateProfile(m_e->programs.at("pencil_profile.comp").id(),
                                                     *m_e->model, m_e->values, builtins(m), radii);
            double sum = 0;
            for (int i = 0; i <= n; ++i) {
                const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
                sum += w * got.value[i].x * radii[i] * radii[i];
            }
            sum *= 2 * kPi * (u1 - u0) / n / 3;
            const double x0 = ref.invD * radii[0];
            sum += ref.A / 4 * ((1 - std::exp(-x0)) + 3 * (1 - std::exp(-x0 / 3)));
            EXPECT_NEAR(sum, ref.A, 1e-5 * ref.A);
        }
    }
}

// The scaling factor the GPU profile has: R(r)·r ∝ e^(-r/d) + e^(-r/(3d)), so far out
// (r = 20 d and 40 d, where the fast term is e^(-2x/3) < 2e-6 of the slow one) the log-slope
// of R·r is 1/(3d) = s(A)/(3 l), l = 1/σ′t or 1/σtr. Float: 1/d carries ~1e-6 (from A) and
// the exponentials (3 + 2x) ulp, x <= 14, over a log ratio of 20/3: ~1e-6 of s; 1e-4 absolute
// on s ~ 1 … 5.
TEST_F(NormalizedDiffusion, ProfileHasThePapersScalingFactor) {
    const Medium m{"", 0.01, 1.0, 0.0, 1.3};
    const double sigmaTr = std::sqrt(3 * m.sa * (m.sa + m.ss));
    for (int configuration : {0, 1, 2, 3, 4}) {
        m_e->values["Configuration"] = {float(configuration), 0, 0};
        m_e->values["S"] = {float(kFreeS), 0, 0};
        const Reference ref = reference(m.sa, m.ss, m.g, m.eta, configuration);
        const double r1 = double(float(20 / ref.invD)), r2 = double(float(40 / ref.invD));
        const auto got = bssrdf::evaluateProfile(m_e->programs.at("pencil_profile.comp").id(),
                                                 *m_e->model, m_e->values, builtins(m), {r1, r2});
        const double slope =
            3 * std::log((got.value[0].x * r1) / (got.value[1].x * r2)) / (r2 - r1);
        const double invL = configuration == 2 || configuration == 4 ? sigmaTr : m.sa + m.ss;
        EXPECT_NEAR(slope / invL, scalingFactor(ref.A, configuration), 1e-4)
            << "configuration " << configuration;
    }
}
