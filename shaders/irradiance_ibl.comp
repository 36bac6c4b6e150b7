#version 450
// Irradiance stage, image based lighting without occlusion (thesis 3.3.2, "Image Based
// Lighting"): the irradiance depends on the normal only, so it is a lookup of the precomputed
// cubemap (irradiance_cubemap.comp) at the normal rotated into the environment's frame:
//   E_t = EnvIntensity · Cube(EnvFromWorld · n).   result[i] = (E_t, 1).
// The lookup is filtered here, not by the sampler: a sampler may compute bilinear weights in
// fixed point (8 fractional bits, as Direct3D 11 requires and NVIDIA's do) or in float
// (llvmpipe), so two drivers' E_t would differ by up to 2^-9 of the texel contrast, past a
// capture's 1e-5. Face and (s, t) as OpenGL 4.5 Table 8.19 (ties go to x, then y); bilinear
// between the four texel centres around (s·N − ½, t·N − ½) with float weights; a tap beyond the
// face's edge takes the texel of the face its centre's direction points into (seamless, as
// GL_TEXTURE_CUBE_MAP_SEAMLESS, up to the corners, where that face is the one of its largest
// component).
layout(local_size_x = 64) in;

#include "common/cube_faces.glsl"
#include "common/irradiance_lighting.glsl"

layout(std430, binding = 0) readonly buffer Points { IrradiancePoint points[]; };
layout(std430, binding = 1) writeonly buffer Result { vec4 result[]; };
// the cubemap's texels as irradiance_cubemap.comp wrote them: t = (face·N + j)·N + i
layout(std430, binding = 2) readonly buffer Cube { vec4 cubeTexels[]; };

uniform uint PointCount;
uniform uint PointOffset; // first point of this dispatch
uniform mat3 EnvFromWorld;
uniform float EnvIntensity;
uniform int FaceSize;

vec3 cubeTexel(int face, int i, int j) {
    int n = FaceSize;
    if (i < 0 || j < 0 || i >= n || j >= n) { // beyond the edge: the neighbouring face's texel
        vec2 st;
        face = cubeFace(cubeTexelDirection(face, i, j, n), st);
        i = clamp(int(floor(st.x * float(n))), 0, n - 1);
        j = clamp(int(floor(st.y * float(n))), 0, n - 1);
    }
    return cubeTexels[(face * n + j) * n + i].rgb;
}

vec3 cubeBilinear(vec3 d) {
    vec2 st;
    int face = cubeFace(d, st);
    precise vec2 u = st * float(FaceSize) - 0.5;
    vec2 f = floor(u);
    precise vec2 w = u - f;
    int i = int(f.x), j = int(f.y);
    vec3 a = mix(cubeTexel(face, i, j), cubeTexel(face, i + 1, j), w.x);
    vec3 b = mix(cubeTexel(face, i, j + 1), cubeTexel(face, i + 1, j + 1), w.x);
    return mix(a, b, w.y);
}

void main() {
    uint i = gl_GlobalInvocationID.x + PointOffset;
    if (i >= PointCount) return;
    vec3 n = EnvFromWorld * points[i].normal.xyz;
    result[i] = vec4(EnvIntensity * cubeBilinear(n), 1.0);
}
