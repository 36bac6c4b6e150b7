// materials/quantized_diffusion.bssrdf on the GPU against an independent double-precision
// evaluation written here from d'Eon & Irving 2011: the time-resolved weight W(v) by Simpson's
// rule over the source depth z (no erfc), the lobe weights and mean variances by Simpson's rule
// in ln v, and the time-resolved integral R(r) = ∫ W(v) G2(r, v) dv that the quantization
// approximates, at every preset medium of materials/presets.json (all channels) and two more.
// Checks: the lobes the shader exposes (QdLobe) against the reference lobes; the GPU profile
// against the exact double lobe sum; the lobe sum against the time-resolved integral; the
// lobes reproduce the profile; 2π ∫ R r dr = Σ w_k = DiffuseReflectance.
#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "bssrdf/program_library.h"
#include "core/core.h"
#include "material/material.h"
#include "model_reference.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

using testsupport::replaced;

namespace {

using model_ref::builtins;
using model_ref::fresnelInside;
using model_ref::media;
using model_ref::Medium;
using model_ref::moment;

constexpr double kPi = std::numbers::pi;
constexpr int kLobes = 40;

// The reference in mean-free-path units (σ′t = 1, lengths in l = 1/σ′t, variances in l²).
struct Reference {
    double stp = 1;         // σ′t, 1/mm
    double rdr = 0;         // closed-form photon-beam R_dr
    double ld = 0;          // diffusion length 1/σtr in l (0 without absorption)
    std::vector<double> u;  // ln v grid, 32 points per octave from 2^-40 to 2^70
    std::vector<double> wv; // W(v) v on the grid (the integrand in ln v)
    double w[kLobes] = {};  // lobe weights
    double v[kLobes] = {};  // lobe variances, l²
};

constexpr int kPerOctave = 32, kLo = -40 * kPerOctave, kHi = 70 * kPerOctave;

// W(v) of the header of quantized_diffusion.bssrdf, by Simpson's rule in the source depth z on
// [0, min(45, 10 √v)] (beyond, e^(-z) < 3e-20 or the Gaussians < e^(-50)), 1000 intervals.
// The integrand's exponentials on the uniform grid z_i = i·dz are products of the previous
// point's and a ratio that is itself a running product (e^(-z²/2v): ratio e^(-(2i+1)dz²/2v),
// times e^(-dz²/v) per step; the image source at z + h takes the extra factor e^(-h·dz/v)): every
// factor is at most 1, and 1000 steps round by ~1e-13 relative, where calling exp at every
// point cost 3.5 million exponentials per medium.
double weightW(double al, double sa, double D, double h, double cphi, double ce, double v) {
    const double Z = std::min(45.0, 10 * std::sqrt(v));
    const int n = 1000;
    const double dz = Z / n, norm = 1 / std::sqrt(2 * kPi * v);
    const double step = std::exp(-dz * dz / v), image = std::exp(-h * dz / v),
                 decay = std::exp(-dz);
    double ea = 1, eb = std::exp(-h * h / (2 * v)), ratio = std::exp(-dz * dz / (2 * v)), ez = 1;
    double s = 0;
    for (int i = 0; i <= n; ++i) {
        const double z = i * dz, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
        const double a = norm * ea, b = norm * eb; // G1(z, v), G1(z + h, v)
        s += w * ez * (cphi * (a - b) / (2 * D) + ce * (z * a + (z + h) * b) / (2 * v));
        ea *= ratio;
        eb *= ratio * image;
        ratio *= step;
        ez *= decay;
    }
    return al * std::exp(-sa * v / (2 * D)) * s * dz / 3;
}

// Simpson's rule in ln v over grid points [a, b] (b - a even) of f(v)·W(v)·v.
template <class F> double integrate(const Reference& ref, int a, int b, F f) {
    const double h = std::log(2.0) / kPerOctave;
    double s = 0;
    for (int i = a; i <= b; ++i) {
        const double w = (i == a || i == b) ? 1 : ((i - a) % 2 ? 4 : 2);
        s += w * ref.wv[i - kLo] * f(std::exp(ref.u[i - kLo]));
    }
    return s * h / 3;
}

// At the float inputs the GPU sees.
Reference reference(const Medium& m) {
    const double sa = float(m.sa), ss = float(m.ss), g = float(m.g), eta = float(m.eta);
    const double ssp = ss * (1 - g), stp = sa + ssp;
    const double al = ssp / stp, sa1 = sa / stp, D = (2 * sa1 + al) / 3;
    const double c1 = moment(1, eta), c2 = moment(2, eta);
    const double A = (1 + 3 * c2) / (1 - 2 * c1), cphi = (1 - 2 * c1) / 4, ce = (1 - 3 * c2) / 2;
    const double h = 4 * A * D;
    Reference ref;
    ref.stp = stp;
    for (int i = kLo; i <= kHi; ++i) {
        const double u = i * std::log(2.0) / kPerOctave, v = std::exp(u);
        ref.u.push_back(u);
        ref.wv.push_back(weightW(al, sa1, D, h, cphi, ce, v) * v);
    }
    // lobe k covers [2^(k-11), 2^(k-10)] l², the first from 0 (here 2^-40), the last to ∞
    for (int k = 0; k < kLobes; ++k) {
        const int a = k == 0 ? kLo : (k - 11) * kPerOctave;
        const int b = k == kLobes - 1 ? kHi : (k - 10) * kPerOctave;
        ref.w[k] = integrate(ref, a, b, [](double) { return 1.0; });
        // below the grid (v < 2^-40 l²) W ∝ v^(-1/2) (the real source's G1(0, v) term), so
        // ∫_0^v0 W dv = 2 v0 W(v0): ~1e-6 of R_dr for strongly absorbing media
        if (k == 0) ref.w[k] += 2 * ref.wv[0];
        const double mean = integrate(ref, a, b, [](double v) { return v; }) / ref.w[k];
        // the last lobe's variance is fixed at 2 b_39 = 2^29 l²; an underflowed lobe gets
        // its interval's centre (its weight is 0 either way)
        const double centre = k == 0 ? std::ldexp(1.0, -11) : std::ldexp(std::sqrt(2.0), k - 11);
        ref.v[k] = k == kLobes - 1 ? std::ldexp(1.0, 29) : ref.w[k] > 0 ? mean : centre;
    }
    const double s = std::sqrt(sa1 / D), x = h * s;
    ref.ld = s > 0 ? 1 / s : 0;
    ref.rdr = al / (1 + s) *
              (cphi * 2 * A * (x > 0 ? -std::expm1(-x) / x : 1) + ce * 0.5 * (1 + std::exp(-x)));
    return ref;
}

// The exact lobe sum in 1/mm² at r in mm.
double lobeSum(const Reference& ref, double r) {
    const double x = r * ref.stp;
    double s = 0;
    for (int k = 0; k < kLobes; ++k)
        s += ref.w[k] * std::exp(-x * x / (2 * ref.v[k])) / (2 * kPi * ref.v[k]);
    return s * ref.stp * ref.stp;
}
// The time-resolved integral ∫ W(v) G2(r, v) dv in 1/mm² at r in mm.
double timeResolved(const Reference& ref, double r) {
    const double x = r * ref.stp;
    return integrate(ref, kLo, kHi,
                     [&](double v) { return std::exp(-x * x / (2 * v)) / (2 * kPi * v); }) *
           ref.stp * ref.stp;
}

// Radii (mm) where the reference is compared: 0 and 0.01 … 10 l, and 0.3 … 3 diffusion lengths.
std::vector<double> radii(const Reference& ref) {
    std::vector<double> out{0.0};
    for (double x : {0.01, 0.1, 0.3, 1.0, 3.0, 10.0})
        out.push_back(double(float(x / ref.stp)));
    if (ref.ld > 0)
        for (double x : {0.3, 1.0, 3.0})
            out.push_back(double(float(x * ref.ld / ref.stp)));
    return out;
}

} // namespace

