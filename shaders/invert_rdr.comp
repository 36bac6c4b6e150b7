#version 450
// Parameter inversion (thesis 3.4): evaluates the model's DiffuseReflectance(α′) for a batch
// of reduced albedos (one vec3 per entry, one α′ per colour channel); the host picks the
// subinterval that brackets the target R_dr and repeats.
layout(local_size_x = 64) in;

#include "common/bssrdf_prelude.glsl"

#pragma bssrdf_model

uniform uint Count;
layout(std430, binding = 0) readonly buffer Alphas { vec4 alphas[]; };
layout(std430, binding = 1) writeonly buffer Values { vec4 values[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= Count) return;
    init();
#ifdef BSSRDF_NO_DIFFUSE_REFLECTANCE
    values[i] = vec4(-1.0);
#else
    values[i] = vec4(DiffuseReflectance(alphas[i].xyz), 0.0);
#endif
}
