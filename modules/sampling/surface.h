// sampling/surface: the geometry the disk estimator probes (King et al. 2013, "we cast probe
// rays ... and compute the incoming irradiance at all intersection points we find inside the
// sphere"), behind one small interface so that the analytic sphere, the infinite plane and a
// triangle mesh (Embree) are interchangeable; and uniform area sampling of the same shapes
// (thesis 3.5's estimator), against which the disk estimator is compared.
#pragma once

#include <glm/vec3.hpp>

#include <vector>

namespace sampling {

// A point of the surface with its unit (outward) normal.
struct SurfacePoint {
    glm::dvec3 x{0.0};
    glm::dvec3 n{0, 0, 1};
};

struct SurfaceHit {
    double t = 0; // org + t·dir
    SurfacePoint point;
};

class Surface {
  public:
    virtual ~Surface() = default;
    // Appends EVERY intersection of org + t·dir with the surface for t in [tMin, tMax] (in any
    // order; a grazing ray that only touches the surface may give none). dir is unit length.
    // Safe to call from several threads at once.
    virtual void intersectAll(const glm::dvec3& org, const glm::dvec3& dir, double tMin,
                              double tMax, std::vector<SurfaceHit>& out) const = 0;
};

// Shapes of finite area that can be sampled uniformly: x with density 1/area().
class AreaSampler {
  public:
    virtual ~AreaSampler() = default;
    virtual double area() const = 0;
    // From three independent uniforms in [0, 1).
    virtual SurfacePoint sampleArea(double u0, double u1, double u2) const = 0;
};

} // namespace sampling
