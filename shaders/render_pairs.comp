#version 450
// Evaluates the model's Bssrdf(Xi, Wi, Xo, Wo) for a list of pairs (positions in mm, unit
// directions): a model consumer template used by render::evaluatePairs (the CPU replica of
// the octree traversal gets its BSSRDF values here, on the same device as the renderer).
layout(local_size_x = 64) in;

#include "common/bssrdf_prelude.glsl"

#pragma bssrdf_model

uniform uint Count;
// 4 vec4 per pair: (Xi, 0), (Wi, 0), (Xo, 0), (Wo, 0)
layout(std430, binding = 0) readonly buffer Pairs { vec4 pairs[]; };
layout(std430, binding = 1) writeonly buffer Values { vec4 values[]; };

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= Count) return;
    init();
    values[i] = vec4(Bssrdf(pairs[4u * i].xyz, pairs[4u * i + 1u].xyz, pairs[4u * i + 2u].xyz,
                            pairs[4u * i + 3u].xyz),
                     0.0);
}
