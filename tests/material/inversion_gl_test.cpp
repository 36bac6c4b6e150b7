// R_dr / l_d inversion round trip on the GPU (thesis 3.4) for every Jensen et al. 2001 preset
// and every shipped model with a DiffuseReflectance section (dipole, better dipole, normalized
// diffusion, photon beam diffusion): σ → (R_dr, l_d) in double precision by independent C++
// closed forms → GPU bisection over the model's own DiffuseReflectance → σ, within 1e-4
// relative.
#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "material/material.h"
#include "pipeline/workbench.h"

#include <cmath>

namespace {

double classicRdr(double a, double eta) { // thesis eq. (3.2)
    const double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    const double A = (1 + fdr) / (1 - fdr), t = std::sqrt(3 * (1 - a));
    return a / 2 * (1 + std::exp(-4.0 / 3.0 * A * t)) * std::exp(-t);
}

// d'Eon 2012 closed form (derivation in materials/better_dipole.bssrdf), in double, with the
// same definition of the Fresnel moments (128-step midpoint rule on the exact Fresnel term).
double betterRdr(double a, double eta) {
    double c1 = 0, c2 = 0;
    for (int i = 0; i < 128; ++i) {
        const double mu = (i + 0.5) / 128, sin2t = eta * eta * (1 - mu * mu);
        double f = 1;
        if (sin2t < 1) {
            const double ct = std::sqrt(1 - sin2t);
            const double rs = (eta * mu - ct) / (eta * mu + ct),
                         rp = (mu - eta * ct) / (mu + eta * ct);
            f = 0.5 * (rs * rs + rp * rp);
        }
        c1 += f * mu / 128;
        c2 += f * mu * mu / 128;
    }
    const double A = (1 + 3 * c2) / (1 - 2 * c1), cphi = 0.25 * (1 - 2 * c1),
                 ce = 0.5 * (1 - 3 * c2);
    const double D = (2 - a) / 3, s = std::sqrt((1 - a) / D), zr = 1, zv = 1 + 4 * A * D;
    const double phiInt =
        s > 0 ? (std::exp(-s * zr) - std::exp(-s * zv)) / (2 * D * s) : (zv - zr) / (2 * D);
    return a * (cphi * phiInt + ce * 0.5 * (std::exp(-s * zr) + std::exp(-s * zv)));
}

// Exact Fresnel moments ∫0^1 F(mu) mu^k dmu (Simpson, 20000 intervals), as the zoo models
// compute them (to float precision), not the 128-step midpoint rule of better_dipole.bssrdf.
double exactMoment(int k, double eta) {
    auto f = [&](double mu) {
        const double sin2t = eta * eta * (1 - mu * mu);
        if (sin2t >= 1) return std::pow(mu, k);
        const double ct = std::sqrt(1 - sin2t);
        const double rs = (eta * mu - ct) / (eta * mu + ct), rp = (mu - eta * ct) / (mu + eta * ct);
        return 0.5 * (rs * rs + rp * rp) * std::pow(mu, k);
    };
    const int n = 20000;
    double sum = f(0) + f(1);
    for (int i = 1; i < n; ++i)
        sum += (i % 2 ? 4 : 2) * f(double(i) / n);
    return sum / (3.0 * n);
}

// normalized_diffusion.bssrdf: A = the better dipole's R_dr with exact moments.
double normalizedDiffusionRdr(double a, double eta) {
    const double c1 = exactMoment(1, eta), c2 = exactMoment(2, eta);
    const double A = (1 + 3 * c2) / (1 - 2 * c1), cphi = 0.25 * (1 - 2 * c1),
                 ce = 0.5 * (1 - 3 * c2);
    const double D = (2 - a) / 3, s = std::sqrt((1 - a) / D), zv = 1 + 4 * A * D;
    const double phiInt = s > 0 ? (std::exp(-s) - std::exp(-s * zv)) / (2 * D * s) : 2 * A;
    return a * (cphi * phiInt + ce * 0.5 * (std::exp(-s) + std::exp(-s * zv)));
}

// photon_beam_diffusion.bssrdf: α′/(1 + s) [C_φ 2A (1 − e^(−x))/x + C_E (1 + e^(−x))/2],
// x = 4 A D s at σ′t = 1 (derivation in the model file).
double photonBeamDiffusionRdr(double a, double eta) {
    const double c1 = exactMoment(1, eta), c2 = exactMoment(2, eta);
    const double A = (1 + 3 * c2) / (1 - 2 * c1), cphi = 0.25 * (1 - 2 * c1),
                 ce = 0.5 * (1 - 3 * c2);
    const double D = (2 - a) / 3, s = std::sqrt((1 - a) / D), x = 4 * A * D * s;
    const double f = x > 0 ? -std::expm1(-x) / x : 1;
    return a / (1 + s) * (cphi * 2 * A * f + ce * 0.5 * (1 + std::exp(-x)));
}

struct Loaded {
    std::unique_ptr<app::Workbench> wb;
    bssrdf::ModelEntry* entry;
};
Loaded load(const std::string& model) {
    testsupport::context();
    Loaded l;
    l.wb = std::make_unique<app::Workbench>(
        testsupport::sourceRoot(), false,
        std::vector<std::filesystem::path>{testsupport::sourceRoot() / "materials" / model});
    l.entry = &l.wb->library().entries().at(0);
    return l;
}

std::string invertError(bssrdf::ModelEntry& e, const app::MaterialSettings& s) {
    try {
        app::effectiveParams(e, s);
    } catch (const core::Error& err) {
        return err.what();
    }
    return "";
}

} // namespace

