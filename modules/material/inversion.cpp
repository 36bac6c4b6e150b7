// R_dr / l_d → σa, σs (thesis 3.4): parallel bisection of R_dr(α′) = target with
// `subdivisions` equal subintervals per round, then eqs. (3.3)–(3.5) and (2.24).
#include "material.h"

#include "core/core.h"
#include "detail/messages.h"

#include <algorithm>
#include <cmath>

namespace material {

namespace {
// Grid of `n`+1 float32 values from lo to hi (both exact floats). When [lo, hi] holds no more
// than n+1 distinct floats the grid is those consecutive floats (padded with hi), so a round
// never wastes points on values the GPU cannot tell apart.
std::vector<double> floatGrid(double lo, double hi, int n) {
    std::vector<double> g(static_cast<size_t>(n) + 1, hi);
    const float flo = static_cast<float>(lo), fhi = static_cast<float>(hi);
    int count = 0;
    for (float f = flo; f < fhi && count <= n; f = std::nextafter(f, 2.0f))
        ++count;
    if (count <= n) {
        float f = flo;
        for (int i = 0; i <= n && f <= fhi; ++i, f = std::nextafter(f, 2.0f))
            g[i] = f;
        return g;
    }
    for (int i = 0; i <= n; ++i)
        g[i] = static_cast<float>(lo + (hi - lo) * (double(i) / n));
    g[0] = flo;
    g[n] = fhi;
    return g;
}
} // namespace

glm::dvec3 solveAlphaPrime(const glm::dvec3& target, const RdrBatch& evaluate, int subdivisions,
                           int rounds) {
    for (int c = 0; c < 3; ++c)
        if (!std::isfinite(target[c]))
            throw core::Error(
                "R_dr", 0, std::string("R_dr is not finite in channel ") + detail::channelName(c));
    glm::dvec3 lo(0.0), hi(1.0), rLo(0.0), rHi(0.0);
    for (int round = 0; round < rounds; ++round) {
        std::vector<double> grid[3];
        for (int c = 0; c < 3; ++c)
            grid[c] = floatGrid(lo[c], hi[c], subdivisions);
        std::vector<glm::dvec3> alpha(subdivisions + 1);
        for (int i = 0; i <= subdivisions; ++i)
            alpha[i] = {grid[0][i], grid[1][i], grid[2][i]};
        std::vector<glm::dvec3> r = evaluate(alpha);
        if (static_cast<int>(r.size()) != subdivisions + 1)
            throw core::Error("R_dr", 0, "DiffuseReflectance evaluation returned wrong size");
        for (int c = 0; c < 3; ++c) {
            if (round == 0) {
                double rmin = r[0][c], rmax = r[subdivisions][c];
                if (!std::isfinite(rmin) || !std::isfinite(rmax))
                    throw core::Error("R_dr", 0,
                                      "DiffuseReflectance is not finite at alpha' = 0 or 1");
                if (!(target[c] >= std::min(rmin, rmax) && target[c] <= std::max(rmin, rmax)))
                    throw core::Error(
                        "R_dr", 0,
                        "R_dr = " + core::formatNumber(target[c], 6) + " (channel " +
                            detail::channelName(c) + ") is outside the invertible range [" +
                            core::formatNumber(rmin, 6) + ", " + core::formatNumber(rmax, 6) +
                            "] of this model's DiffuseReflectance");
            }
            const bool increasing = r[subdivisions][c] >= r[0][c];
            int found = -1;
            for (int i = 0; i < subdivisions && found < 0; ++i) {
                double a = r[i][c], b = r[i + 1][c];
                if (!increasing) std::swap(a, b);
                if (target[c] >= a && target[c] <= b && grid[c][i] < grid[c][i + 1]) found = i;
            }
            if (found < 0) {
                // the bracket is already two adjacent floats: nothing left to split
                if (std::nextafter(static_cast<float>(lo[c]), 2.0f) >= hi[c]) continue;
                throw core::Error("R_dr", 0,
                                  std::string("bisection lost the root in channel ") +
                                      detail::channelName(c) +
                                      " (DiffuseReflectance not monotonic?)");
            }
            lo[c] = grid[c][found];
            hi[c] = grid[c][found + 1];
            rLo[c] = r[found][c];
            rHi[c] = r[found + 1][c];
        }
    }
    // Final step beyond the thesis: linear interpolation inside the last bracket. The bracket
    // is at most a few float32 ulps wide, where R_dr is linear to far below float noise, so α′
    // is recovered to better than the float32 spacing (matters when 1 − α′ ~ 1e-5, e.g. Cream).
    glm::dvec3 out;
    for (int c = 0; c < 3; ++c) {
        const double d = rHi[c] - rLo[c];
        double t = d != 0.0 ? (target[c] - rLo[c]) / d : 0.5;
        out[c] = lo[c] + std::clamp(t, 0.0, 1.0) * (hi[c] - lo[c]);
    }
    return out;
}

SigmaPair sigmaFromAlphaPrime(const glm::dvec3& alphaPrime, const glm::dvec3& ld, double g) {
    if (!std::isfinite(g) || std::abs(g) >= 1)
        throw core::Error("g", 0, "g must satisfy |g| < 1, got " + core::formatNumber(g, 6));
    SigmaPair out;
    for (int c = 0; c < 3; ++c) {
        if (!(ld[c] > 0) || !std::isfinite(ld[c]))
            throw core::Error("l_d", 0,
                              std::string("l_d must be a positive finite length in mm (channel ") +
                                  detail::channelName(c) + " is " + core::formatNumber(ld[c], 6) +
                                  ")");
        double a = alphaPrime[c];
        if (!(a < 1.0))
            throw core::Error("R_dr", 0,
                              std::string("R_dr in channel ") + detail::channelName(c) +
                                  " needs reduced albedo 1 (no absorption): l_d would be "
                                  "infinite; use the sigma parametrisation instead");
        double sigmaTPrime = 1.0 / (ld[c] * std::sqrt(3.0 * (1.0 - a))); // (3.3)
        double sigmaSPrime = a * sigmaTPrime;                            // (3.4)
        out.sigmaA[c] = sigmaTPrime - sigmaSPrime;                       // (3.5)
        out.sigmaS[c] = sigmaSPrime / (1.0 - g);                         // (2.24)
    }
    return out;
}

} // namespace material
