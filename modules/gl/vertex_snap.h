// gl/vertex_snap: another rasteriser emulated vertex by vertex (shaders/common/vertex_snap.glsl).
// GL leaves the sub-pixel precision of window coordinates to the driver (GL_SUBPIXEL_BITS >= 4),
// and each driver snaps and rounds each vertex on its own; the allowances of the light-view maps
// (irradiance::rasterShifts) and the G-buffer's raster rule (render/raster_rule.h) are tested
// against images drawn with every vertex moved by up to `texels` (pixels) along both image axes
// and `depthUlps` of depth (2^-24 each, a float depth near 0.5), from a hash of its index and
// `seed`. The default moves nothing; only tests set one.
#pragma once

#include <glm/vec3.hpp>

#include <cstdint>

namespace gl {

struct VertexSnap {
    float texels = 0.0f, depthUlps = 0.0f;
    uint32_t seed = 0;
    // The shaders' VertexSnap uniform for a width × height viewport (clip units per w): a texel
    // is 2/width and 2/height in clip x and y, and depth = 0.5·z + 0.5, so an ulp of depth is
    // 2^-23 in clip z.
    glm::vec3 clipAmplitude(int width, int height) const {
        return glm::vec3(2.0f * texels / float(width), 2.0f * texels / float(height),
                         depthUlps / 8388608.0f);
    }
};

} // namespace gl