TEST(InversionGpu, RoundTripForEveryPresetAndModel) {
    auto presets = material::loadPresets(testsupport::sourceRoot() / "materials/presets.json");
    for (const char* model : {"dipole.bssrdf", "better_dipole.bssrdf"}) {
        auto l = load(model);
        ASSERT_TRUE(l.entry->hasInversion());
        for (double g : {0.0, 0.7}) {
            for (const auto& pr : presets) {
                if (pr.name == "Spectralon") continue; // σa = 0: l_d infinite, tested below
                if (!pr.unusable.empty()) continue;    // σs = 0 in a channel
                const material::MaterialParams truth = material::applyPreset(pr, [&] {
                    material::MaterialParams b;
                    b.g = g;
                    return b;
                }());
                app::MaterialSettings s;
                s.mode = app::ParamMode::RdrLd;
                s.params.g = truth.g;
                s.params.eta = truth.eta;
                const glm::dvec3 a = material::reducedAlbedo(truth);
                s.ld = material::diffuseMeanFreePath(truth);
                for (int c = 0; c < 3; ++c)
                    s.rdr[c] = std::string(model) == "dipole.bssrdf" ? classicRdr(a[c], truth.eta)
                                                                     : betterRdr(a[c], truth.eta);
                material::MaterialParams got = app::effectiveParams(*l.entry, s);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(got.sigmaA[c] / truth.sigmaA[c], 1.0, 1e-4)
                        << model << " " << pr.name << " g=" << g << " channel " << c;
                    EXPECT_NEAR(got.sigmaS[c] / truth.sigmaS[c], 1.0, 1e-4)
                        << model << " " << pr.name << " g=" << g << " channel " << c;
                }
            }
        }
    }
}

// The same round trip for the zoo models with a DiffuseReflectance section: σ → (R_dr of the
// model's closed form in double, l_d) → GPU bisection → σ.
TEST(InversionGpu, RoundTripForTheZooModels) {
    auto presets = material::loadPresets(testsupport::sourceRoot() / "materials/presets.json");
    for (const char* model : {"normalized_diffusion.bssrdf", "photon_beam_diffusion.bssrdf"}) {
        auto l = load(model);
        ASSERT_TRUE(l.entry->hasInversion()) << model;
        for (double g : {0.0, 0.7}) {
            for (const auto& pr : presets) {
                if (pr.name == "Spectralon") continue; // σa = 0: l_d infinite
                if (!pr.unusable.empty()) continue;    // σs = 0 in a channel
                const material::MaterialParams truth = material::applyPreset(pr, [&] {
                    material::MaterialParams b;
                    b.g = g;
                    return b;
                }());
                app::MaterialSettings s;
                s.mode = app::ParamMode::RdrLd;
                s.params.g = truth.g;
                s.params.eta = truth.eta;
                const glm::dvec3 a = material::reducedAlbedo(truth);
                s.ld = material::diffuseMeanFreePath(truth);
                for (int c = 0; c < 3; ++c)
                    s.rdr[c] = std::string(model) == "normalized_diffusion.bssrdf"
                                   ? normalizedDiffusionRdr(a[c], truth.eta)
                                   : photonBeamDiffusionRdr(a[c], truth.eta);
                material::MaterialParams got = app::effectiveParams(*l.entry, s);
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(got.sigmaA[c] / truth.sigmaA[c], 1.0, 1e-4)
                        << model << " " << pr.name << " g=" << g << " channel " << c;
                    EXPECT_NEAR(got.sigmaS[c] / truth.sigmaS[c], 1.0, 1e-4)
                        << model << " " << pr.name << " g=" << g << " channel " << c;
                }
            }
        }
    }
}

