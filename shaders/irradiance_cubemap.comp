#version 450
// Irradiance cubemap by quadrature (thesis 3.3.2, "Image Based Lighting"; the thesis uses Monte
// Carlo, this is the deterministic quadrature of modules/irradiance/environment.h): for the
// centre direction n of every cubemap texel
//   E_t(n) = Σ_k  W_k · Ft(eta, n·ω_k) · max(0, n·ω_k),   W_k = L_k·Ω_k (RGB)
// over the quadrature nodes (ω_k, W_k) of the lat-long map. Nodes come in chunks (FirstNode,
// NodeCount) of at most 16384 per dispatch (llvmpipe stops a loop after 65535 iterations);
// each chunk's sum is added to acc[t] by the texel's own invocation, so the result does not
// depend on scheduling. Texel t = (face·N + j)·N + i, faces +X −X +Y −Y +Z −Z, texel (i, j) at
// s = (i + ½)/N, t = (j + ½)/N with the OpenGL cube-map face orientation (common/cube_faces.glsl).
layout(local_size_x = 64) in;

#include "common/cube_faces.glsl"
#include "common/irradiance_lighting.glsl"

struct QuadratureNode {
    vec4 direction; // xyz unit (environment frame)
    vec4 weight;    // rgb = L·Ω
};
layout(std430, binding = 0) readonly buffer Nodes { QuadratureNode nodes[]; };
layout(std430, binding = 1) buffer Acc { vec4 acc[]; };

uniform int FaceSize;
uniform uint FirstNode;
uniform uint NodeCount;
uniform float Eta;

void main() {
    uint t = gl_GlobalInvocationID.x;
    uint perFace = uint(FaceSize * FaceSize);
    if (t >= 6u * perFace) return;
    int face = int(t / perFace);
    int rem = int(t % perFace);
    vec3 n = normalize(cubeTexelDirection(face, rem % FaceSize, rem / FaceSize, FaceSize));
    vec3 sum = vec3(0.0);
    for (uint k = 0u; k < NodeCount; ++k) {
        QuadratureNode q = nodes[FirstNode + k];
        float c = dot(n, q.direction.xyz);
        if (c > 0.0) sum += q.weight.rgb * (irradianceFt(c, Eta) * c);
    }
    acc[t] += vec4(sum, 0.0);
}
