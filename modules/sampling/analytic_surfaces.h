// sampling/analytic_surfaces: the sphere and the infinite plane as probe targets (see
// surface.h). Sphere: both roots of |org + t·dir − c|² = R² by the cancellation-free quadratic
// (q = −(b + sign(b)·√disc), t = q and c/q), so a probe may find 0, 1 or 2 points; uniform area
// sampling by z = 1 − 2u, φ = 2πu' (Archimedes). Plane: the one root, none for a probe
// parallel to it; no area sampling (infinite).
#pragma once

#include "sampling/surface.h"

namespace sampling {

class SphereSurface final : public Surface, public AreaSampler {
  public:
    SphereSurface(const glm::dvec3& centre, double radius) : m_centre(centre), m_radius(radius) {}
    void intersectAll(const glm::dvec3& org, const glm::dvec3& dir, double tMin, double tMax,
                      std::vector<SurfaceHit>& out) const override;
    double area() const override;
    SurfacePoint sampleArea(double u0, double u1, double u2) const override;
    const glm::dvec3& centre() const { return m_centre; }
    double radius() const { return m_radius; }

  private:
    glm::dvec3 m_centre;
    double m_radius;
};

class PlaneSurface final : public Surface {
  public:
    // `normal` need not be unit length.
    PlaneSurface(const glm::dvec3& point, const glm::dvec3& normal);
    void intersectAll(const glm::dvec3& org, const glm::dvec3& dir, double tMin, double tMax,
                      std::vector<SurfaceHit>& out) const override;

  private:
    glm::dvec3 m_point, m_normal;
};

} // namespace sampling
