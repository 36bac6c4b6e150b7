// sampling/inverse_cdf_radial: a radial distribution given by its inverse CDF at uniformly spaced
// probabilities — how a model's analytic sampler (its `::begin sample` section, materials/
// README.md) reaches the CPU: SampleRadius(ξ) evaluated once (on the GPU) at ξ_j = j/J,
// j = 0 … J, giving radii ρ_j. It is that sampler evaluated on a grid, not the closed form.
//   Between knots the disk is sampled uniformly in AREA within the annulus ρ_j <= r <= ρ_{j+1}:
//       r(u)         = sqrt(ρ_j² + t·(ρ_{j+1}² − ρ_j²)),  t = (u − ξ_j)/(ξ_{j+1} − ξ_j),
//       pdf_area(r)  = (ξ_{j+1} − ξ_j) / (π (ρ_{j+1}² − ρ_j²)),
//       cdf(r)       = ξ_j + (ξ_{j+1} − ξ_j)·(r² − ρ_j²)/(ρ_{j+1}² − ρ_j²),
//   so sample(), pdfArea() and cdf() describe exactly one distribution (the disk estimator
//   divides by the density of the point it sampled), whose CDF is the sampler's at every knot,
//   and the density is finite at r = 0. Knots whose radius does not exceed the last kept one
//   (float rounding; a sampler that is not increasing) are dropped, their probability going to
//   the next annulus; if the last radii repeat, the last kept annulus ends at ξ = 1.
//   R_m = the given radiusMax (MaxRadius of the sampler, >= ρ_J); the density is 0 beyond ρ_J.
//   profile() and totalEnergy() are those of the model's tabulated profile passed in, and
//   keptEnergy() its energy within R_m: the sampler does not see the profile.
//   Errors (core::Error(name, 0, "channel c: …")): fewer than 2 knots, a radius that is not finite
//   or negative, radiusMax below ρ_J or not finite, all radii equal.
#pragma once

#include "sampling/radial.h"
#include "sampling/tabulated_radial.h"

#include <string>
#include <vector>

namespace sampling {

class InverseCdfRadial final : public RadialDistribution {
  public:
    // radii[j] = the sampler's radius at ξ_j = j/(radii.size() − 1).
    InverseCdfRadial(const std::vector<double>& radii, double radiusMax, TabulatedRadial profile,
                     int channel = 0, const std::string& name = "analytic sampler");

    double sample(double u) const override;
    double pdfArea(double r) const override;
    double cdf(double r) const override;
    double radiusMax() const override { return m_radiusMax; }
    double profile(double r) const override { return m_profile.profile(r); }
    double totalEnergy() const override { return m_profile.totalEnergy(); }
    double keptEnergy() const override { return m_profile.energyWithin(m_radiusMax); }

    size_t annuli() const { return m_density.size(); }

  private:
    size_t annulusOf(double r) const; // a with ρ_a <= r < ρ_{a+1}, clamped to the last

    std::vector<double> m_u, m_rho, m_rho2; // kept knots: ξ, ρ, ρ²
    std::vector<double> m_density;          // pdf_area within annulus a
    std::vector<unsigned> m_annulusOfCell;  // grid cell [j/J, (j+1)/J) -> its annulus
    double m_radiusMax = 0;
    TabulatedRadial m_profile;
};

} // namespace sampling
