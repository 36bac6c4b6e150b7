// materials/photon_beam_diffusion.bssrdf on the GPU against an independent double-precision
// evaluation of Habel, Christensen & Jarosz 2013 (multiple scattering at normal incidence)
// written here from the paper: the better-dipole exitance of point sources along the beam,
// weighted by σ′s e^(-σ′t t), integrated over the depth t by Simpson's rule on geometrically
// growing intervals (not the model's Gauss-Legendre rule in a log variable), at every preset
// medium of materials/presets.json (all channels) and two more; 2π ∫ R r dr of the GPU
// profile = the closed-form DiffuseReflectance.
#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "bssrdf/program_library.h"
#include "material/material.h"
#include "model_reference.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

namespace {

using model_ref::builtins;
using model_ref::fresnelInside;
using model_ref::media;
using model_ref::Medium;
using model_ref::moment;
using model_ref::simpson;

constexpr double kPi = std::numbers::pi;

// The paper's multiple-scattering profile in double at the float inputs the GPU sees.
struct Pbd {
    double ssp, stp, D, s, zb2, cphi, ce, A;
    Pbd(const Medium& m) {
        const double sa = float(m.sa), ss = float(m.ss), g = float(m.g), eta = float(m.eta);
        const double c1 = moment(1, eta), c2 = moment(2, eta);
        A = (1 + 3 * c2) / (1 - 2 * c1);
        cphi = (1 - 2 * c1) / 4;
        ce = (1 - 3 * c2) / 2;
        ssp = ss * (1 - g);
        stp = sa + ssp;
        D = (2 * sa + ssp) / (3 * stp * stp);
        s = std::sqrt(sa / D);
        zb2 = 4 * A * D;
    }
    // σ′s e^(-σ′t t) (C_φ φ + C_E E) of the dipole whose real source is at depth t
    double integrand(double r, double t) const {
        const double zr = t, zv = t + zb2;
        const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
        const double er = std::exp(-s * dr), ev = std::exp(-s * dv);
        const double phi = (er / dr - ev / dv) / (4 * kPi * D);
        const double E =
            (zr * (1 + s * dr) * er / (dr * dr * dr) + zv * (1 + s * dv) * ev / (dv * dv * dv)) /
            (4 * kPi);
        return ssp * std::exp(-stp * t) * (cphi * phi + ce * E);
    }
    // ∫0^(80/σ′t) … dt: Simpson with n intervals on each of [0, r/64], [r/64, r/32], … (the
    // integrand varies on the scale r near t = 0 and on 1/σ′t deeper).
    double profile(double r, int n = 200) const {
        const double T = 80 / stp;
        std::vector<double> b{0};
        for (double x = r / 64; x < T; x *= 2)
            b.push_back(x);
        b.push_back(T);
        double sum = 0;
        for (size_t k = 0; k + 1 < b.size(); ++k)
            sum += simpson([&](double t) { return integrand(r, t); }, b[k], b[k + 1], n);
        return sum;
    }
    // Closed form of 2π ∫ R r dr (derivation in the model file), in double.
    double rdr() const {
        const double x = zb2 * s;
        const double phiPart = x > 0 ? -std::expm1(-x) / (2 * D * s) : zb2 / (2 * D);
        return ssp / (stp + s) * (cphi * phiPart + ce * (1 + std::exp(-x)) / 2);
    }
};

} // namespace

class PhotonBeamDiffusion : public model_ref::ModelTest {
  protected:
    PhotonBeamDiffusion() : ModelTest("photon_beam_diffusion.bssrdf") {}
};

TEST_F(PhotonBeamDiffusion, Attributes) {
    EXPECT_TRUE(m_e->model->attrs.radial);
    EXPECT_TRUE(m_e->model->attrs.noWi);
    EXPECT_TRUE(m_e->model->attrs.noWo);
    EXPECT_TRUE(m_e->hasInversion());
}

// The reference's own quadrature converges: halving its intervals changes it by < 1e-9.
TEST_F(PhotonBeamDiffusion, ReferenceQuadratureConverges) {
    for (const Medium& m : {Medium{"", 0.0002, 7.38, 0, 1.3}, Medium{"", 1.45, 0.03, 0, 1.3}}) {
        const Pbd pbd(m);
        for (double x : {1e-4, 0.1, 1.0, 30.0}) {
            const double r = x / pbd.stp;
            EXPECT_NEAR(pbd.profile(r, 100), pbd.profile(r, 200), 1e-9 * pbd.profile(r, 200))
                << m.sa << " r " << r;
        }
    }
}

