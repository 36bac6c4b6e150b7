// render/camera: the orbit camera of the point-cloud view (thesis 3.6.4): it looks at `target`
// from `distance` away, the direction given by yaw (around +y; 0 puts the camera on +z) and
// pitch (positive = above), y up, vertical field of view fovY, aspect width/height.
//   position = target + distance·(cos(pitch)·sin(yaw), sin(pitch), cos(pitch)·cos(yaw))
//   view = lookAt(position, target, +y); projection = OpenGL perspective with
//   near = max(1e-3·distance, distance − 1.5·radius), far = distance + 1.5·radius, where
//   radius is the framed object's bounding-sphere radius (`radius`).
// fit(mesh) frames a mesh: target = bounding-box centre, radius = largest vertex distance
// from it, distance such that the bounding sphere fits the narrower field of view with 5 %
// margin: distance = 1.05·radius / sin(min(fovY, fovX)/2).
#pragma once

#include "core/limits.h"
#include "mesh/mesh.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace render {

struct Camera {
    glm::vec3 target{0.0f};
    float yaw = 0.0f;        // radians
    float pitch = 0.0f;      // radians, clamped to ±89° when used
    float distance = 2.5f;   // mesh units
    float fovY = 0.6981317f; // radians (40°)
    float aspect = 16.0f / 9.0f;
    float radius = 0.8660254f; // bounding-sphere radius of what is framed (clip planes)

    glm::vec3 position() const;
    glm::mat4 view() const;
    glm::mat4 projection() const;
    void fit(const mesh::Mesh& m);
};
// The description of Camera's members (core/fields.h).
template <class V> void fields(V& v, Camera& c) {
    v("target", c.target, "point looked at, mesh units");
    v("yaw", c.yaw, "orbit angle about +y, radians");
    v("pitch", c.pitch, "orbit elevation, radians");
    v("distance", c.distance, "distance from the target, mesh units", core::Limits{1e-6, 1e6});
    v("fov_y", c.fovY, "vertical field of view, radians", core::Limits{0.001, 3.1});
    v.skip(c.aspect, "replaced by the image's width/height");
    v("radius", c.radius, "bounding-sphere radius of the framed object (clip planes)",
      core::Limits{1e-9, 1e9});
}

} // namespace render
