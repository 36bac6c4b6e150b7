// pathtrace/sampling: the sampling steps of thesis Algorithm 1 (Section 3.2).
//   - free-flight distance s = −ln(1−ξ)/σt (pdf σt e^{−σt s}), line 3 of Algorithm 1;
//   - Henyey–Greenstein phase function (thesis eq. 2.7 for the mean cosine g) sampled by exact
//     inversion of its CDF in cos θ. The textbook inversion (e.g. MCML, Wang et al. 1995)
//         cos θ = (1 + g² − ((1 − g²)/(1 − g + 2gξ))²) / (2g)
//     is 0/0 at g = 0; with u = 2ξ − 1 it is rewritten, algebraically identically, as
//         cos θ = (u + g(3 + u² + 2gu + g²u² − g²)/2) / (1 + gu)²
//     which needs no special case and loses no precision as g → 0 (it gives u at g = 0);
//   - for g = 0, a uniform direction on the sphere by Marsaglia's (1972) disc map;
//   - uniform azimuth as (cos φ, sin φ) from a point in the unit disc, by the double-angle
//     map (a² − b², 2ab)/(a² + b²) (von Neumann 1951): no trigonometric call;
//   - the direction frame: the new direction at polar angle θ and azimuth φ about the old one
//     (the "spin" of MCML, Wang et al. 1995, eq. 3.38), with the |u_z| ≈ 1 special case.
#pragma once

#include "pathtrace/rng.h"

#include <cmath>

namespace pathtrace {

struct Dir {
    double x, y, z;
};

// Free-flight distance with pdf σt e^{−σt s}, from ξ in [0, 1). For ξ = k·2^-53 (Pcg32::uniform)
// 1 − ξ is exact, so only the logarithm rounds.
inline double sampleDistance(double sigmaT, double xi) {
    return -std::log(1.0 - xi) / sigmaT;
}

// cos θ distributed by the HG phase function of mean cosine g (|g| < 1), from ξ in [0, 1).
inline double sampleHgCos(double g, double xi) {
    const double u = 2.0 * xi - 1.0;
    const double t = 1.0 + g * u;
    const double c = (u + 0.5 * g * (3.0 + u * u + 2.0 * g * u + g * g * (u * u - 1.0))) / (t * t);
    return c < -1.0 ? -1.0 : (c > 1.0 ? 1.0 : c);
}
// Density of cos θ (integrates to 1 over [−1, 1]): (1 − g²) / (2 (1 + g² − 2g cos θ)^{3/2}).
inline double hgPdfCos(double g, double cosTheta) {
    const double d = 1.0 + g * g - 2.0 * g * cosTheta;
    return 0.5 * (1.0 - g * g) / (d * std::sqrt(d));
}
// Its CDF P(cos θ' <= c) = (1 − g²)/(2g) (1/√d − 1/(1 + g)), d = 1 + g² − 2gc, rewritten with
// (1 + g) − √d = 2g(1 + c)/((1 + g) + √d) as (1 − g)(1 + c) / (√d ((1 + g) + √d)) (no 0/0 at g =
// 0).
inline double hgCdfCos(double g, double c) {
    const double sd = std::sqrt(1.0 + g * g - 2.0 * g * c);
    return (1.0 - g) * (1.0 + c) / (sd * ((1.0 + g) + sd));
}

// (cos φ, sin φ) of a uniform azimuth φ, by rejection in the unit disc (acceptance π/4).
inline void sampleAzimuth(Pcg32& rng, double& cosPhi, double& sinPhi) {
    for (;;) {
        const double a = 2.0 * rng.uniform32() - 1.0;
        const double b = 2.0 * rng.uniform32() - 1.0;
        const double r2 = a * a + b * b;
        if (r2 < 1.0 && r2 > 0x1p-40) {
            const double inv = 1.0 / r2;
            cosPhi = (a * a - b * b) * inv;
            sinPhi = 2.0 * a * b * inv;
            return;
        }
    }
}

// The unit direction at polar angle θ (cos θ, and sin θ >= 0) and azimuth φ about unit `u`.
inline Dir rotateDir(const Dir& u, double cosTheta, double cosPhi, double sinPhi) {
    const double sinTheta = std::sqrt(std::fmax(0.0, 1.0 - cosTheta * cosTheta));
    if (std::fabs(u.z) > 1.0 - 1e-12) {
        return {sinTheta * cosPhi, sinTheta * sinPhi, u.z > 0.0 ? cosTheta : -cosTheta};
    }
    const double tmp = std::sqrt(1.0 - u.z * u.z);
    const double k = sinTheta / tmp;
    return {k * (u.x * u.z * cosPhi - u.y * sinPhi) + u.x * cosTheta,
            k * (u.y * u.z * cosPhi + u.x * sinPhi) + u.y * cosTheta,
            -sinTheta * cosPhi * tmp + u.z * cosTheta};
}

// A uniform direction on the sphere (the HG direction for g = 0, which ignores the old one), by
// Marsaglia (1972): (a, b) uniform in the unit disc, r² = a² + b²,
//   (2a√(1 − r²), 2b√(1 − r²), 1 − 2r²).
inline Dir sampleSphere(Pcg32& rng) {
    for (;;) {
        const double a = 2.0 * rng.uniform32() - 1.0;
        const double b = 2.0 * rng.uniform32() - 1.0;
        const double r2 = a * a + b * b;
        if (r2 < 1.0) {
            const double k = 2.0 * std::sqrt(1.0 - r2);
            return {k * a, k * b, 1.0 - 2.0 * r2};
        }
    }
}

// One HG scattering of direction `u` (two to four draws).
inline Dir scatterHg(const Dir& u, double g, Pcg32& rng) {
    const double cosTheta = sampleHgCos(g, rng.uniform32());
    double cosPhi, sinPhi;
    sampleAzimuth(rng, cosPhi, sinPhi);
    return rotateDir(u, cosTheta, cosPhi, sinPhi);
}

} // namespace pathtrace
