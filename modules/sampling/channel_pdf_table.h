// sampling/channel_pdf_table: the three channels' pdf_area(r) of tabulated profiles
// (tabulated_radial.h) that share their radii, looked up together: one interval search for all
// three, so the balance-heuristic density of disk sampling (disk_sampling.h, King et al. 2013,
// "Axis and Weight Multiple Importance Sampling": p(x) = Σ_a Σ_c P_a P_c pdf_c(r_a(x)) |V_a·N_x|)
// costs one search per axis instead of one per axis and channel.
//   The values are those of TabulatedRadial::pdfArea: per interval [r_k, r_{k+1}] and channel
//       pdf_c(r) = R_c,k/E_m,c + (r − r_k)·(R_c,k+1 − R_c,k)/((r_{k+1} − r_k)·E_m,c),
//   R linear between entries as there (equal up to rounding: the slope is divided once here),
//   and 0 beyond R_m,c or for r < 0. On the profile grid r_k = r_{K−1}(k/(K−1))² the interval
//   comes from a square root, as TabulatedRadial::intervalOf; on other radii from a binary
//   search. Each interval's data (r_k and three values and slopes) is one 64-byte record.
#pragma once

#include "sampling/radial.h"
#include "sampling/tabulated_radial.h"

#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <vector>

namespace sampling {

class ChannelPdfTable {
  public:
    // The table of the given channels when every one that is not nullptr is a TabulatedRadial
    // and they all have the same radii; nullopt otherwise (and when all are nullptr). A
    // nullptr channel's pdf is 0.
    static std::optional<ChannelPdfTable>
    of(const std::array<const RadialDistribution*, 3>& channels);

    // pdf_area(r) of the three channels (TabulatedRadial::pdfArea of each).
    glm::dvec3 pdfArea(double r) const;

  private:
    struct alignas(64) Interval {
        double r0 = 0;
        double v[3] = {0, 0, 0};     // pdf_c(r_k)
        double slope[3] = {0, 0, 0}; // d pdf_c / dr within the interval
    };
    size_t intervalOf(double r) const; // k with r_k <= r < r_{k+1}, clamped to [0, K − 2]

    std::vector<Interval> m_intervals; // K − 1
    std::vector<double> m_radii;
    bool m_quadraticGrid = false;
    double m_rLast = 0, m_invRLast = 0;
    std::array<double, 3> m_radiusMax{-1, -1, -1}; // R_m,c; −1: no channel (pdf 0)
};

} // namespace sampling
