#version 450
// The pencil-beam profile of pencil_profile.comp (thesis 3.6.3: Bssrdf(Xi = 0, Wi = n,
// Xo = (r, 0, 0), Wo = n) on the semi-infinite slab, r in mm) with the model's transcendental
// functions moved by the error GLSL allows them (common/perturbed_builtins.glsl): the spread of
// its values over several PerturbSeeds is how far two conforming drivers may differ
// (bssrdf/conditioning.h; the replay of pencil-plot and slice captures allows for it). With
// Queries = 1 an entry is three vec4 (Xo, Wi, Wo in .xyz), as pencil_profile.comp's query mode.
layout(local_size_x = 64) in;

#include "common/bssrdf_prelude.glsl"
#include "common/perturbed_builtins.glsl"

#pragma bssrdf_model

uniform uint Count;
uniform uint Queries; // 0: radii, 1: (Xo, Wi, Wo)
layout(std430, binding = 0) readonly buffer Radii { vec4 radii[]; };
layout(std430, binding = 1) writeonly buffer Values { vec4 values[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= Count) return;
    init();
    if (Queries == 1u) {
        vec3 xo = radii[3u * i].xyz, wi = radii[3u * i + 1u].xyz, wo = radii[3u * i + 2u].xyz;
        values[i] = vec4(Bssrdf(vec3(0.0), wi, xo, wo), length(xo));
        return;
    }
    const vec3 n = vec3(0.0, 0.0, 1.0);
    float r = radii[i].x;
    values[i] = vec4(Bssrdf(vec3(0.0), n, vec3(r, 0.0, 0.0), n), r);
}
