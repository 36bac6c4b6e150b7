#version 450
// Pencil-beam profile (thesis 3.6.3): the model's Bssrdf() on the semi-infinite slab z <= 0
// with the surface normal n = (0,0,1), a normally incident pencil beam entering at the origin
// (Xi = 0, Wi = n) and light leaving at Xo = (r, 0, 0) along Wo = n. r in mm.
layout(local_size_x = 64) in;

#include "common/bssrdf_prelude.glsl"

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
