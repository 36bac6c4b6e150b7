// irradiance/light_frame: bounding sphere and orthographic light basis (see light_frame.h).
#include "irradiance/light_frame.h"

#include "core/core.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace irradiance {

BoundingSphere boundingSphere(const mesh::Mesh& m, const std::vector<glm::vec3>& points) {
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const auto& v : m.vertices) {
        const glm::vec3 p(v[0], v[1], v[2]);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    for (const auto& p : points) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    BoundingSphere s;
    if (!(lo.x <= hi.x)) return s; // nothing: unit sphere at the origin
    s.centre = 0.5f * (lo + hi);
    float r2 = 0;
    for (const auto& v : m.vertices) {
        const glm::vec3 d = glm::vec3(v[0], v[1], v[2]) - s.centre;
        r2 = std::max(r2, glm::dot(d, d));
    }
    for (const auto& p : points)
        r2 = std::max(r2, glm::dot(p - s.centre, p - s.centre));
    s.radius = std::max(std::sqrt(r2), 1e-6f);
    return s;
}

glm::vec3 LightFrame::lightCoords(const glm::vec3& p) const {
    const glm::vec3 d = p - centre;
    return {glm::dot(d, u), glm::dot(d, v), glm::dot(d, w)};
}
glm::vec2 LightFrame::uv(const glm::vec3& p) const {
    const glm::vec3 l = lightCoords(p);
    return glm::vec2(0.5f) + 0.5f * glm::vec2(l.x, l.y) / extent;
}
float LightFrame::depth(const glm::vec3& p) const {
    return 0.5f - 0.5f * lightCoords(p).z / extent;
}
glm::mat4 LightFrame::clipFromWorld() const {
    // rows: u/e, v/e, −w/e (then the translation by −c), and (0, 0, 0, 1)
    glm::mat4 m(1.0f);
    const glm::vec3 r[3] = {u / extent, v / extent, -w / extent};
    for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col)
            m[col][row] = r[row][col];
        m[3][row] = -glm::dot(r[row], centre);
    }
    return m;
}

LightFrame makeLightFrame(const glm::vec3& towardsLight, const BoundingSphere& bounds) {
    const float len = glm::length(towardsLight);
    if (!std::isfinite(len) || !(len > 0.0f))
        throw core::Error("light direction must be a finite, non-zero vector");
    LightFrame f;
    f.w = towardsLight / len;
    const glm::vec3 a = std::abs(f.w.y) > 0.999f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
    f.u = glm::normalize(glm::cross(a, f.w));
    f.v = glm::cross(f.w, f.u);
    f.centre = bounds.centre;
    f.extent = 1.02f * bounds.radius;
    return f;
}

} // namespace irradiance
