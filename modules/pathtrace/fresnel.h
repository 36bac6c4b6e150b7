// pathtrace/fresnel: exact Fresnel equations of a smooth dielectric interface, unpolarised
//   (the transmission term f_t of thesis Algorithm 1, lines 6–10, is 1 − R).
//   With eta = n_t / n_i (transmitted over incident side), Snell sin θ_t = sin θ_i / eta and
//     r_s = (cos θ_i − eta cos θ_t) / (cos θ_i + eta cos θ_t),
//     r_p = (eta cos θ_i − cos θ_t) / (eta cos θ_i + cos θ_t),
//     R = (r_s² + r_p²) / 2 (unpolarised light: the average of the two polarisations),
//   and total internal reflection (R = 1) when sin θ_t >= 1. The transmittances
//     T_s = eta cos θ_t / cos θ_i · t_s², t_s = 2 cos θ_i / (cos θ_i + eta cos θ_t),
//     T_p = eta cos θ_t / cos θ_i · t_p², t_p = 2 cos θ_i / (eta cos θ_i + cos θ_t)
//   are computed separately (fresnelTerms) so that tests can check R + T = 1 per polarisation.
//   At normal incidence R = ((eta − 1)/(eta + 1))² (MCML's specular reflectance R_sp).
#pragma once

#include <cmath>

namespace pathtrace {

// Unpolarised reflectance for light arriving at cos θ_i in (0, 1], eta = n_t / n_i > 0.
inline double fresnelDielectric(double cosI, double eta) {
    if (eta == 1.0) return 0.0; // index-matched: exactly no reflection (no rounding residue)
    const double sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return 1.0; // total internal reflection
    const double cosT = std::sqrt(1.0 - sin2T);
    const double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    const double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 0.5 * (rs * rs + rp * rp);
}

struct FresnelTerms {
    double rs = 1, rp = 1; // reflectances per polarisation (squared amplitude ratios)
    double ts = 0, tp = 0; // transmittances per polarisation (power, with the beam-area factor)
    double cosT = 0;       // cos θ_t (0 under total internal reflection)
    bool tir = true;
};
inline FresnelTerms fresnelTerms(double cosI, double eta) {
    FresnelTerms f;
    if (eta == 1.0) return {0.0, 0.0, 1.0, 1.0, cosI, false};
    const double sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return f;
    f.tir = false;
    f.cosT = std::sqrt(1.0 - sin2T);
    const double as = (cosI - eta * f.cosT) / (cosI + eta * f.cosT);
    const double ap = (eta * cosI - f.cosT) / (eta * cosI + f.cosT);
    const double bs = 2.0 * cosI / (cosI + eta * f.cosT);
    const double bp = 2.0 * cosI / (eta * cosI + f.cosT);
    const double area = eta * f.cosT / cosI;
    f.rs = as * as;
    f.rp = ap * ap;
    f.ts = area * bs * bs;
    f.tp = area * bp * bp;
    return f;
}

} // namespace pathtrace
