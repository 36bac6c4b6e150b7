// Shared by the sampling tests: the classical dipole of Jensen et al. 2001 in double (the
// independent reference profile), its table on render::ProfileTable's grid, sample
// accumulators (mean, standard error, batch variances), exact quadrature of a table's pdf and
// the z-test helpers. Thresholds: every z-test uses core::bonferroniZ(1e-3, m), i.e. a
// family-wise false-failure probability of 1e-3 over the m comparisons of one test.
#pragma once

#include "../pathtrace/stats.h"
#include "core/core.h"
#include "core/statistics.h"
#include "sampling/tabulated_radial.h"

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

namespace samplingtest {

struct Medium {
    glm::dvec3 sigmaSPrime, sigmaA;
    double eta;
};
// Jensen et al. 2001, Table 2, "Skin1" (mm⁻¹), as in materials/presets.json.
inline Medium skin1() {
    return {{0.74, 0.88, 1.01}, {0.032, 0.17, 0.48}, 1.3};
}

// The classical dipole R_d(r) (Jensen et al. 2001, eq. 5 with the F_dr fit of eq. 6's text),
// one channel.
inline double dipoleRd(double sigmaSPrime, double sigmaA, double eta, double r) {
    const double sigmaT = sigmaA + sigmaSPrime, alpha = sigmaSPrime / sigmaT;
    const double sigmaTr = std::sqrt(3 * sigmaA * sigmaT);
    const double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    const double a = (1 + fdr) / (1 - fdr);
    const double zr = 1 / sigmaT, zv = zr * (1 + 4.0 / 3.0 * a);
    const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
    return alpha / (4 * std::numbers::pi) *
           (zr * (sigmaTr * dr + 1) * std::exp(-sigmaTr * dr) / (dr * dr * dr) +
            zv * (sigmaTr * dv + 1) * std::exp(-sigmaTr * dv) / (dv * dv * dv));
}
// Its total diffuse reflectance ∫ R_d 2πr dr (Jensen et al. 2001, eq. 6's closed form).
inline double dipoleTotal(double sigmaSPrime, double sigmaA, double eta) {
    const double alpha = sigmaSPrime / (sigmaA + sigmaSPrime);
    const double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    const double a = (1 + fdr) / (1 - fdr);
    const double s = std::sqrt(3 * (1 - alpha));
    return alpha / 2 * (1 + std::exp(-4.0 / 3.0 * a * s)) * std::exp(-s);
}

struct Table {
    std::vector<double> radii;
    std::vector<glm::dvec3> values;
};
// The dipole of `m` on the profile grid r_k = rMax (k/(K−1))².
inline Table dipoleTable(const Medium& m, double rMax, int count = 4096) {
    Table t;
    t.radii = sampling::profileGridRadii(rMax, count);
    for (double r : t.radii) {
        glm::dvec3 v;
        for (int c = 0; c < 3; ++c)
            v[c] = dipoleRd(m.sigmaSPrime[c], m.sigmaA[c], m.eta, r);
        t.values.push_back(v);
    }
    return t;
}
inline std::array<sampling::TabulatedRadial, 3> skinChannels(double eps = 1e-3) {
    const Table t = dipoleTable(skin1(), 60.0);
    return sampling::tabulateChannels(t.radii, t.values, eps);
}

// ∫_lo^hi f by 3-point Gauss–Legendre on every piece between consecutive `breaks` (exact for a
// polynomial of degree <= 5 on each piece, e.g. r·(linear R) between table radii).
inline double integratePieces(const std::function<double(double)>& f, double lo, double hi,
                              const std::vector<double>& breaks) {
    static const double x3[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    static const double w3[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
    double sum = 0, a = lo;
    auto piece = [&](double p, double q) {
        const double m = 0.5 * (p + q), h = 0.5 * (q - p);
        for (int i = 0; i < 3; ++i)
            sum += h * w3[i] * f(m + h * x3[i]);
    };
    for (double b : breaks) {
        if (b <= a) continue;
        if (b >= hi) break;
        piece(a, b);
        a = b;
    }
    piece(a, hi);
    return sum;
}

// Running mean and variance (Welford), per channel.
struct Accumulator {
    double n = 0;
    glm::dvec3 mean{0.0}, m2{0.0};
    void add(const glm::dvec3& x) {
        n += 1;
        const glm::dvec3 d = x - mean;
        mean += d / n;
        m2 += d * (x - mean);
    }
    glm::dvec3 variance() const { return m2 / (n - 1); } // of one sample
    glm::dvec3 stderrOfMean() const { return glm::sqrt(variance() / n); }
};

// z of the difference of two independent estimates.
inline double zDiff(double a, double sa, double b, double sb) {
    const double s = std::sqrt(sa * sa + sb * sb);
    return s > 0 ? (a - b) / s : (a == b ? 0.0 : INFINITY);
}

// The three channels' distributions as the samplers take them.
inline std::array<const sampling::RadialDistribution*, 3>
pointers(const std::array<sampling::TabulatedRadial, 3>& ch) {
    return {&ch[0], &ch[1], &ch[2]};
}

// The message of the core::Error thrown by f ("" if none).
template <class F> std::string errorOf(F&& f) {
    try {
        f();
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}

} // namespace samplingtest
