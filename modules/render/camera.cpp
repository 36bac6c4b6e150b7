// render/camera: orbit camera matrices and mesh framing (see camera.h).
#include "render/camera.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace render {

namespace {
constexpr float kMaxPitch = 1.5533430f; // 89°
}

glm::vec3 Camera::position() const {
    const float p = std::clamp(pitch, -kMaxPitch, kMaxPitch);
    return target + distance * glm::vec3(std::cos(p) * std::sin(yaw), std::sin(p),
                                         std::cos(p) * std::cos(yaw));
}

glm::mat4 Camera::view() const {
    return glm::lookAt(position(), target, glm::vec3(0.0f, 1.0f, 0.0f));
}

glm::mat4 Camera::projection() const {
    const float r = std::max(radius, 1e-6f);
    const float nearPlane = std::max(1e-3f * distance, distance - 1.5f * r);
    const float farPlane = distance + 1.5f * r;
    return glm::perspective(fovY, aspect, nearPlane, farPlane);
}

void Camera::fit(const mesh::Mesh& m) {
    if (m.vertices.empty()) return;
    glm::vec3 lo(m.vertices[0][0], m.vertices[0][1], m.vertices[0][2]), hi = lo;
    for (const auto& v : m.vertices) {
        const glm::vec3 p(v[0], v[1], v[2]);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    target = 0.5f * (lo + hi);
    float r2 = 0.0f;
    for (const auto& v : m.vertices) {
        const glm::vec3 d = glm::vec3(v[0], v[1], v[2]) - target;
        r2 = std::max(r2, d.x * d.x + d.y * d.y + d.z * d.z);
    }
    radius = std::max(std::sqrt(r2), 1e-6f);
    const float fovX = 2.0f * std::atan(std::tan(0.5f * fovY) * aspect);
    const float half = 0.5f * std::min(fovY, fovX);
    distance = 1.05f * radius / std::sin(half);
}

} // namespace render
