#version 450
// The local term of the hybrid method (seed 004 §3.3.2, modules/texspace/hybrid.h): per G-buffer
// pixel x_o (mesh units) the ring filter around its projection on the directional light's plane,
//   B_l(x_o) = Σ_taps E0 · Ft(η, n_i·L) · R_d(d_i) · W_l(d_i) · A_tap,   d_i = Scale·|x_i − x_o|,
// x_i and n_i the first surface the light sees at the tap (the light-view map; a tap where the
// light sees nothing, or a back-facing normal, adds 0), R_d from the model's profile table,
// W_l(r) = 1 − ½e^{(r−R_p)K} (r <= R_p), ½e^{−(r−R_p)K} (r > R_p) per channel, A_tap in mm².
// Light plane coordinates: ((p − c)·u, (p − c)·v) in mesh units, texel = floor((0.5 + 0.5·q/e)·M)
// (irradiance/light_frame.h; the map is not flipped: row 0 at v = 0).
// Output per pixel p = y·width + x (row 0 the top, as the G-buffer): LocalExitance[p] = (B_l, hit),
// LocalRadiance[p] = (Ft(η, cos θo)/π · B_l, hit), cos θo = min(1, |n_o·ω_o|).
// LocalTapMode 1 and 2 serve the allowance of another driver's map (texspace/local_spread.cpp):
// for the j-th of LocalPixelCount listed pixels (LocalPixels, one workgroup of 64 a dispatch
// group) and tap t, k = j·taps + t: mode 1 keeps each tap's own L_o term (TapOwn[k]) and clears
// its spreads; mode 2 raises TapSpread[2k + LocalTapGroup] to |this map's or lookup's term −
// TapOwn[k]|, per channel (group 0: the map's moves, 1: the lookups').
layout(local_size_x = 8, local_size_y = 8) in;

#include "common/octree_profile.glsl"

layout(rgba32f, binding = 0) readonly uniform image2D GPosition;
layout(rgba32f, binding = 1) readonly uniform image2D GNormal;
layout(rgba32f, binding = 2) readonly uniform image2D LightPosition;
layout(rgba32f, binding = 3) readonly uniform image2D LightNormal;
layout(std430, binding = 5) readonly buffer LocalTaps { vec4 localTaps[]; }; // offset mm, area mm²
// (M, 1) and (Ft/π · M, 1) per pixel, in two blocks of 16 bytes a pixel, not one of 32: a block
// of 32 bytes a pixel would pass NVIDIA's GL_MAX_SHADER_STORAGE_BLOCK_SIZE (2^31 - 1) at 8192²
layout(std430, binding = 6) writeonly buffer LocalExitance { vec4 localExitance[]; };
layout(std430, binding = 7) writeonly buffer LocalRadiance { vec4 localRadiance[]; };
layout(std430, binding = 8) readonly buffer LocalPixels { uint localPixels[]; };
layout(std430, binding = 9) buffer TapOwn { vec4 tapOwn[]; };
layout(std430, binding = 10) buffer TapSpread { vec4 tapSpread[]; };

uniform ivec2 LocalSize;
uniform int LocalRowOffset; // first row of this dispatch (the host dispatches bands of rows)
uniform int LocalTapCount;
uniform int LightMapSize;
uniform vec2 LocalLookupShift; // texels; 0 but for an emulated other driver (texspace/hybrid.h)
uniform vec3 LightCentre, LightU, LightV, LightW;
uniform float LightExtent;
uniform vec3 LightIrradiance; // E0, RGB
uniform float LocalIor;       // η
uniform float LocalScale;     // mm per mesh unit
uniform vec3 LocalRp;         // R_p per channel, mm
uniform float LocalK;         // 1/mm
uniform vec3 LocalCamera;     // mesh units
uniform int LocalTapMode;     // 0: the local term; 1, 2: the taps of listed pixels (above)
uniform uint LocalPixelCount;
uniform int LocalTapGroup;

float localFresnelTransmittance(float cosI, float eta) {
    if (eta == 1.0) return 1.0;
    if (cosI <= 0.0) return 0.0;
    float sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return 0.0;
    float cosT = sqrt(1.0 - sin2T);
    float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
}

