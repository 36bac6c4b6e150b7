#version 450
// BSSRDF integration on the sphere (thesis 3.5; the lit-sphere setup of
// modules/pathtrace/lit_sphere.h): a model consumer template, one invocation per pixel.
//
// Setup. Sphere of radius SphereRadius (mm) at the origin; directional light, SphereLightDir
// (unit, from the surface towards the light, irradiance 1); orthographic camera looking along
// −z, image square [−SphereExtent, SphereExtent]² (mm), pixel (0, 0) at the top left. Pixel
// (i, j) (column, row) looks at the centre (x, y) = E·(2(i + ½)/W − 1, 1 − 2(j + ½)/H); it
// hits the sphere when x² + y² < R², at xo = (x, y, +sqrt(R² − x² − y²)) with n(xo) = xo / R.
//
// Estimator. Radiant exitance
//   M(xo) = ∫_A Bssrdf(xi, L, xo, n(xo)) · Ft(IOR, n(xi)·L) · max(0, n(xi)·L) dA(xi)
// by uniform area sampling, pdf 1/(4πR²): xi = R·(sqrt(1 − z²) cos φ, sqrt(1 − z²) sin φ, z),
// z = 1 − 2ξ1, φ = 2πξ2, and per sample f = Bssrdf(…) · Ft · cos⁺ · 4πR² (f = 0 without
// evaluating the model where n(xi)·L <= 0). Ft = 1 − F is the exact unpolarised Fresnel
// transmittance for light entering the medium (index IOR) from outside (index 1).
//
// Random numbers. Counter-based: sample s of pixel p under the 64-bit seed draws
//   pcg4d(uvec4(p, s_lo, s_hi, 0) ^ key),   key = pcg4d(uvec4(seed_lo, seed_hi, 'SPHR', 0)),
// pcg4d of Jarzynski & Olano, "Hash Functions for GPU Rendering", JCGT 9(3), 2020: a bijection
// of 128 bits, so for one seed every (pixel, sample) gets its own input and output. ξ1, ξ2 are
// the top 24 bits of the first two words (k·2^-24 in [0, 1)). A sample's numbers depend on
// nothing else: not on dispatch sizes, invocation order or the device.
//
// Output. Each dispatch draws samples SphereFirstSample … SphereFirstSample + SphereSamples − 1
// (64-bit index) for every pixel and WRITES (does not add) per pixel Σf and Σf² of those
// samples, RGB, into Sums[2p] and Sums[2p + 1]; pixels that miss write zeros. The sums are
// Kahan-compensated float (`precise`, so the compiler keeps the compensation), about one
// rounding per dispatch whatever its sample count; the host adds every dispatch into doubles
// (modules/bssrdf/sphere_integrator.cpp). SphereSamples stays far below Mesa llvmpipe's limit of
// 65535 loop iterations per invocation.
layout(local_size_x = 8, local_size_y = 8) in;

#include "common/bssrdf_prelude.glsl"

#pragma bssrdf_model

uniform ivec2 SphereSize;        // image width, height (pixels)
uniform float SphereRadius;      // R, mm
uniform float SphereExtent;      // E = half the image side, mm
uniform vec3 SphereLightDir;     // unit, towards the light
uniform uvec2 SphereSeed;        // 64-bit seed (lo, hi)
uniform uvec2 SphereFirstSample; // 64-bit index of this dispatch's first sample (lo, hi)
uniform uint SphereSamples;      // samples per pixel in this dispatch
uniform uint SphereSentinel;     // length of a loop run after the samples (> 0, not a constant)

layout(std430, binding = 0) writeonly buffer SphereSums { vec4 sphereSums[]; };

uvec4 spherePcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    return v;
}

// Unpolarised Fresnel transmittance 1 − F for light arriving from index 1 at cos θi in (0, 1]
// onto a medium of relative index eta (> 0); total internal reflection (eta < 1) gives 0.
float sphereFresnelTransmittance(float cosI, float eta) {
    float sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return 0.0;
    float cosT = sqrt(1.0 - sin2T);
    float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
}

void main() {
    ivec2 pix = ivec2(gl_GlobalInvocationID.xy);
    if (pix.x >= SphereSize.x || pix.y >= SphereSize.y) return;
    uint p = uint(pix.y * SphereSize.x + pix.x);

    vec2 ndc = vec2(2.0 * (float(pix.x) + 0.5) / float(SphereSize.x) - 1.0,
                    1.0 - 2.0 * (float(pix.y) + 0.5) / float(SphereSize.y));
    vec2 q = ndc * (SphereExtent / SphereRadius); // in units of R
    float q2 = dot(q, q);
    if (!(q2 < 1.0)) {
        sphereSums[2u * p] = vec4(0.0, 0.0, 0.0, 1.0);
        sphereSums[2u * p + 1u] = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    init();
    const vec3 no = vec3(q, sqrt(1.0 - q2));
    const vec3 xo = SphereRadius * no;
    const vec3 L = SphereLightDir;
    const float area = 4.0 * PI * SphereRadius * SphereRadius;
    const uvec4 key = spherePcg4d(uvec4(SphereSeed, 0x53504852u, 0u));

    uint samplesDone = 0u;
    precise vec3 sum = vec3(0.0), sumC = vec3(0.0);     // Σf and its Kahan compensation
    precise vec3 sumSq = vec3(0.0), sumSqC = vec3(0.0); // Σf²
    for (uint k = 0u; k < SphereSamples; ++k) {
        uint lo = SphereFirstSample.x + k;
        uint hi = SphereFirstSample.y + (lo < k ? 1u : 0u);
        uvec4 h = spherePcg4d(uvec4(p, lo, hi, 0u) ^ key);
        float z = 1.0 - 2.0 * (float(h.x >> 8u) * (1.0 / 16777216.0));
        float phi = 2.0 * PI * (float(h.y >> 8u) * (1.0 / 16777216.0));
        float s = sqrt(max(0.0, 1.0 - z * z));
        vec3 ni = vec3(s * cos(phi), s * sin(phi), z);
        float cosI = dot(ni, L);
        vec3 f = vec3(0.0);
        if (cosI > 0.0) {
            f = Bssrdf(SphereRadius * ni, L, xo, no) *
                (sphereFresnelTransmittance(min(cosI, 1.0), IOR) * cosI * area);
        }
        precise vec3 y = f - sumC;
        precise vec3 t = sum + y;
        sumC = (t - sum) - y;
        sum = t;
        precise vec3 y2 = f * f - sumSqC;
        precise vec3 t2 = sumSq + y2;
        sumSqC = (t2 - sumSq) - y2;
        sumSq = t2;
        ++samplesDone;
    }
    // Mesa llvmpipe ends every loop of an invocation once 65535 iterations have run in all
    // (nested loops included): a model with loops of its own (quantized diffusion's lobes) can
    // use that up, cutting samples short. Then this loop is cut too; .w = 0 tells the host,
    // which takes fewer samples per dispatch (sphere_integrator.cpp).
    uint sentinel = 0u;
    for (uint k = 0u; k < SphereSentinel; ++k)
        ++sentinel;
    const float complete = samplesDone == SphereSamples && sentinel == SphereSentinel ? 1.0 : 0.0;
    sphereSums[2u * p] = vec4(sum, complete);
    sphereSums[2u * p + 1u] = vec4(sumSq, complete);
}
