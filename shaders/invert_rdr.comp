#version 450
// Parameter inversion (thesis 3.4): evaluates the model's DiffuseReflectance(α′) for a batch
// of reduced albedos (one vec3 per entry, one α′ per colour channel); the host picks the
// subinterval that brackets the target R_dr and repeats. With Sentinel > 0 (the check of a new
// model, bssrdf/model_probe.h) .w is -1 where a loop of that length after DiffuseReflectance()
// was cut short: the model's loops used up a driver's total iteration budget (Mesa llvmpipe).
layout(local_size_x = 64) in;

#include "common/bssrdf_prelude.glsl"

#pragma bssrdf_model

uniform uint Count;
uniform uint Sentinel; // 0, or the length of a loop that must run in full after the model
layout(std430, binding = 0) readonly buffer Alphas { vec4 alphas[]; };
layout(std430, binding = 1) writeonly buffer Values { vec4 values[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= Count) return;
    init();
#ifdef BSSRDF_NO_DIFFUSE_REFLECTANCE
    values[i] = vec4(-1.0);
#else
    vec3 v = DiffuseReflectance(alphas[i].xyz);
    uint s = 0u;
    for (uint q = 0u; q < Sentinel; ++q) s += 1u;
    values[i] = vec4(v, s == Sentinel ? 0.0 : -1.0);
#endif
}
