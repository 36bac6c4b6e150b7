// pathtrace_tally.glsl: exact, order-independent tallies for the GPU path tracers with 32-bit
// integer atomics only (float atomics are not core OpenGL); no #version here. Needs
// common/pathtrace_rng.glsl first.
//
// A tally slot holds Σv and Σv² over the paths that reached it, each as a 64-bit unsigned
// fixed-point number with 32 fraction bits (unit 2^-32), stored as two uint words (lo, hi):
//   word 4·slot + 0/1: Σv lo/hi,   word 4·slot + 2/3: Σv² lo/hi.
// A 64-bit add is an atomicAdd on lo plus, when it wrapped (old + lo < old), a carry into hi:
// every wrap is seen by exactly one adder, so the pair is an exact 64-bit sum in any order.
// Values are rounded to the 2^-32 grid stochastically with the path's own random numbers
// (round up with probability equal to the remainder), so E[tally] = Σv: the quantisation adds
// variance below 2^-66 per contribution and no bias (up to the 2^-24 resolution of the
// rounding variate: < 2^-56 per contribution). v² is formed in float (relative error 2^-24,
// round to nearest) before that; it only feeds the standard errors.
//
// Overflow: a path adds at most one value per slot and atomic adds take only v ≤ HEAVY (16),
// so v² ≤ 256 and a slot grows by < (256 + 1)·2^32 per path: 2^23 paths between host
// readbacks cannot wrap 64 bits (the slab and sphere tracers' host reads back once per round,
// in which at most 2^16 paths end; the BSSRDF walk, which adds per loop iteration, after every
// dispatch: modules/pathtrace/detail/gpu_work_queue.h, TallyReads).
// Heavier values (possible only for a weight-roulette survival probability below 1/160, whose
// survivors carry rouletteWeight/p), and anything non-finite or negative, go to the heavy list
// as float bits (slot, bits) for the host to add exactly; the host sizes it for every slot a
// path can reach with a weight (exit or truncation, absorbed, roulette loss: 3 per path of a
// dispatch), so it cannot fill, and the count shows any excess.

const float PT_HEAVY_WEIGHT = 16.0;

layout(std430, binding = 0) coherent buffer PtTally { uint ptAcc[]; };
layout(std430, binding = 1) coherent buffer PtHeavy {
    uint ptHeavyCount;
    uint ptHeavyPad;
    uvec2 ptHeavy[];
};
// The entries ptHeavy holds, set by the host: the .length() of a runtime-sized array is not to
// be relied on (Mesa's zink returned too small a length, and every entry was dropped).
uniform uint PtHeavyCapacity;

// v in [0, 2^31) as 32.32 fixed point, stochastically rounded with xi in [0, 1).
uvec2 ptFixed(float v, float xi) {
    float ip = floor(v);
    float scaled = (v - ip) * 4294967296.0; // exact: a float minus its integer part, times 2^32
    float fl = floor(scaled);
    uint lo = uint(fl);
    uint hi = uint(ip);
    if (xi < scaled - fl) {
        lo += 1u;
        if (lo == 0u) hi += 1u;
    }
    return uvec2(lo, hi);
}

void ptAdd64(uint word, uvec2 v) {
    uint old = atomicAdd(ptAcc[word], v.x);
    uint carry = (old + v.x < old) ? 1u : 0u;
    if (v.y + carry != 0u) atomicAdd(ptAcc[word + 1u], v.y + carry);
}

#ifdef PT_SHARED_SLOTS
// Workgroup-shared tallies (a tracer that defines PT_SHARED_SLOTS before this file: the slab
// tracer). Most paths leave within a few bins of the beam, so the global atomics of every
// workgroup meet on a handful of words; instead each workgroup sums into its own copy of the
// slots in shared memory (the same 64-bit words, the same carries) and adds its nonzero sums to
// the global ones once, at the end of the dispatch. Integer sums in any order: the tally is
// bitwise the same. Overflow: one workgroup and dispatch adds at most 64 invocations ×
// 32768 events × 256 · 2^32 < 2^61 per word. The host sets PtSharedTally only when every slot
// fits (slots ≤ PT_SHARED_SLOTS); the tracer calls ptSharedBegin() first and ptSharedFlush()
// last, both in uniform control flow (they hold barrier()s).
shared uint ptShared[4u * PT_SHARED_SLOTS];
uniform bool PtSharedTally;

void ptAdd64Shared(uint word, uvec2 v) {
    uint old = atomicAdd(ptShared[word], v.x);
    uint carry = (old + v.x < old) ? 1u : 0u;
    if (v.y + carry != 0u) atomicAdd(ptShared[word + 1u], v.y + carry);
}

void ptSharedBegin() {
    if (!PtSharedTally) return;
    for (uint i = gl_LocalInvocationIndex; i < 4u * PT_SHARED_SLOTS; i += gl_WorkGroupSize.x)
        ptShared[i] = 0u;
    barrier();
}

// Adds the workgroup's sums of slots [0, slots) to the global tally.
void ptSharedFlush(uint slots) {
    if (!PtSharedTally) return;
    barrier(); // every invocation's last shared add before anyone reads the sums
    for (uint s = gl_LocalInvocationIndex; s < slots; s += gl_WorkGroupSize.x)
        for (uint m = 0u; m < 2u; ++m) {
            uint w = 4u * s + 2u * m;
            uvec2 v = uvec2(ptShared[w], ptShared[w + 1u]);
            if (v != uvec2(0u)) ptAdd64(w, v);
        }
}
#endif

// Adds one path's value v to slot `slot` (first and second moment).
void ptTally(uint slot, float v, inout Rng rng) {
    if (v == 0.0) return;
    if (!(v > 0.0 && v <= PT_HEAVY_WEIGHT)) {
        uint i = atomicAdd(ptHeavyCount, 1u);
        if (i < PtHeavyCapacity) ptHeavy[i] = uvec2(slot, floatBitsToUint(v));
        return;
    }
    uvec2 first = ptFixed(v, rngUniform(rng));
    uvec2 second = ptFixed(v * v, rngUniform(rng));
#ifdef PT_SHARED_SLOTS
    if (PtSharedTally) {
        ptAdd64Shared(4u * slot, first);
        ptAdd64Shared(4u * slot + 2u, second);
        return;
    }
#endif
    ptAdd64(4u * slot, first);
    ptAdd64(4u * slot + 2u, second);
}

// Adds a value to the first moment of slot `slot` only (for tallies whose second moments are
// formed otherwise, e.g. from batch sums: shaders/bssrdf_walk.comp). Same range rules.
void ptTallySum(uint slot, float v, inout Rng rng) {
    if (v == 0.0) return;
    if (!(v > 0.0 && v <= PT_HEAVY_WEIGHT)) {
        uint i = atomicAdd(ptHeavyCount, 1u);
        if (i < PtHeavyCapacity) ptHeavy[i] = uvec2(slot, floatBitsToUint(v));
        return;
    }
    ptAdd64(4u * slot, ptFixed(v, rngUniform(rng)));
}
