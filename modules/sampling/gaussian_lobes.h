// sampling/gaussian_lobes: the radial distribution of a sum of planar Gaussians (King et al.
// 2013, "a single planar gaussian" and the one-sample MIS over the Gaussians of a channel "by
// their weight", after d'Eon & Irving 2011).
//   The paper's printed formulas are garbled (R_d = 2πv e^{−r²/v} is not normalised, and its
//   warp does not invert its own pdf), so the convention here is derived afresh. A lobe of
//   variance v is the normalised 2D Gaussian (d'Eon's convention)
//       G_v(r) = exp(−r²/(2v)) / (2πv),          ∫0^∞ G_v(r) 2πr dr = 1,
//   and a channel's profile is R(r) = Σ_k w_k G_{v_k}(r), of energy W = Σ_k w_k.
//   R_m: the one radius (per channel) with Σ_k w_k e^{−R_m²/(2v_k)} = eps·W, i.e. all but eps
//   of the energy lies within R_m (solved by bisection in R², the left side decreasing).
//   Lobe k truncated at R_m keeps T_k = 1 − e^{−R_m²/(2v_k)} of its energy; its radius CDF
//   and exact inverse are
//       F_k(r) = (1 − e^{−r²/(2v)}) / T_k,       r(u) = sqrt(−2v·ln(1 − u·T_k)),
//   (evaluated with expm1/log1p). One-sample MIS over lobes: lobe k is chosen with
//   probability q_k = w_k T_k / Σ_j w_j T_j (its share of the energy kept within R_m; → w_k/W
//   as eps → 0), then r from lobe k; the balance-heuristic combined density is
//       pdf_area(r) = Σ_k q_k G_k(r)/T_k = R(r) / Σ_j w_j T_j = R(r) / E_m   (r <= R_m),
//   exactly proportional to R as for tables (choosing by w_k/W instead, with each lobe cut at
//   R_m, would not be proportional to R, and each lobe cut at its own radius would make R_m
//   per lobe). Lobes of weight 0 are kept but never chosen.
//   Errors (core::Error(name, 0, "channel c: …")): no lobes, a weight that is NaN, infinite or
//   negative, a variance that is not finite and > 0, all weights 0, eps outside (0, 1).
#pragma once

#include "sampling/radial.h"
#include "sampling/tabulated_radial.h"

#include <string>
#include <vector>

namespace sampling {

struct GaussianLobe {
    double weight = 1;   // w_k (energy of the lobe)
    double variance = 1; // v_k (mm²)
};

// The normalised 2D Gaussian G_v(r) above.
double gaussian2d(double variance, double r);

class GaussianLobes final : public RadialDistribution {
  public:
    GaussianLobes(std::vector<GaussianLobe> lobes, double eps = kDefaultEnergyLoss, int channel = 0,
                  const std::string& name = "gaussian lobes");

    double sample(double u) const override;
    double pdfArea(double r) const override;
    double cdf(double r) const override;
    double radiusMax() const override { return m_radiusMax; }
    double profile(double r) const override;
    double totalEnergy() const override { return m_total; }
    double keptEnergy() const override { return m_kept; }

    const std::vector<GaussianLobe>& lobes() const { return m_lobes; }
    // q_k, the probability of choosing lobe k.
    double lobeProbability(size_t k) const { return m_prob[k]; }
    // Lobe k alone, truncated at R_m: its inverse CDF r(u) and radius CDF F_k(r).
    double sampleLobe(size_t k, double u) const;
    double lobeCdf(size_t k, double r) const;

  private:
    std::vector<GaussianLobe> m_lobes;
    std::vector<double> m_kept_k; // T_k
    std::vector<double> m_prob;   // q_k
    std::vector<double> m_cumProb;
    double m_radiusMax = 0, m_total = 0, m_kept = 0;
};

} // namespace sampling
