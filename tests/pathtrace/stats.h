// Statistics helpers for the pathtrace tests: chi-square goodness of fit with its p-value (the
// regularised upper incomplete gamma function Q(k/2, x/2), Numerical Recipes 3rd ed. §6.2:
// series for x < a + 1, Lentz continued fraction otherwise), and Gauss–Legendre nodes
// (Newton on P_n, Golub–Welsch-free).
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

namespace pttest {

// Q(a, x) = Γ(a, x)/Γ(a).
inline double gammaQ(double a, double x) {
    if (x <= 0) return 1.0;
    const double lnPre = a * std::log(x) - x - std::lgamma(a);
    if (x < a + 1) { // P by its series, Q = 1 − P
        double ap = a, sum = 1.0 / a, del = sum;
        for (int i = 0; i < 100000; ++i) {
            ap += 1;
            del *= x / ap;
            sum += del;
            if (std::fabs(del) < std::fabs(sum) * 1e-16) break;
        }
        return 1.0 - sum * std::exp(lnPre);
    }
    const double tiny = 1e-300;
    double b = x + 1 - a, c = 1 / tiny, d = 1 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        const double an = -i * (i - a);
        b += 2;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1 / d;
        const double del = d * c;
        h *= del;
        if (std::fabs(del - 1) < 1e-16) break;
    }
    return std::exp(lnPre) * h;
}

struct ChiSquare {
    double stat = 0;
    int dof = 0;
    double pValue = 1;
};
// Pearson chi-square of observed counts against expected counts; adjacent bins are pooled
// until each pooled expectation is at least `minExpected` (the usual validity rule).
inline ChiSquare chiSquare(const std::vector<double>& observed, const std::vector<double>& expected,
                           double minExpected = 5.0) {
    ChiSquare r;
    double o = 0, e = 0;
    int cells = 0;
    for (size_t i = 0; i < observed.size(); ++i) {
        o += observed[i];
        e += expected[i];
        if (e >= minExpected) {
            r.stat += (o - e) * (o - e) / e;
            ++cells;
            o = e = 0;
        }
    }
    if (e > 0) { // remainder: fold into the statistic as its own cell
        r.stat += (o - e) * (o - e) / e;
        ++cells;
    }
    r.dof = cells - 1;
    r.pValue = gammaQ(0.5 * r.dof, 0.5 * r.stat);
    return r;
}

// n-point Gauss–Legendre rule on [a, b].
inline void gaussLegendre(int n, double a, double b, std::vector<double>& x,
                          std::vector<double>& w) {
    x.assign(n, 0);
    w.assign(n, 0);
    for (int i = 0; i < n; ++i) {
        double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1, p1 = 0;
            for (int k = 1; k <= n; ++k) {
                const double p2 = p1;
                p1 = p0;
                p0 = ((2.0 * k - 1) * z * p1 - (k - 1.0) * p2) / k;
            }
            dp = n * (z * p0 - p1) / (z * z - 1);
            const double dz = p0 / dp;
            z -= dz;
            if (std::fabs(dz) < 1e-15) break;
        }
        x[i] = 0.5 * (a + b) - 0.5 * (b - a) * z;
        w[i] = (b - a) / ((1 - z * z) * dp * dp);
    }
}

// Chandrasekhar's H-function for isotropic scattering (ϖ < 1) by its integral representation
//     ln H(μ) = −(μ/π) ∫0^{π/2} ln(1 − ϖ θ cot θ) / (cos²θ + μ² sin²θ) dθ,
// 64 panels of 16-point Gauss–Legendre (gaussLegendre above).
inline double hByIntegral(double omega, double mu) {
    const int panels = 64;
    const double step = std::numbers::pi / 2 / panels;
    double sum = 0;
    std::vector<double> x, w;
    for (int p = 0; p < panels; ++p) {
        pttest::gaussLegendre(16, p * step, (p + 1) * step, x, w);
        for (size_t i = 0; i < x.size(); ++i) {
            const double t = x[i], c = std::cos(t), s = std::sin(t);
            sum += w[i] * std::log(1 - omega * t * c / s) / (c * c + mu * mu * s * s);
        }
    }
    return std::exp(-mu / std::numbers::pi * sum);
}

} // namespace pttest
