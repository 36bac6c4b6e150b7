// Irradiance stage shadow lookups (thesis 3.3.2 and Fig. 3.3): the point's light coordinates
// lc = ((p−c)·u, (p−c)·v, (p−c)·w) are projected onto layer `layer` of the depth array,
// uv = 0.5 + 0.5·lc.xy/e, depth = 0.5 − 0.5·lc.z/e (modules/irradiance/light_frame.h).
//   ShadowFilter 0 naive:   one nearest depth test, no offset                        (Fig. 3.3 a)
//   ShadowFilter 1 offset:  nearest test against depth − bias                        (b)
//   ShadowFilter 2 PCF:     hardware PCF (linear compare sampler: the 4 nearest
//                           texels tested and bilinearly weighted), depth − bias     (c)
//   ShadowFilter 3 jitter:  the mean of JitterSamples PCF lookups at uv + R·d_k·r·texel, d_k
//                           the first entries of a 16-point Poisson disk (|d_k| <= 1.234),
//                           R a rotation by an angle hashed from `salt`, r = JitterRadius  (d)
//   ShadowFilter 4 none:    V = 1, no shadowing (the lighting alone; a capture records E_t as
//                           this times V, each within its own precision)
// The offset (world units) is slope scaled, bias = DepthOffset + SlopeOffset·f·t·min(tan θ, 10)
// with t = 2e/size the texel size, θ the angle between normal and light and f the footprint
// radius of the filter in texels (the farthest texel centre it reads: √2/2, √2, 1.234·r + √2),
// i.e. the depth change of the tangent plane across the footprint; it is converted to depth
// units by 1/(2e). Outside the map the border depth 1 reads as lit.
layout(binding = 0) uniform sampler2DArrayShadow ShadowNearest;
layout(binding = 1) uniform sampler2DArrayShadow ShadowLinear;
uniform int ShadowFilter;
uniform float ShadowTexel; // 1/size (uv units)
uniform float DepthOffset;
uniform float SlopeOffset;
uniform int JitterSamples;
uniform float JitterRadius;

const vec2 kIrradiancePoisson[16] = vec2[16](
    vec2(-0.94201624, -0.39906216), vec2(0.94558609, -0.76890725), vec2(-0.09418410, -0.92938870),
    vec2(0.34495938, 0.29387760), vec2(-0.91588581, 0.45771432), vec2(-0.81544232, -0.87912464),
    vec2(-0.38277543, 0.27676845), vec2(0.97484398, 0.75648379), vec2(0.44323325, -0.97511554),
    vec2(0.53742981, -0.47373420), vec2(-0.26496911, -0.41893023), vec2(0.79197514, 0.19090188),
    vec2(-0.24188840, 0.99706507), vec2(-0.81409955, 0.91437590), vec2(0.19984126, 0.78641367),
    vec2(0.14383161, -0.14100790));

uint irradianceHash(uint x) { // PCG output hash
    uint state = x * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

float shadowVisibility(vec3 lc, float extent, float cosTheta, float layer, uint salt) {
    vec2 uv = 0.5 + 0.5 * lc.xy / extent;
    float depth = 0.5 - 0.5 * lc.z / extent;
    if (ShadowFilter == 4) return 1.0;
    if (ShadowFilter == 0) return texture(ShadowNearest, vec4(uv, layer, depth));
    float footprint = ShadowFilter == 1   ? 0.70710678
                      : ShadowFilter == 2 ? 1.41421356
                                          : 1.234 * JitterRadius + 1.41421356;
    float c = max(cosTheta, 1e-6);
    float tanT = min(sqrt(max(0.0, 1.0 - c * c)) / c, 10.0);
    float texelWorld = 2.0 * extent * ShadowTexel;
    float bias = DepthOffset + SlopeOffset * footprint * texelWorld * tanT;
    float ref = depth - 0.5 * bias / extent;
    if (ShadowFilter == 1) return texture(ShadowNearest, vec4(uv, layer, ref));
    if (ShadowFilter == 2) return texture(ShadowLinear, vec4(uv, layer, ref));
    float a = 6.28318531 * float(irradianceHash(salt) >> 8) * (1.0 / 16777216.0);
    mat2 R = mat2(cos(a), sin(a), -sin(a), cos(a));
    float sum = 0.0;
    int n = clamp(JitterSamples, 1, 16);
    for (int k = 0; k < n; ++k) {
        vec2 o = R * kIrradiancePoisson[k] * (JitterRadius * ShadowTexel);
        sum += texture(ShadowLinear, vec4(uv + o, layer, ref));
    }
    return sum / float(n);
}