class QuantizedDiffusion : public model_ref::ModelTest {
  protected:
    QuantizedDiffusion() : ModelTest("quantized_diffusion.bssrdf") {}
    bssrdf::Profile profile(const Medium& m, const std::vector<double>& r) {
        return bssrdf::evaluateProfile(m_e->programs.at("pencil_profile.comp").id(), *m_e->model,
                                       m_e->values, builtins(m), r);
    }
};

TEST_F(QuantizedDiffusion, Attributes) {
    EXPECT_TRUE(m_e->model->attrs.radial);
    EXPECT_TRUE(m_e->model->attrs.noWi);
    EXPECT_TRUE(m_e->model->attrs.noWo);
    EXPECT_TRUE(m_e->hasInversion());
}

// The GPU profile against the exact double lobe sum of the reference lobes. Float error: the
// GPU weights are 8-point Gauss-Legendre rules of W (rule error measured < 2e-5 of a lobe
// against the reference's Simpson rule, whose own error is < 1e-7) with W in float (erfcx fit
// 1.2e-7, the differences I(0) - I(h) and G1 - I lose at most a factor 16 below v = 16, i.e.
// ~1e-6); a variance error δv/v ~ 1e-6 grows by r²/(2v) <= ~20 where a lobe's tail dominates:
// ~2e-5 in all; 1e-4 relative keeps a margin of 5.
TEST_F(QuantizedDiffusion, GpuMatchesTheExactLobeSum) {
    for (const Medium& m : media()) {
        SCOPED_TRACE(m.name);
        const Reference ref = reference(m);
        const std::vector<double> r = radii(ref);
        const auto got = profile(m, r);
        for (size_t i = 0; i < r.size(); ++i) {
            const double want = lobeSum(ref, r[i]);
            EXPECT_TRUE(std::isfinite(got.value[i].x) && got.value[i].x >= 0);
            EXPECT_NEAR(got.value[i].x, want, 1e-4 * want) << "r = " << r[i] << " mm";
        }
    }
}

