// octree_profile.glsl: the tabulated 1D profile of a radial model (materials with the
// `radial` attribute), used by shaders/octree_render.comp instead of calling Bssrdf() per
// evaluation. No #version here. The table is filled by render::Renderer (modules/render/
// profile_table.h) from Bssrdf(0, n, (r, 0, 0), n) (shaders/pencil_profile.comp) whenever the
// model, its parameters or the material change.
//
// Mapping (K = ProfileCount entries, r in mm):
//   entry k holds R(r_k), r_k = ProfileRMax·(k/(K−1))²      (dense near r = 0, where R varies most)
//   lookup: t = sqrt(r/ProfileRMax)·(K−1); r >= ProfileRMax (t >= K−1) → 0;
//           i = floor(t), f = t − i, R = T[i] + f·(T[i+1] − T[i])   (linear, in float)
// render::lookupProfile is the same arithmetic on the CPU.

uniform float ProfileRMax; // mm
uniform uint ProfileCount; // K >= 2

layout(std430, binding = 4) readonly buffer ProfileTable { vec4 profileTable[]; }; // rgb, w = r_k

vec3 profileLookup(float r) {
    float t = sqrt(r / ProfileRMax) * float(ProfileCount - 1u);
    if (!(t < float(ProfileCount - 1u))) return vec3(0.0);
    uint i = uint(t);
    float f = t - float(i);
    vec3 a = profileTable[i].xyz;
    vec3 b = profileTable[i + 1u].xyz;
    return a + f * (b - a);
}
