// sampling/tabulated_radial: the radial distribution of a tabulated profile, the general case of
// King et al. 2013's "pdf_disk(r) proportional to R_d" for a model that only gives values.
//   Input: radii r_0 = 0 < r_1 < … < r_{K−1} (e.g. render::ProfileTable's grid
//   r_k = rMax·(k/(K−1))², profileGridRadii below) and one channel's values R_k = R(r_k).
//   Quadrature: R is linear within each interval [a, b] = [r_k, r_{k+1}] (the table lookup of
//   the renderer), and r·R(r) is integrated exactly there: with t = r − a, R_t = R_a + s·t,
//       ∫_a^{a+t} r R(r) dr = t/6 · (R_a (3a + t) + R_t (3a + 2t))          (all terms >= 0),
//   so the CDF of R(r)·2πr is a cubic in t within each interval.
//   R_m: the smallest radius with ∫0^{R_m} R 2πr dr = (1 − eps)·E (eps a parameter, 1e-3 by
//   default), found by the same inversion as the samples.
//   Sampling: u·E_m is located among the interval sums, then the cubic is solved for t by
//   Newton's method safeguarded by bisection (its derivative (a + t)·R_t >= 0, so it is
//   monotone and the bracket always holds the root), to a few ulps of r. The first guess is
//   exact for r·R(r) linear over the interval (a quadratic CDF, inverted in closed form at u
//   scaled to its total), off by O((h/a)²) of the width h, so one or two steps suffice; the
//   iteration stops once Newton's error estimate |E''/(2E')|·step² is below the tolerance.
//   Errors (core::Error(name, 0, "channel c: …")): fewer than 2 radii, lengths that differ, a
//   first radius other than 0, radii not strictly increasing or not finite, eps outside
//   (0, 1); a value that is NaN, infinite or negative (with its radius and entry); a profile
//   with no energy; and a profile whose energy does not converge within the table: when the
//   last 1 % of the radius range (r > 0.99·r_{K−1}) holds more than eps of the energy, R_m
//   would lie there and the table cannot tell how much energy lies beyond it; the message
//   gives that fraction and the radius R_m reached.
#pragma once

#include "sampling/radial.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sampling {

inline constexpr double kDefaultEnergyLoss = 1e-3; // eps: the energy given up beyond R_m

class TabulatedRadial final : public RadialDistribution {
  public:
    // Throws core::Error(name, 0, ...) as described above; `channel` only labels messages.
    TabulatedRadial(std::vector<double> radii, std::vector<double> values,
                    double eps = kDefaultEnergyLoss, int channel = 0,
                    const std::string& name = "radial profile");

    double sample(double u) const override;
    double pdfArea(double r) const override;
    double cdf(double r) const override;
    double radiusMax() const override { return m_radiusMax; }
    double profile(double r) const override; // linear between entries, 0 beyond the table
    double totalEnergy() const override;
    double keptEnergy() const override;

    // ∫0^r R 2πr' dr' of the tabulated profile (any r >= 0; the whole energy beyond the table).
    double energyWithin(double r) const;

    double eps() const { return m_eps; }
    const std::vector<double>& radii() const { return m_radii; }
    const std::vector<double>& values() const { return m_values; }

  private:
    // ∫_{r_k}^{r_k + t} r R(r) dr (no 2π).
    double partial(size_t k, double t) const;
    // What sample() reads of interval k, in one record: ∫0^{r_k} r R dr, r_k, R_k and the
    // slope of R over [r_k, r_{k+1}] (the last record: r_{K−1} and its sums only).
    struct alignas(32) Piece {
        double cumulative = 0, r = 0, value = 0, slope = 0;
    };
    // t in [0, h] with partial(k, t) = y, pc = m_pieces[k].
    static double invert(const Piece& pc, double h, double y);
    size_t intervalOf(double r) const; // k with r_k <= r < r_{k+1}, clamped to [0, K − 2]

    std::vector<double> m_radii, m_values;
    std::vector<double> m_cumulative; // ∫0^{r_k} r R dr (no 2π)
    double m_eps = kDefaultEnergyLoss;
    size_t m_lastInterval = 0;     // interval holding R_m
    bool m_quadraticGrid = false;  // radii are profileGridRadii(r_{K−1}, K): O(1) intervalOf
    std::vector<Piece> m_pieces;   // K records (sample())
    std::vector<uint32_t> m_guide; // sample(): first candidate interval per 1/K of probability
    double m_radiusMax = 0;
    double m_kept = 0; // ∫0^{R_m} r R dr (no 2π)
};

// r_k = rMax·(k/(count − 1))², k = 0 … count − 1: the grid of render::ProfileTable (in double).
std::vector<double> profileGridRadii(double rMax, int count);

// One TabulatedRadial per colour channel from RGB values at the given radii.
std::array<TabulatedRadial, 3> tabulateChannels(const std::vector<double>& radii,
                                                const std::vector<glm::dvec3>& values,
                                                double eps = kDefaultEnergyLoss,
                                                const std::string& name = "radial profile");

} // namespace sampling
