#version 450
// Pencil-beam profile (thesis 3.6.3): the model's Bssrdf() on the semi-infinite slab z <= 0
// with the surface normal n = (0,0,1), a normally incident pencil beam entering at the origin
// (Xi = 0, Wi = n) and light leaving at Xo = (r, 0, 0) along Wo = n. r in mm.
// With Queries = 1 the same program evaluates Bssrdf(0, Wi, Xo, Wo) at arbitrary geometry: each
// entry is three vec4 (Xo, Wi, Wo in .xyz) — the BSSRDF slice panel's bins (app/slice_model.h).
// With Sentinel > 0 (the check of a new model, bssrdf/model_probe.h) a loop of that length runs
// after Bssrdf(): a driver that stops loops after a total iteration count (Mesa llvmpipe) cuts
// it short when a loop in the model used up the budget, and .w of the value is then -1.
// With Queries = 2 (models with a `sample` section) an entry (x, channel, function) gives
// SampleRadius(x, channel) (function 0), PdfRadius(x, channel) (1) or MaxRadius(channel) (2); with
// Queries = 3 (models with the lobe interface) an entry (k, channel) gives (QdLobe(k, channel),
// QdLobeCount()) — the radial distributions of disk sampling (integrate/radial_source.h).
layout(local_size_x = 64) in;

#include "common/bssrdf_prelude.glsl"

#define BSSRDF_WANT_SAMPLE 1
#pragma bssrdf_model

uniform uint Count;
uniform uint Queries; // 0: radii, 1: (Xo, Wi, Wo), 2: sampler functions, 3: Gaussian lobes
uniform uint Sentinel; // 0, or the length of a loop that must run in full after Bssrdf()
layout(std430, binding = 0) readonly buffer Radii { vec4 radii[]; };
layout(std430, binding = 1) writeonly buffer Values { vec4 values[]; };

// .w: r (or |Xo|), -1 when the sentinel loop was cut short.
float sentinelCheck(float w) {
    uint s = 0u;
    for (uint q = 0u; q < Sentinel; ++q) s += 1u;
    return s == Sentinel ? w : -1.0;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= Count) return;
    init();
    const vec3 n = vec3(0.0, 0.0, 1.0);
    if (Queries == 1u) {
        vec3 xo = radii[3u * i].xyz, wi = radii[3u * i + 1u].xyz, wo = radii[3u * i + 2u].xyz;
        vec3 v = Bssrdf(vec3(0.0), wi, xo, wo);
        values[i] = vec4(v, sentinelCheck(length(xo)));
        return;
    }
#if defined(BSSRDF_HAS_SAMPLE)
    if (Queries == 2u) {
        vec4 q = radii[i];
        int channel = int(q.y), function = int(q.z);
        float v = function == 0 ? SampleRadius(q.x, channel)
                : function == 1 ? PdfRadius(q.x, channel) : MaxRadius(channel);
        values[i] = vec4(v, q.x, 0.0, 0.0);
        return;
    }
#endif
#if defined(BSSRDF_HAS_LOBES)
    if (Queries == 3u) {
        vec4 q = radii[i];
        values[i] = vec4(QdLobe(int(q.x), int(q.y)), float(QdLobeCount()), 0.0);
        return;
    }
#endif
    float r = radii[i].x;
    vec3 v = Bssrdf(vec3(0.0), n, vec3(r, 0.0, 0.0), n);
    values[i] = vec4(v, sentinelCheck(r));
}