// The quantization against the time-resolved integral it replaces, from 0.1 l to 3 l or 3
// diffusion lengths, whichever is larger. This is the model's own error, not a float error:
// the lobe sum replaces G2(r, v) in each octave of v by one Gaussian of the mean variance, an
// O((ln 2)²) midpoint-type error; measured up to 1.7 % on these media (largest at 3 diffusion
// lengths of strongly absorbing media). 3 % bounds it. Closer to the beam (r < 0.1 l) the
// integral diverges like 1/r while the Gaussians are finite (-10 % at 0.01 l, +22 % at 0.03 l),
// and beyond a few diffusion lengths the Gaussian tails fall faster than e^(-σtr r).
TEST_F(QuantizedDiffusion, LobeSumApproximatesTheTimeResolvedIntegral) {
    for (const Medium& m : media()) {
        SCOPED_TRACE(m.name);
        const Reference ref = reference(m);
        const double far = std::max(3.0, 3 * ref.ld);
        for (double x : {0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0}) {
            if (x > far) continue;
            const double r = x / ref.stp, exact = timeResolved(ref, r);
            EXPECT_NEAR(lobeSum(ref, r), exact, 0.03 * exact) << "r = " << x << " l";
        }
        for (double x : {0.3, 1.0, 3.0}) {
            if (ref.ld == 0) continue;
            const double r = x * ref.ld / ref.stp, exact = timeResolved(ref, r);
            EXPECT_NEAR(lobeSum(ref, r), exact, 0.03 * exact) << "r = " << x << " l_d";
        }
    }
}