TEST(InversionGpu, ClearErrorsForTargetsThatCannotBeInverted) {
    auto l = load("dipole.bssrdf");
    app::MaterialSettings s;
    s.mode = app::ParamMode::RdrLd;
    s.rdr = {0.5, 1.3, 0.5}; // R_dr of the dipole lies in [0, 1]
    std::string m = invertError(*l.entry, s);
    EXPECT_NE(m.find("outside the invertible range"), std::string::npos) << m;
    EXPECT_NE(m.find("channel G"), std::string::npos) << m;
    s.rdr = {0.5, -0.1, 0.5};
    EXPECT_NE(invertError(*l.entry, s).find("outside the invertible range"), std::string::npos);
    // Spectralon: no absorption means R_dr = R_dr(1) = 1 and an infinite l_d.
    s.rdr = {1.0, 0.5, 0.5};
    m = invertError(*l.entry, s);
    EXPECT_NE(m.find("infinite"), std::string::npos) << m;
    s.rdr = {0.5, 0.5, 0.5};
    s.ld = {1.0, 0.0, 1.0};
    m = invertError(*l.entry, s);
    EXPECT_NE(m.find("l_d"), std::string::npos) << m;
    s.ld = {1.0, 1.0, 1.0};
    s.params.g = 1.0;
    EXPECT_NE(invertError(*l.entry, s).find("|g| < 1"), std::string::npos);
}

// A model without a diffuseReflectance section: R_dr is its profile integrated numerically
// (bssrdf::integrateDiffuseReflectance). For the dipole that integral has a closed form
// (thesis eq. 3.2, its own section): the two agree, and so do the σ they invert to.
TEST(InversionGpu, ModelWithoutDiffuseReflectanceInvertsByItsIntegratedProfile) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("nodr", {"dipole.bssrdf"});
    std::string text = testsupport::readText(testsupport::sourceRoot() / "materials/dipole.bssrdf");
    auto b = text.find("::begin diffuseReflectance");
    auto e = text.find("::end diffuseReflectance");
    ASSERT_NE(b, std::string::npos);
    text.erase(b, e + std::string("::end diffuseReflectance").size() - b);
    core::writeFile(root / "materials/nodr.bssrdf", text);
    app::Workbench wb(root, false);
    auto* withSection = wb.library().find("materials/dipole.bssrdf");
    auto* without = wb.library().find("materials/nodr.bssrdf");
    ASSERT_TRUE(without && without->usable())
        << (without && without->problem ? without->problem->text() : "");
    EXPECT_FALSE(without->hasInversion());
    // the integral against the closed form, α′ from 0.3 to 0.999, η 1.3 and 1.0
    for (float eta : {1.3f, 1.0f}) {
        bssrdf::Builtins bi;
        bi.ior = eta;
        const std::vector<glm::dvec3> alpha{{0.3, 0.6, 0.9}, {0.99, 0.995, 0.999}};
        const auto numeric =
            bssrdf::integrateDiffuseReflectance(without->programs.at("pencil_profile.comp").id(),
                                                *without->model, without->values, bi, alpha);
        const auto closed =
            bssrdf::evaluateDiffuseReflectance(withSection->programs.at("invert_rdr.comp").id(),
                                               *withSection->model, withSection->values, bi, alpha);
        for (size_t k = 0; k < alpha.size(); ++k)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(numeric[k][c], closed[k][c], 2e-5 * closed[k][c])
                    << "eta " << eta << " alpha' " << alpha[k][c];
    }
    // the inversion through either gives the same σ (float R_dr near α′ = 1 moves α′ by
    // ~1e-7, amplified in σa by 1/(1 − α′) ≤ ~1e3 for these targets)
    app::MaterialSettings s;
    s.mode = app::ParamMode::RdrLd;
    s.rdr = {0.6, 0.45, 0.3};
    s.ld = {8.0, 4.0, 2.0};
    const auto pClosed = app::effectiveParams(*withSection, s);
    const auto pNumeric = app::effectiveParams(*without, s);
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(pNumeric.sigmaA[c], pClosed.sigmaA[c], 1e-3 * pClosed.sigmaA[c]) << c;
        EXPECT_NEAR(pNumeric.sigmaS[c], pClosed.sigmaS[c], 1e-4 * pClosed.sigmaS[c]) << c;
    }
    // the workbench uses it: no material problem in R_dr / l_d mode
    wb.shared() = s;
    wb.update();
    EXPECT_TRUE(wb.view(without->displayPath).effective.has_value())
        << wb.view(without->displayPath).materialProblem;
    // a target no α′ reaches is refused naming the model and the fallback
    s.rdr = {1.5, 0.5, 0.5};
    try {
        app::effectiveParams(*without, s);
        ADD_FAILURE() << "R_dr 1.5 inverted";
    } catch (const core::Error& err) {
        const std::string m = err.what();
        EXPECT_NE(m.find("materials/nodr.bssrdf"), std::string::npos) << m;
        EXPECT_NE(m.find("numerically integrated"), std::string::npos) << m;
    }
    std::filesystem::remove_all(root);
}
