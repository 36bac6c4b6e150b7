// pathtrace/detail/ring_sampler: the azimuth of a connection point on a ring, sampled
// proportionally to 1/d² from a vertex (the connection's inverse-square falloff), by the
// wrapped Cauchy distribution (Mardia & Jupp 2000, §3.5.7).
//   A vertex at horizontal distance ρ (azimuth μ) and depth z sees the ring point at radius r
//   and azimuth θ at squared distance d² = A − B cos(θ − μ), A = r² + ρ² + z², B = 2rρ. The
//   wrapped Cauchy density (1 − c²) / (2π (1 + c² − 2c cos Δ)) is proportional to exactly that
//   1/d² when (1 + c²)/(2c) = A/B, i.e. c = B / (A + sqrt(A² − B²)) (A > B whenever z ≠ 0).
//   Its CDF from 0 is G(Δ) = atan(k tan(Δ/2))/π on (−π, π), k = (1 + c)/(1 − c), inverted as
//   tan(Δ/2) = tan(πG)/k.
#pragma once

#include <cmath>
#include <numbers>

namespace pathtrace::detail {

class RingSampler {
  public:
    // Vertex at horizontal (vx, vy), depth z (< 0), ring radius r (> 0).
    RingSampler(double vx, double vy, double z, double r) {
        const double rho2 = vx * vx + vy * vy;
        const double a = r * r + rho2 + z * z, b = 2.0 * r * std::sqrt(rho2);
        const double rho = std::sqrt(rho2);
        m_cosMu = rho2 > 0 ? vx / rho : 1.0;
        m_sinMu = rho2 > 0 ? vy / rho : 0.0;
        m_c = b > 0 ? b / (a + std::sqrt(std::fmax(0.0, (a - b) * (a + b)))) : 0.0;
        m_k = (1.0 + m_c) / (1.0 - m_c);
    }
    // The whole ring: a point (cos θ, sin θ) and its density, with no trigonometric call but
    // one tan: t = tan(Δ/2) = tan(π(ξ − ½))/k, cos Δ = (1 − t²)/(1 + t²), sin Δ = 2t/(1 + t²),
    // rotated by μ.
    void sampleRing(double xi, double& cosT, double& sinT, double& density) const {
        const double t = std::tan(kPi * (xi - 0.5)) / m_k;
        const double inv = 1.0 / (1.0 + t * t);
        const double cd = (1.0 - t * t) * inv, sd = 2.0 * t * inv;
        cosT = cd * m_cosMu - sd * m_sinMu;
        sinT = sd * m_cosMu + cd * m_sinMu;
        const double c = m_c;
        density = (1.0 - c * c) / (2.0 * kPi * (1.0 + c * c - 2.0 * c * cd));
    }
    // Density of θ on the circle (integrates to 1 over 2π) at the point (cos θ, sin θ).
    double pdf(double cosT, double sinT) const {
        const double c = m_c, cosDelta = cosT * m_cosMu + sinT * m_sinMu;
        return (1.0 - c * c) / (2.0 * kPi * (1.0 + c * c - 2.0 * c * cosDelta));
    }

  private:
    static constexpr double kPi = std::numbers::pi;
    double m_cosMu = 1, m_sinMu = 0, m_c = 0, m_k = 1;
};

} // namespace pathtrace::detail
