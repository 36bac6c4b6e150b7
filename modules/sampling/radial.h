// sampling/radial: the radial sampling distribution of one colour channel, the "pdf_disk(r)" of
// King et al. 2013 (eq. 1 and the text after it): a density on the disk around the shading point
// proportional to the model's radial profile R(r) and cut off at a radius R_m.
//   Convention (both implementations): the profile R(r) is a density per unit AREA of the
//   plane (as R_d(r) of Jensen et al. 2001), its energy is E = ∫0^∞ R(r) 2πr dr; R_m keeps all
//   but a fraction eps of it, E_m = ∫0^{R_m} R(r) 2πr dr = (1 − eps)·E, and
//       pdf_area(r)   = R(r) / E_m   for r <= R_m, 0 beyond (∫0^{R_m} pdf_area 2πr dr = 1),
//       pdf_radius(r) = 2πr · pdf_area(r)            (the density of the radius itself).
//   So on a plane the disk estimator R/pdf_area is the constant E_m: perfect importance
//   sampling, as the paper says. A point at angle φ = 2πu around the disk with radius
//   sample(u') then has density pdf_area per unit disk area.
#pragma once

#include <numbers>

namespace sampling {

class RadialDistribution {
  public:
    virtual ~RadialDistribution() = default;

    // A radius in [0, radiusMax()] with density pdfRadius, from u in [0, 1) (inversion, so
    // monotone in u).
    virtual double sample(double u) const = 0;
    // Density per unit area of the plane (see above); 0 for r > radiusMax() or r < 0.
    virtual double pdfArea(double r) const = 0;
    double pdfRadius(double r) const { return 2 * std::numbers::pi * r * pdfArea(r); }
    // Fraction of the kept energy within radius r: ∫0^r pdfRadius (1 at r >= radiusMax()).
    virtual double cdf(double r) const = 0;
    // R_m.
    virtual double radiusMax() const = 0;
    // The profile R(r) the distribution was built from (not truncated).
    virtual double profile(double r) const = 0;
    // E = ∫0^∞ R 2πr dr (tables: over the tabulated range) and E_m = ∫0^{R_m} R 2πr dr.
    virtual double totalEnergy() const = 0;
    virtual double keptEnergy() const = 0;
};

} // namespace sampling
