#include "pipeline/param_mappings.h"

#include "core/core.h"
#include "core/text.h"
#include "pipeline/model_stages.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace app {

const std::vector<ParamMapping>& paramMappings() {
    static const std::vector<ParamMapping> all = {
        {"rdr_ld_dipole", "R_dr / l_d, classical dipole",
         "Jensen & Buhler 2002 with the R_dr of Jensen et al. 2001 (materials/dipole.bssrdf)",
         "diffuse mean free path l_d = 1/sigma_tr", "materials/dipole.bssrdf"},
        {"rdr_ld_better_dipole", "R_dr / l_d, better dipole",
         "Jensen & Buhler 2002 with the R_dr of d'Eon 2012 (materials/better_dipole.bssrdf)",
         "diffuse mean free path l_d = 1/sigma_tr", "materials/better_dipole.bssrdf"},
        {"pbd_mfp", "photon beam diffusion albedo, mean free path",
         "pbrt-v4 SubsurfaceFromDiffuse (src/pbrt/bssrdf.h): the single-scattering albedo whose "
         "photon beam diffusion R_dr (Habel et al. 2013; materials/photon_beam_diffusion.bssrdf) "
         "is A",
         "mean free path 1/sigma_t", "materials/photon_beam_diffusion.bssrdf"},
        {"rdr_mfp_better_dipole", "better dipole albedo, mean free path",
         "appleseed's standard and better dipoles (appleseedhq/appleseed dipolebssrdf.h "
         "@0148b736, sss.cpp @0fa605bb compute_absorption_and_scattering_mfp): the albedo whose "
         "better-dipole R_dr (d'Eon 2012) is A, used as the single-scattering albedo, g ignored",
         "mean free path 1/sigma_t", "materials/better_dipole.bssrdf"},
        {"van_de_hulst", "van de Hulst albedo, mean free path",
         "van de Hulst 1980, the index-matched half space's albedo A = (1 - s)(1 - 0.139 s)/"
         "(1 + 1.17 s), s = sqrt((1 - a)/(1 - g a)), inverted (d'Eon, A Hitchhiker's Guide to "
         "Multiple Scattering, eq. 53.7): Blender Cycles' Random Walk (blender/cycles "
         "src/kernel/integrator/subsurface_random_walk.h @97dbe6f5 lines 76-94) and appleseed's "
         "random walk (randomwalkbssrdf.cpp @c39aed74)",
         "mean free path 1/sigma_t", ""},
        {"cycles_anisotropic_fit", "Cycles' anisotropic albedo fit, reduced mean free path",
         "Blender Cycles' Random Walk (Legacy) and Skin (blender/cycles "
         "src/kernel/integrator/subsurface_random_walk.h @97dbe6f5 lines 29-74, citing Chiang, "
         "Kutz, Burley 2016 and, for g, Wrenninge, Villemin, Hery 2017): "
         "a = (1 - A^(1/4)) A(g) atan(B(g) A)^C(g) + A^(1/4) D(g) atan(E(g) A)^F(g) with six "
         "degree-7 fits in g; sigma_t = 1/(d (1 - g)); eta is ignored",
         "reduced mean free path 1/sigma'_t", ""},
        {"exp_albedo_fit", "exponential albedo fit, mean free path",
         "a = 1 - exp(A (-5.09406 + A (2.61188 - 4.31805 A))): appleseed's directional dipole "
         "(directionaldipolebssrdf.cpp @0c01e1e6, sigma_t = 1/mfp) and Blender Cycles' random "
         "walk before 2021 (intern/cycles/kernel/kernel_subsurface.h @e6e130ccf lines 440-452, "
         "citing Chiang, Kutz, Burley 2016, with sigma_t = 1/(d s(A)) there)",
         "mean free path 1/sigma_t", ""},
    };
    return all;
}

const ParamMapping* findParamMapping(const std::string& id) {
    for (const ParamMapping& m : paramMappings())
        if (m.id == id) return &m;
    return nullptr;
}

