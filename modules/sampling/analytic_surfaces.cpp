// sampling/analytic_surfaces: see analytic_surfaces.h.
#include "sampling/analytic_surfaces.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sampling {

void SphereSurface::intersectAll(const glm::dvec3& org, const glm::dvec3& dir, double tMin,
                                 double tMax, std::vector<SurfaceHit>& out) const {
    // t² + 2·b'·t + c = 0 with b' = dir·(org − centre), c = |org − centre|² − R² (|dir| = 1).
    const glm::dvec3 o = org - m_centre;
    const double bh = glm::dot(dir, o);
    const double c = glm::dot(o, o) - m_radius * m_radius;
    const double disc = bh * bh - c;
    if (!(disc > 0)) return; // a miss, or a tangent touch (no area)
    const double q = -(bh + std::copysign(std::sqrt(disc), bh));
    const double roots[2] = {q, q != 0 ? c / q : 0.0};
    for (double t : roots) {
        if (!(t >= tMin && t <= tMax)) continue;
        SurfaceHit h;
        h.t = t;
        h.point.x = org + t * dir;
        h.point.n = glm::normalize(h.point.x - m_centre);
        out.push_back(h);
    }
}

double SphereSurface::area() const {
    return 4 * std::numbers::pi * m_radius * m_radius;
}

SurfacePoint SphereSurface::sampleArea(double u0, double u1, double) const {
    const double z = 1 - 2 * u0, s = std::sqrt(std::max(0.0, 1 - z * z));
    const double phi = 2 * std::numbers::pi * u1;
    SurfacePoint p;
    p.n = {s * std::cos(phi), s * std::sin(phi), z};
    p.x = m_centre + m_radius * p.n;
    return p;
}

PlaneSurface::PlaneSurface(const glm::dvec3& point, const glm::dvec3& normal)
    : m_point(point), m_normal(glm::normalize(normal)) {}

void PlaneSurface::intersectAll(const glm::dvec3& org, const glm::dvec3& dir, double tMin,
                                double tMax, std::vector<SurfaceHit>& out) const {
    const double denom = glm::dot(dir, m_normal);
    if (denom == 0) return;
    const double t = glm::dot(m_point - org, m_normal) / denom;
    if (!(t >= tMin && t <= tMax)) return;
    SurfaceHit h;
    h.t = t;
    h.point.x = org + t * dir;
    h.point.n = m_normal;
    out.push_back(h);
}

} // namespace sampling
