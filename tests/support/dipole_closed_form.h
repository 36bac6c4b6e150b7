// Shared by tests that check renders against closed forms: the classical dipole of Jensen et al.
// 2001 (materials/dipole.bssrdf) in double precision — R_d(r) in 1/mm² and the total diffuse
// reflectance R_dr = α′/2·(1 + e^{−4/3·A·√(3(1−α′))})·e^{−√(3(1−α′))} — with F_dr's fit and
// A = (1 + F_dr)/(1 − F_dr). σa, σ′s in 1/mm.
#pragma once

#include <cmath>

namespace testsupport {

struct ClassicalDipole {
    double sigmaA, sigmaSPrime, eta;

    double A() const {
        const double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
        return (1 + fdr) / (1 - fdr);
    }
    double operator()(double r) const { // R_d(r)
        const double st = sigmaA + sigmaSPrime, alpha = sigmaSPrime / st;
        const double tr = std::sqrt(3 * sigmaA * st);
        const double zr = 1 / st, zv = zr * (1 + 4 * A() / 3);
        const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
        return alpha / (4 * M_PI) *
               (zr * (tr * dr + 1) * std::exp(-tr * dr) / (dr * dr * dr) +
                zv * (tr * dv + 1) * std::exp(-tr * dv) / (dv * dv * dv));
    }
    double rdr() const { // ∫ R_d dA over the plane
        const double alpha = sigmaSPrime / (sigmaA + sigmaSPrime);
        const double t = std::sqrt(3 * (1 - alpha));
        return alpha / 2 * (1 + std::exp(-4.0 / 3.0 * A() * t)) * std::exp(-t);
    }
};

} // namespace testsupport
