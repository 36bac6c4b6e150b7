#version 450
// Irradiance stage, directional light (thesis 3.3.2, "Directional Lighting"; modules/irradiance):
// per point the transmitted irradiance
//   E_t = E0 · T(uv) · Ft(eta, n·L) · max(0, n·L) · V
// with E0 the light's irradiance on a surface facing it, T the projected texture (filtered
// mode; 1 otherwise) and V the shadow-map visibility (common/irradiance_shadow.glsl, layer 0).
// result[i] = (E_t, V). T is filtered here, not by the sampler (projectedBilinear), as
// irradiance_ibl.comp filters its cubemap: a sampler may compute bilinear weights in fixed point
// (8 fractional bits: Direct3D 11, NVIDIA) or in float (llvmpipe), 2^-9 of the texel contrast
// apart. What two drivers may still differ by is a uv rounded a few ulp apart: about N ulp of
// the texel contrast for a texture N texels wide (docs/ARCHITECTURE.md, "a sampler's weights").
layout(local_size_x = 64) in;

#include "common/irradiance_lighting.glsl"
#include "common/irradiance_shadow.glsl"

layout(std430, binding = 0) readonly buffer Points { IrradiancePoint points[]; };
layout(std430, binding = 1) writeonly buffer Result { vec4 result[]; };
layout(binding = 2) uniform sampler2D Projected;

uniform uint PointCount;
uniform uint PointOffset; // first point of this dispatch
uniform vec3 LightCentre;
uniform float LightExtent;
uniform vec3 LightU;
uniform vec3 LightV;
uniform vec3 LightW; // towards the light
uniform vec3 Irradiance;
uniform float Eta;
uniform int UseProjected;

// T(uv) as GL_LINEAR with GL_CLAMP_TO_EDGE samples it (OpenGL 4.5 §8.14.2), in float
vec3 projectedBilinear(vec2 uv) {
    ivec2 size = textureSize(Projected, 0);
    precise vec2 u = uv * vec2(size) - 0.5;
    vec2 f = floor(u);
    precise vec2 w = u - f;
    ivec2 i0 = clamp(ivec2(f), ivec2(0), size - 1);
    ivec2 i1 = clamp(ivec2(f) + 1, ivec2(0), size - 1);
    vec3 a = mix(texelFetch(Projected, i0, 0).rgb, texelFetch(Projected, ivec2(i1.x, i0.y), 0).rgb,
                 w.x);
    vec3 b = mix(texelFetch(Projected, ivec2(i0.x, i1.y), 0).rgb, texelFetch(Projected, i1, 0).rgb,
                 w.x);
    return mix(a, b, w.y);
}

void main() {
    uint i = gl_GlobalInvocationID.x + PointOffset;
    if (i >= PointCount) return;
    vec3 p = points[i].position.xyz;
    vec3 n = points[i].normal.xyz;
    float c = dot(n, LightW);
    precise vec3 E = vec3(0.0);
    float V = 0.0;
    if (c > 0.0) {
        vec3 d = p - LightCentre;
        vec3 lc = vec3(dot(d, LightU), dot(d, LightV), dot(d, LightW));
        V = shadowVisibility(lc, LightExtent, c, 0.0, i);
        vec3 colour = Irradiance;
        if (UseProjected != 0) colour *= projectedBilinear(0.5 + 0.5 * lc.xy / LightExtent);
        // E_t = E_u · V with the product last: a replay forms E_t from the recorded factors in
        // float (app/pipeline/scene_capture.cpp), so bit for bit on the recording driver
        precise vec3 unshadowed = colour * (irradianceFt(c, Eta) * c);
        E = unshadowed * V;
    }
    result[i] = vec4(E, V);
}
