#version 450
// Irradiance stage, image based lighting with occlusion (thesis 3.3.2, last paragraphs): the
// same environment samples ω_k for every point, each treated as a directional light with its
// own shadow map (layer k of the depth array, all frames sharing centre and extent). One step
// adds, per point and channel,
//   Y_k = weight_k · Ft(eta, n·ω_k) · max(0, n·ω_k) · V_k(p)       (weight_k = L/pdf · intensity)
// to the running sums Σ Y and Σ Y² read from `prev` and written to `next` (ping-pong pair;
// record 2i holds Σ Y, 2i+1 Σ Y²). Within a step the samples are summed in order first.
layout(local_size_x = 64) in;

#include "common/irradiance_lighting.glsl"
#include "common/irradiance_shadow.glsl"

struct OccludedSample {
    vec4 direction; // xyz world, towards the light (the frame's w)
    vec4 weight;    // rgb
    vec4 u;         // frame basis (light_frame.h)
    vec4 v;
};
layout(std430, binding = 0) readonly buffer Points { IrradiancePoint points[]; };
layout(std430, binding = 1) readonly buffer Prev { vec4 prev[]; };
layout(std430, binding = 2) writeonly buffer Next { vec4 next[]; };
layout(std430, binding = 3) readonly buffer Samples { OccludedSample samples[]; };

uniform uint PointCount;
uniform uint PointOffset; // first point of this dispatch
uniform uint SampleCount;
uniform uint FirstSample; // global index of samples[0] (salts the jitter rotation)
uniform vec3 LightCentre;
uniform float LightExtent;
uniform float Eta;

void main() {
    uint i = gl_GlobalInvocationID.x + PointOffset;
    if (i >= PointCount) return;
    vec3 p = points[i].position.xyz;
    vec3 n = points[i].normal.xyz;
    vec3 d = p - LightCentre;
    vec3 sum = vec3(0.0), sumSq = vec3(0.0);
    for (uint k = 0u; k < SampleCount; ++k) {
        vec3 w = samples[k].direction.xyz;
        float c = dot(n, w);
        if (c <= 0.0) continue;
        vec3 lc = vec3(dot(d, samples[k].u.xyz), dot(d, samples[k].v.xyz), dot(d, w));
        float V = shadowVisibility(lc, LightExtent, c, float(k), i * 9781u + (FirstSample + k));
        vec3 Y = samples[k].weight.rgb * (irradianceFt(c, Eta) * c * V);
        sum += Y;
        sumSq += Y * Y;
    }
    next[2u * i] = prev[2u * i] + vec4(sum, 0.0);
    next[2u * i + 1u] = prev[2u * i + 1u] + vec4(sumSq, 0.0);
}