// QdLobeCount() and QdLobe(k, channel) through a test copy of the model whose Bssrdf returns
// them (at r = k + 0.25 the weights, at r = k + 0.75 the variances, at r = 100.5 the count):
// the lobes against the reference lobes, and Σ_k w_k G2(r, v_k) of the GPU lobes, in double,
// against the GPU profile. Float: weights and variances as in GpuMatchesTheExactLobeSum
// (2e-5 of a lobe; lobes below 1e-7 of the total weight are not compared one by one); the
// sum of the GPU's own lobes differs from its profile only by the float exp and sum, < 1e-6:
// 1e-4 and 1e-5.
TEST_F(QuantizedDiffusion, LobesReproduceTheProfile) {
    std::string text =
        testsupport::readText(testsupport::sourceRoot() / "materials/quantized_diffusion.bssrdf");
    text = replaced(text, "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {",
                    "vec3 QdProfile(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {");
    text = replaced(text, "::end shader",
                    "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                    "    float r = length(Xo - Xi);\n"
                    "    if (r > 100.0) return vec3(float(QdLobeCount()));\n"
                    "    int k = int(floor(r));\n"
                    "    int c = fract(r) < 0.5 ? 0 : 1;\n"
                    "    return vec3(QdLobe(k, 0)[c], QdLobe(k, 1)[c], QdLobe(k, 2)[c]);\n"
                    "}\n::end shader");
    const auto root = testsupport::makeProjectRoot("qd_lobes", {});
    core::writeFile(root / "materials" / "lobes.bssrdf", text);
    bssrdf::ModelLibrary lib(root,
                             std::vector<std::string>{"pencil_profile.comp", "invert_rdr.comp"});
    lib.scanAll();
    auto* e = lib.find("materials/lobes.bssrdf");
    ASSERT_NE(e, nullptr);
    ASSERT_FALSE(e->problem) << e->problem->text();
    std::vector<double> at;
    for (int k = 0; k < kLobes; ++k) {
        at.push_back(k + 0.25);
        at.push_back(k + 0.75);
    }
    at.push_back(100.5);
    for (const Medium& m : media()) {
        SCOPED_TRACE(m.name);
        const Reference ref = reference(m);
        const auto lobes = bssrdf::evaluateProfile(e->programs.at("pencil_profile.comp").id(),
                                                   *e->model, e->values, builtins(m), at);
        ASSERT_EQ(lobes.value.back().x, double(kLobes));
        double total = 0;
        for (int k = 0; k < kLobes; ++k)
            total += ref.w[k];
        const double l2 = 1 / (ref.stp * ref.stp);
        for (int k = 0; k < kLobes; ++k) {
            const double w = lobes.value[2 * k].x, v = lobes.value[2 * k + 1].x;
            EXPECT_EQ(w, lobes.value[2 * k].y); // all channels are the same medium here
            EXPECT_NEAR(w, ref.w[k], 1e-4 * ref.w[k] + 1e-7 * total) << "lobe " << k;
            if (ref.w[k] > 1e-7 * total) {
                EXPECT_NEAR(v, ref.v[k] * l2, 1e-4 * ref.v[k] * l2) << "lobe " << k;
            }
        }
        const std::vector<double> r = radii(ref);
        const auto got = profile(m, r);
        for (size_t i = 0; i < r.size(); ++i) {
            double s = 0;
            for (int k = 0; k < kLobes; ++k) {
                const double w = lobes.value[2 * k].x, v = lobes.value[2 * k + 1].x;
                s += w * std::exp(-r[i] * r[i] / (2 * v)) / (2 * kPi * v);
            }
            EXPECT_NEAR(got.value[i].x, s, 1e-5 * s) << "r = " << r[i] << " mm";
        }
    }
}

// 2π ∫ R r dr of the GPU profile (Simpson in ln r on 1001 points from 1e-4 l to 1e6 l, plus
// π R(0) r_min² below) = Σ w_k of the reference = the closed-form R_dr, and the model's
// DiffuseReflectance on the GPU is the same. Float: each GPU value carries ~2e-5 at most
// (above), mostly less; the Simpson error on Gaussians in ln r with step 0.023 is ~1e-12 (40
// unit lobes of variance 2^-10.5 … 2^28.5 l², computed apart; 2000 points gave the same, and
// each GPU value costs 40 lobes on llvmpipe); the reference weights sum to the closed form
// within 1e-6 (Simpson in ln v, the tail beyond 2^70 l² < 1e-10); DiffuseReflectance has no
// cancellation (series for 1 - e^(-x)): 3e-5.
TEST_F(QuantizedDiffusion, ProfileIntegratesToTheWeightsAndDiffuseReflectance) {
    for (const Medium& m : media()) {
        SCOPED_TRACE(m.name);
        const Reference ref = reference(m);
        double total = 0;
        for (int k = 0; k < kLobes; ++k)
            total += ref.w[k];
        EXPECT_NEAR(total, ref.rdr, 1e-6 * ref.rdr);
        const double alphaP = float(m.ss * (1 - m.g) / (m.sa + m.ss * (1 - m.g)));
        const auto rdr = bssrdf::evaluateDiffuseReflectance(
            m_e->programs.at("invert_rdr.comp").id(), *m_e->model, m_e->values, builtins(m),
            {glm::dvec3(alphaP)});
        EXPECT_NEAR(rdr[0].x, ref.rdr, 3e-5 * ref.rdr) << "alpha' " << alphaP;
        const double u0 = std::log(1e-4 / ref.stp), u1 = std::log(1e6 / ref.stp);
        const int n = 1000;
        std::vector<double> r{0.0};
        for (int i = 0; i <= n; ++i)
            r.push_back(std::exp(u0 + (u1 - u0) * i / n));
        const auto got = profile(m, r);
        double sum = 0;
        for (int i = 0; i <= n; ++i) {
            const double w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
            sum += w * got.value[i + 1].x * r[i + 1] * r[i + 1];
        }
        sum *= 2 * kPi * (u1 - u0) / n / 3;
        sum += kPi * got.value[0].x * r[1] * r[1];
        EXPECT_NEAR(sum, total, 3e-5 * total);
    }
}
