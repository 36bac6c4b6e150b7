// irradiance/light_frame: the orthographic light frame of a directional light's shadow map
// (thesis 3.3.2, "Directional Lighting": the model is rendered as a depth map from the light,
// each point is transformed into the light's coordinate space and projected onto it).
//   Bounding sphere: centre c = centre of the bounding box of the mesh vertices and the points,
//   radius R = largest distance from c to any of them (at least 1e-6).
//   Basis: w = the unit direction towards the light; u = normalize(a × w) with the up hint
//   a = (0, 1, 0), or a = (0, 0, −1) when |w.y| > 0.999; v = w × u (so u × v = w: looking from
//   the light, u points right and v up).
//   Orthographic extent e = 1.02·R (a margin so that no geometry touches the clip planes).
//   A point p maps to light coordinates (x, y, z) = ((p−c)·u, (p−c)·v, (p−c)·w) and to
//     shadow-map / projected-texture coordinates  uv = 0.5 + 0.5·(x, y)/e,
//     depth = 0.5 − 0.5·z/e  (0 nearest the light, 1 farthest; the clip-space z is −z/e).
//   One shadow-map texel spans 2e/size mesh units.
#pragma once

#include "mesh/mesh.h"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <vector>

namespace irradiance {

struct BoundingSphere {
    glm::vec3 centre{0.0f};
    float radius = 1.0f;
};
BoundingSphere boundingSphere(const mesh::Mesh& m, const std::vector<glm::vec3>& points);

struct LightFrame {
    glm::vec3 centre{0.0f};
    float extent = 1.0f;
    glm::vec3 u{1, 0, 0}, v{0, 1, 0}, w{0, 0, 1};
    glm::vec3 lightCoords(const glm::vec3& p) const;
    glm::vec2 uv(const glm::vec3& p) const;
    float depth(const glm::vec3& p) const;
    // Maps world positions to clip space (x/e, y/e, −z/e, 1): the shadow pass's matrix.
    glm::mat4 clipFromWorld() const;
};

// Throws core::Error when `towardsLight` has zero length or is not finite.
LightFrame makeLightFrame(const glm::vec3& towardsLight, const BoundingSphere& bounds);

} // namespace irradiance
