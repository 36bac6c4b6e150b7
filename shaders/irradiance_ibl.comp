#version 450
// Irradiance stage, image based lighting without occlusion (thesis 3.3.2, "Image Based
// Lighting"): the irradiance depends on the normal only, so it is a lookup of the precomputed
// cubemap (irradiance_cubemap.comp) at the normal rotated into the environment's frame:
//   E_t = EnvIntensity · Cube(EnvFromWorld · n).   result[i] = (E_t, 1).
layout(local_size_x = 64) in;

#include "common/irradiance_lighting.glsl"

layout(std430, binding = 0) readonly buffer Points { IrradiancePoint points[]; };
layout(std430, binding = 1) writeonly buffer Result { vec4 result[]; };
layout(binding = 3) uniform samplerCube IrradianceCube;

uniform uint PointCount;
uniform uint PointOffset; // first point of this dispatch
uniform mat3 EnvFromWorld;
uniform float EnvIntensity;

void main() {
    uint i = gl_GlobalInvocationID.x + PointOffset;
    if (i >= PointCount) return;
    vec3 n = EnvFromWorld * points[i].normal.xyz;
    result[i] = vec4(EnvIntensity * texture(IrradianceCube, n).rgb, 1.0);
}