namespace {

// The root of f(x) = target on [0, 1] with f increasing, by bisection to 1e-12.
double bisect(const std::function<double(double)>& f, double target) {
    double lo = 0, hi = 1;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (f(mid) < target ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// Σ c[i] g^i.
template <size_t N> double poly(const double (&c)[N], double g) {
    double v = 0;
    for (size_t i = N; i-- > 0;)
        v = v * g + c[i];
    return v;
}

// The single-scattering albedo of Cycles' anisotropic fit (constants as printed in
// subsurface_random_walk.h @97dbe6f5 lines 29-74).
double cyclesAnisotropicAlbedo(double albedo, double g) {
    static const double a[] = {1.8260523782,   -1.28451056436, -1.79904629312, 9.19393289202,
                               -22.8215585862, 32.0234874259,  -23.6264803333, 7.21067002658};
    static const double b[] = {
        0.0,           31.1491581433,  -201.847017512, 841.576016723, -2018.09288505,
        2731.71560286, -1935.41424244, 559.009054474};
    static const double c[] = {1.09686102424, -0.394704063468, 1.05258115941, -8.83963712726,
                               28.8643230661, -46.8802913581,  38.5402837518, -12.7181042538};
    static const double d[] = {0.496310210422, 0.360146581622, -2.15139309747, 17.8896899217,
                               -55.2984010333, 82.065982243,   -58.5106008578, 15.8478295021};
    static const double e[] = {
        0.0,           76.7316253952,  -594.356773233, 2448.8834203, -5576.68528998,
        7116.60171912, -4763.54467887, 1303.5318055};
    static const double f[] = {2.40602999408, -2.51814844609, 9.18494908356, -79.2191708682,
                               259.082868209, -403.613804597, 302.85712436,  -87.4370473567};
    const double A = poly(a, g), B = 4.98511194385 + 0.127355959438 * std::exp(poly(b, g));
    const double C = poly(c, g), D = poly(d, g);
    const double E = 4.23190299701 + 0.00310603949088 * std::exp(poly(e, g)), F = poly(f, g);
    const double blend = std::pow(albedo, 0.25);
    const double alpha = (1 - blend) * A * std::pow(std::atan(B * albedo), C) +
                         blend * D * std::pow(std::atan(E * albedo), F);
    return std::clamp(alpha, 0.0, 0.999999);
}

double vanDeHulstAlbedo(double alpha, double g) {
    const double s = std::sqrt((1 - alpha) / (1 - g * alpha));
    return (1 - s) * (1 - 0.139 * s) / (1 + 1.17 * s);
}

} // namespace

material::MaterialParams mapArtistParams(const ParamMapping& mapping, const glm::dvec3& albedo,
                                         const glm::dvec3& d, double g, double eta,
                                         const bssrdf::ModelEntry* model) {
    const std::string what = "mapping " + mapping.id;
    for (int c = 0; c < 3; ++c) {
        if (!(albedo[c] > 0 && albedo[c] < 1))
            throw core::Error(what, 0,
                              std::string("albedo channel ") + "RGB"[c] +
                                  " must lie in (0, 1), got " + core::formatNumber(albedo[c], 6));
        if (!(d[c] > 0 && std::isfinite(d[c])))
            throw core::Error(what, 0,
                              std::string("length channel ") + "RGB"[c] + " must be > 0 mm, got " +
                                  core::formatNumber(d[c], 6));
    }
    if (!(std::abs(g) < 1)) throw core::Error(what, 0, "g must satisfy |g| < 1");
    material::MaterialParams p;
    p.g = g;
    p.eta = eta;
    if (!mapping.model.empty()) {
        if (!model || !model->usable() || !model->hasInversion())
            throw core::Error(what, 0,
                              mapping.model + " is not loaded or has no DiffuseReflectance");
        MaterialSettings s;
        s.mode = ParamMode::RdrLd;
        s.params = p;
        s.rdr = albedo;
        if (mapping.id == "rdr_mfp_better_dipole") { // α′ used as the albedo, σt = 1/d
            s.ld = glm::dvec3(1.0);
            s.params.g = 0;
            const material::MaterialParams q = effectiveParams(*model, s);
            for (int c = 0; c < 3; ++c) {
                const double a = q.sigmaS[c] / (q.sigmaA[c] + q.sigmaS[c]);
                p.sigmaS[c] = a / d[c];
                p.sigmaA[c] = (1 - a) / d[c];
            }
            return p;
        }
        if (mapping.id == "pbd_mfp") { // α′ first, then σt = 1/d
            s.ld = glm::dvec3(1.0);
            const material::MaterialParams q = effectiveParams(*model, s);
            for (int c = 0; c < 3; ++c) {
                const double a = q.sigmaS[c] * (1 - g) / (q.sigmaA[c] + q.sigmaS[c] * (1 - g));
                // σs + σa = 1/d with σs (1 − g)/(σa + σs (1 − g)) = α′
                const double x = a / (1 - g + a * g);
                p.sigmaS[c] = x / d[c];
                p.sigmaA[c] = (1 - x) / d[c];
            }
            return p;
        }
        s.ld = d;
        return effectiveParams(*model, s);
    }
    if (mapping.id == "van_de_hulst") {
        for (int c = 0; c < 3; ++c) {
            const double a = bisect([&](double x) { return vanDeHulstAlbedo(x, g); }, albedo[c]);
            p.sigmaS[c] = a / d[c];
            p.sigmaA[c] = (1 - a) / d[c];
        }
        return p;
    }
    if (mapping.id == "cycles_anisotropic_fit") {
        for (int c = 0; c < 3; ++c) {
            const double a = cyclesAnisotropicAlbedo(albedo[c], g);
            const double sigmaT = 1 / (d[c] * (1 - g));
            p.sigmaS[c] = a * sigmaT;
            p.sigmaA[c] = (1 - a) * sigmaT;
        }
        return p;
    }
    if (mapping.id == "exp_albedo_fit") {
        for (int c = 0; c < 3; ++c) {
            const double A = albedo[c];
            const double a = 1 - std::exp(A * (-5.09406 + A * (2.61188 - 4.31805 * A)));
            p.sigmaS[c] = a / d[c];
            p.sigmaA[c] = (1 - a) / d[c];
        }
        return p;
    }
    throw core::Error(what, 0, "no such mapping");
}

} // namespace app