// The profile at r σ′t = 1e-3 … 30 and at 1 and 3 diffusion lengths 1/σtr, for every medium
// (all channels), against the double evaluation at the float inputs the GPU sees. Float error:
// 40 positive terms (the two-source difference of φ evaluated without cancellation), each
// with exponentials e^(-x), x = σtr d + σ′t t <= ~40, carrying (3 + 2x) ulp: ~1e-5 at worst;
// the quadrature itself is within 1e-7 (model header). 1e-4 relative.
TEST_F(PhotonBeamDiffusion, GpuMatchesAnIndependentDoubleEvaluation) {
    for (const Medium& m : media()) {
        SCOPED_TRACE(m.name);
        const Pbd pbd(m);
        std::vector<double> radii;
        for (double x : {1e-3, 0.01, 0.1, 0.5, 1.0, 3.0, 10.0, 30.0})
            radii.push_back(double(float(x / pbd.stp)));
        if (pbd.s > 0)
            for (double x : {1.0, 3.0})
                radii.push_back(double(float(x / pbd.s)));
        const auto got = bssrdf::evaluateProfile(m_e->programs.at("pencil_profile.comp").id(),
                                                 *m_e->model, m_e->values, builtins(m), radii);
        for (size_t i = 0; i < radii.size(); ++i) {
            const double want = pbd.profile(radii[i]);
            EXPECT_NEAR(got.value[i].x, want, 1e-4 * want) << "r = " << radii[i] << " mm";
        }
    }
}

// 2π ∫ R r dr of the GPU profile (Simpson in ln r on 4001 points from 1e-5/σ′t to
// 60/σtr + 100/σ′t, plus 2π r0² R(r0) below r0 where R ~ 1/r) equals the closed-form R_dr
// (double), and the model's DiffuseReflectance(α′) on the GPU equals it at the float α′ it
// receives. Float: the GPU values carry <= 1e-5 (above), so does their weighted sum: 2e-5.
TEST_F(PhotonBeamDiffusion, ProfileIntegratesToDiffuseReflectance) {
    for (const Medium& m : media()) {
        SCOPED_TRACE(m.name);
        const Pbd pbd(m);
        const double alphaP = float(pbd.ssp / pbd.stp);
        const auto rdr = bssrdf::evaluateDiffuseReflectance(
            m_e->programs.at("invert_rdr.comp").id(), *m_e->model, m_e->values, builtins(m),
            {glm::dvec3(alphaP)});
        // the closed form at σ′t = 1 and the float α′
        Medium unit = m;
        unit.sa = 1 - alphaP;
        unit.ss = alphaP;
        unit.g = 0;
        Pbd atAlpha(unit);
        atAlpha.ssp = alphaP;
        atAlpha.stp = 1;
        atAlpha.D = (2 - alphaP) / 3;
        atAlpha.s = std::sqrt((1 - alphaP) / atAlpha.D);
        atAlpha.zb2 = 4 * atAlpha.A * atAlpha.D;
        EXPECT_NEAR(rdr[0].x, atAlpha.rdr(), 1e-5 * atAlpha.rdr()) << "alpha' " << alphaP;

        const double rMax =
            (pbd.s > 0 ? std::min(60 / pbd.s, 1e6 / pbd.stp) : 1e6 / pbd.stp) + 100 / pbd.stp;
        const double u0 = std::log(1e-5 / pbd.stp), u1 = std::log(rMax);
        const int n = 4000;
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
        sum += 2 * kPi * radii[0] * radii[0] * got.value[0].x;
        if (pbd.s == 0) continue; // no absorption: an r^-3 tail beyond r_max, tested by α′ = 1
        EXPECT_NEAR(sum, pbd.rdr(), 2e-5 * pbd.rdr());
    }
}

// Without absorption all light that enters comes back: R_dr(1) = C_φ 2A + C_E = 1.
TEST_F(PhotonBeamDiffusion, DiffuseReflectanceIsOneWithoutAbsorption) {
    const auto rdr = bssrdf::evaluateDiffuseReflectance(
        m_e->programs.at("invert_rdr.comp").id(), *m_e->model, m_e->values,
        builtins({"", 0.0, 1.0, 0.0, 1.3}), {glm::dvec3(1.0), glm::dvec3(0.5)});
    EXPECT_NEAR(rdr[0].x, 1.0, 1e-6);
    EXPECT_LT(rdr[1].x, rdr[0].x);
}