vec3 localWeight(float r) {
    vec3 d = vec3(r) - LocalRp;
    vec3 below = 1.0 - 0.5 * exp(d * LocalK);
    vec3 above = 0.5 * exp(-d * LocalK);
    return mix(below, above, greaterThan(d, vec3(0.0)));
}

// One tap's term of M at x_o, whose light-plane coordinates are q (0 where the light sees
// nothing there, or a surface facing away from it).
vec3 tapTerm(vec3 xo, vec2 q, int t) {
    vec4 tap = localTaps[t];
    vec2 qt = q + tap.xy / LocalScale;
    vec2 uv = 0.5 + 0.5 * qt / LightExtent;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return vec3(0.0);
    ivec2 texel = ivec2(uv * float(LightMapSize) + LocalLookupShift);
    vec4 xi = imageLoad(LightPosition, texel);
    if (xi.w == 0.0) return vec3(0.0);
    vec3 ni = imageLoad(LightNormal, texel).xyz;
    float ft = localFresnelTransmittance(dot(ni, LightW), LocalIor);
    if (ft <= 0.0) return vec3(0.0);
    float d = LocalScale * length(xi.xyz - xo);
    return (LightIrradiance * ft) * profileLookup(d) * localWeight(d) * tap.z;
}

vec2 lightPlane(vec3 xo) {
    return vec2(dot(xo - LightCentre, LightU), dot(xo - LightCentre, LightV));
}

// L_o = Ft(η, cos θo)/π · M at a surface pixel.
float radianceFactor(vec3 xo, vec3 no) {
    vec3 wo = normalize(LocalCamera - xo);
    float cosO = min(1.0, abs(dot(no, wo)));
    return localFresnelTransmittance(cosO, LocalIor) / 3.14159265358979;
}

void listedPixelTaps() {
    uint j = gl_WorkGroupID.x * 64u + gl_LocalInvocationIndex;
    if (j >= LocalPixelCount) return;
    uint p = localPixels[j];
    ivec2 pix = ivec2(int(p % uint(LocalSize.x)), int(p / uint(LocalSize.x)));
    vec4 pos = imageLoad(GPosition, pix);
    vec3 xo = pos.xyz;
    float factor = pos.w == 0.0 ? 0.0 : radianceFactor(xo, imageLoad(GNormal, pix).xyz);
    vec2 q = lightPlane(xo);
    for (int t = 0; t < LocalTapCount; ++t) {
        uint k = j * uint(LocalTapCount) + uint(t);
        vec3 term = factor == 0.0 ? vec3(0.0) : factor * tapTerm(xo, q, t);
        if (LocalTapMode == 1) {
            tapOwn[k] = vec4(term, 0.0);
            tapSpread[2u * k] = vec4(0.0);
            tapSpread[2u * k + 1u] = vec4(0.0);
        } else {
            uint s = 2u * k + uint(LocalTapGroup);
            tapSpread[s] = max(tapSpread[s], vec4(abs(term - tapOwn[k].rgb), 0.0));
        }
    }
}

void main() {
    if (LocalTapMode != 0) {
        listedPixelTaps();
        return;
    }
    ivec2 pix = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, LocalRowOffset);
    if (pix.x >= LocalSize.x || pix.y >= LocalSize.y) return;
    uint p = uint(pix.y * LocalSize.x + pix.x);
    vec4 pos = imageLoad(GPosition, pix);
    if (pos.w == 0.0) {
        localExitance[p] = vec4(0.0);
        localRadiance[p] = vec4(0.0);
        return;
    }
    vec3 xo = pos.xyz;
    vec3 no = imageLoad(GNormal, pix).xyz;
    vec2 q = lightPlane(xo);
    vec3 M = vec3(0.0);
    for (int t = 0; t < LocalTapCount; ++t)
        M += tapTerm(xo, q, t);
    localExitance[p] = vec4(M, 1.0);
    localRadiance[p] = vec4(radianceFactor(xo, no) * M, 1.0);
}
