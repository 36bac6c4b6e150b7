// pathtrace_rng.glsl: counter-based random numbers for the GPU path tracers; no #version here.
//
// Philox4x32-10 (Salmon, Moraes, Dror & Shaw, "Parallel random numbers: as easy as 1, 2, 3",
// SC 2011; Random123). A path's stream is a pure function of (seed, path index, stream tag):
//   key     = the 64-bit seed (lo, hi)
//   counter = (path lo, path hi, block, stream tag); block counts the 4-word blocks drawn.
// So every path draws the same numbers whatever invocation, dispatch or driver traces it.
// Floats take the top 24 bits (the thesis, Appendix A.1, takes 23 from an LCG; Philox is a
// crush-resistant generator whose words are all equally good):
//   rngUniform  k·2^-24        in [0, 1)   (roulette tests: P(ξ < p) = ceil(p·2^24)/2^24)
//   rngOpen    (k + ½)·2^-24   in (0, 1)   (log arguments: −ln ξ ≤ 17.3, never infinite)

const uint PHILOX_M0 = 0xD2511F53u;
const uint PHILOX_M1 = 0xCD9E8D57u;
const uint PHILOX_W0 = 0x9E3779B9u;
const uint PHILOX_W1 = 0xBB67AE85u;

uvec4 philoxRound(uvec4 ctr, uvec2 key) {
    uint hi0, lo0, hi1, lo1;
    umulExtended(PHILOX_M0, ctr.x, hi0, lo0);
    umulExtended(PHILOX_M1, ctr.z, hi1, lo1);
    return uvec4(hi1 ^ ctr.y ^ key.x, lo1, hi0 ^ ctr.w ^ key.y, lo0);
}

// Philox4x32 with 10 rounds (Random123 kat_vectors: counter 0, key 0 -> 6627e8d5 e169c58d
// bc57ac4c 9b00dbd8). Unrolled by hand: llvmpipe counts every loop iteration of an invocation
// against one limit (see pathtrace_slab.comp), so the tracers keep loops to the one they budget.
uvec4 philox4x32_10(uvec4 ctr, uvec2 key) {
    const uvec2 bump = uvec2(PHILOX_W0, PHILOX_W1);
    ctr = philoxRound(ctr, key);
    ctr = philoxRound(ctr, key += bump);
    ctr = philoxRound(ctr, key += bump);
    ctr = philoxRound(ctr, key += bump);
    ctr = philoxRound(ctr, key += bump);
    ctr = philoxRound(ctr, key += bump);
    ctr = philoxRound(ctr, key += bump);
    ctr = philoxRound(ctr, key += bump);
    ctr = philoxRound(ctr, key += bump);
    ctr = philoxRound(ctr, key += bump);
    return ctr;
}

struct Rng {
    uvec4 ctr;  // (path lo, path hi, next block, stream tag)
    uvec2 key;  // seed
    uvec4 buf;  // current block
    uint used;  // words of buf already returned
};

Rng rngInit(uvec2 seed, uvec2 path, uint stream) {
    Rng r;
    r.ctr = uvec4(path, 0u, stream);
    r.key = seed;
    r.buf = uvec4(0u);
    r.used = 4u;
    return r;
}

uint rngNext(inout Rng r) {
    if (r.used == 4u) {
        r.buf = philox4x32_10(r.ctr, r.key);
        r.ctr.z += 1u;
        r.used = 0u;
    }
    uint v = r.buf[r.used];
    r.used += 1u;
    return v;
}

float rngUniform(inout Rng r) {
    return float(rngNext(r) >> 8) * (1.0 / 16777216.0);
}

float rngOpen(inout Rng r) {
    return (float(rngNext(r) >> 8) + 0.5) * (1.0 / 16777216.0);
}
