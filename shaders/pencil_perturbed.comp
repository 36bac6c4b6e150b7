#version 450
// The pencil-beam profile of pencil_profile.comp (thesis 3.6.3: Bssrdf(Xi = 0, Wi = n,
// Xo = (r, 0, 0), Wo = n) on the semi-infinite slab, r in mm) with the model's transcendental
// functions moved by the error GLSL allows them (common/perturbed_builtins.glsl): the spread of
// its values over several PerturbSeeds is how far two conforming drivers may differ
// (bssrdf/conditioning.h; the replay of pencil-plot captures allows for it).
layout(local_size_x = 64) in;

#include "common/bssrdf_prelude.glsl"
#include "common/perturbed_builtins.glsl"

#pragma bssrdf_model

uniform uint Count;
layout(std430, binding = 0) readonly buffer Radii { vec4 radii[]; };
layout(std430, binding = 1) writeonly buffer Values { vec4 values[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= Count) return;
    init();
    const vec3 n = vec3(0.0, 0.0, 1.0);
    float r = radii[i].x;
    values[i] = vec4(Bssrdf(vec3(0.0), n, vec3(r, 0.0, 0.0), n), r);
}
