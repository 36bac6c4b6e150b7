// sampling/frame: the shading frame (P, N, T, B) whose three axes King et al. 2013 choose the
// probe direction from. T and B complete N to a right-handed orthonormal basis by the
// branch-free construction of Duff et al. 2017 ("Building an orthonormal basis, revisited",
// JCGT 6(1)), continuous except where N.z changes sign.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace sampling {

struct Frame {
    glm::dvec3 p{0.0}, n{0, 0, 1}, t{1, 0, 0}, b{0, 1, 0};

    // Axis a of the probe: 0 = N, 1 = T, 2 = B.
    const glm::dvec3& axis(int a) const { return a == 0 ? n : (a == 1 ? t : b); }

    // `normal` need not be unit length (it is normalised).
    static Frame fromNormal(const glm::dvec3& point, const glm::dvec3& normal) {
        Frame f;
        f.p = point;
        f.n = glm::normalize(normal);
        const double sign = std::copysign(1.0, f.n.z);
        const double a = -1.0 / (sign + f.n.z);
        const double c = f.n.x * f.n.y * a;
        f.t = {1.0 + sign * f.n.x * f.n.x * a, sign * c, -sign * f.n.x};
        f.b = {c, sign + f.n.y * f.n.y * a, -f.n.y};
        return f;
    }
};

} // namespace sampling
