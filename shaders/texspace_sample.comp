#version 450
// Texture-space importance sampling, stage 2 (Chang 2007, seed 004, §3.2.2, Algorithm 3.1):
// N texels drawn by descending the mip-ordered CDF, one invocation per sample, every sample
// independent (counter-based random numbers), so one sample set serves every outgoing point.
//
// Levels. The pyramid of sums (modules/texspace/texture_space.h, MipCdf): level 0 the K × K
// texel weights, level l of side K/2^l the sums of its 2 × 2 children, concatenated finest first
// in Levels[], level l starting at LevelOffset[l]; LevelCount levels (the last has one value).
// Descent. From the top, p = u · total; at each level the four children in the order of the
// paper's texel_next offsets ((0,0), (1,0), (1,1), (0,1) within the parent): the first whose
// weight exceeds the rest of p is taken, p minus the weights before it carries on. Rounding can
// leave p at or beyond the last child's end: the last child with weight is taken then.
// Random numbers. Sample s (64-bit index) under the 64-bit seed: u = the top 24 bits of the first word of
// pcg4d(uvec4(s_lo, s_hi, 0, 0) ^ pcg4d(uvec4(seed_lo, seed_hi, 'TXSM', 0))) (Jarzynski
// & Olano 2020), as a multiple of 2^-24 in [0, 1); u itself is written too, so a host replica can
// descend with the same u.
layout(local_size_x = 64) in;

uniform uint SampleCount;
uniform uint LevelCount;
uniform uint TextureSize;       // K, a power of two
uniform uvec2 SampleSeed;       // 64-bit seed (lo, hi)
uniform uvec2 SampleFirst;      // 64-bit index of this dispatch's first sample (lo, hi)
uniform uint LevelOffset[16];   // start of level l in Levels[]

layout(std430, binding = 0) readonly buffer MipLevels { float Levels[]; };
layout(std430, binding = 1) writeonly buffer Samples { uvec2 samples[]; }; // (texel, u bits)

uvec4 texspacePcg4d(uvec4 v) {
    v = v * 1664525u + 1013904223u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    v ^= v >> 16u;
    v.x += v.y * v.w;
    v.y += v.z * v.x;
    v.z += v.x * v.y;
    v.w += v.y * v.z;
    return v;
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= SampleCount) return;
    uint lo = SampleFirst.x + i;
    uint hi = SampleFirst.y + (lo < i ? 1u : 0u);
    uvec4 key = texspacePcg4d(uvec4(SampleSeed, 0x5458534du, 0u));
    uint bits = texspacePcg4d(uvec4(lo, hi, 0u, 0u) ^ key).x >> 8u;
    float u = float(bits) * (1.0 / 16777216.0);
    // precise: u * total and the first p -= w must not be contracted into one fma (NVIDIA does
    // where it may), or a u within an ulp of a child's end takes another texel there than on the
    // host replica and on drivers that round each step (the capture's samples are compared exactly)
    precise float p = u * Levels[LevelOffset[LevelCount - 1u]];
    uint x = 0u, y = 0u;
    const uvec2 child[4] = uvec2[4](uvec2(0u, 0u), uvec2(1u, 0u), uvec2(1u, 1u), uvec2(0u, 1u));
    for (int l = int(LevelCount) - 2; l >= 0; --l) {
        uint side = TextureSize >> uint(l);
        int chosen = -1, lastNonZero = 0;
        for (int k = 0; k < 4; ++k) {
            uvec2 c = uvec2(2u * x, 2u * y) + child[k];
            float w = Levels[LevelOffset[l] + c.y * side + c.x];
            if (w > 0.0) lastNonZero = k;
            if (chosen < 0 && w > 0.0 && p < w) chosen = k;
            if (chosen < 0) p -= w;
        }
        if (chosen < 0) {
            chosen = lastNonZero;
            uvec2 c = uvec2(2u * x, 2u * y) + child[chosen];
            p = 0.5 * Levels[LevelOffset[l] + c.y * side + c.x];
        }
        x = 2u * x + child[chosen].x;
        y = 2u * y + child[chosen].y;
    }
    samples[i] = uvec2(y * TextureSize + x, bits);
}
