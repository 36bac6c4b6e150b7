#version 450
// GPU slab path tracer (thesis 3.2, Algorithm 1): the same estimator as the CPU tracer in
// modules/pathtrace (see pathtrace.h for the conventions). Semi-infinite homogeneous slab
// z < 0 under a dielectric boundary at z = 0; a pencil beam enters at the origin at normal
// incidence. MCML convention: the specular reflection R_sp is deterministic (host side) and
// the photon enters with weight EntryWeight = 1 − R_sp. Lengths in mm, σ in 1/mm.
//
// Loop structure. One flat loop per invocation, one event per iteration: a lane whose path
// ended takes the next piece of work (first the paths suspended by the previous dispatch, then
// new path indices of this round from a shared counter), so lanes do not idle next to long
// paths. After EventBudget iterations the loop stops and an unfinished path is written out
// whole (position, direction, weights, event count, RNG position) for the next dispatch to
// resume bit for bit. This bounds every dispatch (GPU watchdogs, UI frames) and matters on
// Mesa's llvmpipe: it silently ends every loop once an invocation has run 65535 loop
// iterations in total (LP_MAX_TGSI_LOOP_ITERATIONS, Mesa 22.3), which dropped long paths
// without a trace in a loop-per-path design. The budget stays below that limit, and since a
// path is saved whatever ended the loop, a driver cutting it short loses nothing either.
// No other loops (Philox is unrolled). Each dispatch's last invocation plans the next
// (common/pathtrace_queue.glsl); the host issues them indirectly until no path is left.
// Path p's random numbers are Philox(seed, p) only and the tallies are integer sums, so the
// result does not depend on budgets, dispatches or scheduling.
//
// Per event (the order of the CPU walk, modules/pathtrace/bssrdf_walk.cpp): free flight s = −ln ξ / σt; a flight that crosses
// z = 0 stops there and plays Fresnel roulette (exit with probability 1 − F, else mirror and
// fly the rest of s); at the interaction point either (Implicit) the weight loses the fraction
// σa/σt to the absorbed tally and weights below RouletteWeight play Russian roulette, or
// (Analog, Algorithm 1 as printed) the path is absorbed with probability 1 − α; then a path
// that has reached MaxEvents interactions is truncated (its weight tallied as truncated: a
// bound on the bias, see Termination in pathtrace.h; the thesis's long-path roulette is not
// used, its survivors' weights grow without bound); then a Henyey-Greenstein deflection.
// Weight a roulette removes (or adds, negative) is tallied as the path's roulette loss, so per
// path specular + reflected + absorbed + truncated + loss = 1 up to float rounding, with
// E[loss] = 0.
//
// Precision: float state (positions, directions, weights: rounding 6e-8 relative per
// operation, unbiased to first order); flight lengths from 24-bit uniforms, so at most 17.3
// mean free paths (the exponential tail beyond has probability 3e-8 per flight); Fresnel
// tests on 24 bits (2^-24 absolute), roulettes and the analog absorption test on 32-bit words.
// All of these are far below the statistical error of any run this tracer can make.
layout(local_size_x = 64) in;

// PT_SHARED_SLOTS (512u) is defined by the host when workgroup-shared tallies are on: up to 506
// bins (common/pathtrace_tally.glsl, modules/pathtrace/gpu_slab.h)
#include "common/pathtrace_rng.glsl"
#include "common/pathtrace_scatter.glsl"
#include "common/pathtrace_tally.glsl"
#include "common/pathtrace_queue.glsl"

uniform uvec2 Seed;            // 64-bit seed (lo, hi)
uniform uint EventBudget;      // loop iterations (events) per invocation and dispatch
uniform float SigmaT;          // σa + σs, 1/mm
uniform float AbsorbFraction;  // σa / σt (Implicit)
uniform bool Analog;           // absorb by roulette instead of by weight
uniform uint SurviveAlbedo;    // Analog: survive an interaction if a word < this (α·2^32)
uniform bool AlwaysScatter;    // Analog with α = 1
uniform float G;               // HG mean cosine
uniform float Eta;             // relative index of refraction (medium / outside)
uniform float EntryWeight;     // 1 − R_sp
uniform float BinsPerMm;       // bins / rMax
uniform uint Bins;             // slots: 0..Bins-1 radial bins, then the four below
uniform uint MaxEvents;        // truncate a path after this many interactions
uniform float RouletteWeight;  // Implicit: weight roulette below this weight
uniform uint SurviveWeight;    // ... survives if a word < this (p·2^32; p = 1: never played)
uniform float WeightGain;      // ... and then w *= 2^32 / SurviveWeight

// Slots after the radial bins.
uint slotBeyond() { return Bins; }       // exits at r >= rMax
uint slotAbsorbed() { return Bins + 1u; }
uint slotLossPos() { return Bins + 2u; } // roulette loss of paths that lost weight
uint slotLossNeg() { return Bins + 3u; } // |roulette loss| of paths that gained weight
uint slotTruncated() { return Bins + 4u; } // weight of paths truncated at MaxEvents
uint slotTruncatedPaths() { return Bins + 5u; } // 1 per truncated path

const uint SLAB_STREAM = 0x534C4142u; // 'SLAB': the counter's 4th word for this tracer

// A suspended path: 5 uvec4 (see save/load).
layout(std430, binding = 3) readonly buffer PtIn { uvec4 ptIn[]; };
layout(std430, binding = 4) writeonly buffer PtOut { uvec4 ptOut[]; };

struct Path {
    vec3 x, d;       // position (mm), unit direction
    float w;         // weight
    float absorbed;  // weight absorbed so far
    float loss;      // roulette loss so far
    uint events;     // interactions so far
    Rng rng;
};

Path startPath(uvec2 index) {
    Path p;
    p.x = vec3(0.0);
    p.d = vec3(0.0, 0.0, -1.0);
    p.w = EntryWeight;
    p.absorbed = 0.0;
    p.loss = 0.0;
    p.events = 0u;
    p.rng = rngInit(Seed, index, SLAB_STREAM);
    return p;
}

void savePath(uint k, Path p) {
    uint b = 5u * k;
    ptOut[b] = floatBitsToUint(vec4(p.x, p.d.x));
    ptOut[b + 1u] = floatBitsToUint(vec4(p.d.yz, p.w, p.absorbed));
    ptOut[b + 2u] = uvec4(floatBitsToUint(p.loss), p.events, p.rng.ctr.xy);
    ptOut[b + 3u] = p.rng.buf;
    ptOut[b + 4u] = uvec4(p.rng.ctr.z, p.rng.used, 0u, 0u);
}

Path loadPath(uint k) {
    uint b = 5u * k;
    vec4 q0 = uintBitsToFloat(ptIn[b]);
    vec4 q1 = uintBitsToFloat(ptIn[b + 1u]);
    uvec4 q2 = ptIn[b + 2u];
    uvec4 q4 = ptIn[b + 4u];
    Path p;
    p.x = q0.xyz;
    p.d = vec3(q0.w, q1.xy);
    p.w = q1.z;
    p.absorbed = q1.w;
    p.loss = uintBitsToFloat(q2.x);
    p.events = q2.y;
    p.rng = rngInit(Seed, q2.zw, SLAB_STREAM);
    p.rng.buf = ptIn[b + 3u];
    p.rng.ctr.z = q4.x;
    p.rng.used = q4.y;
    return p;
}

// The path has ended: tally what it absorbed and its roulette loss.
void finishPath(inout Path p) {
    ptTally(slotAbsorbed(), p.absorbed, p.rng);
    if (p.loss > 0.0) ptTally(slotLossPos(), p.loss, p.rng);
    if (p.loss < 0.0) ptTally(slotLossNeg(), -p.loss, p.rng);
}

// Ends the path at the event limit: its weight is tallied as truncated.
void truncatePath(inout Path p) {
    ptTally(slotTruncated(), p.w, p.rng);
    ptTally(slotTruncatedPaths(), 1.0, p.rng);
    finishPath(p);
}

// One event: a free flight and what happens at its end. Returns true when the path has ended
// (and is tallied).
bool advance(inout Path p) {
    float s = -log(rngOpen(p.rng)) / SigmaT;
    if (p.d.z > 0.0 && s * p.d.z >= -p.x.z) {
        // the flight reaches the surface: Fresnel roulette there
        float tSurf = max(-p.x.z / p.d.z, 0.0);
        vec2 xs = p.x.xy + tSurf * p.d.xy;
        if (rngUniform(p.rng) >= fresnelExit(p.d.z, Eta)) {
            float bin = length(xs) * BinsPerMm;
            ptTally(bin < float(Bins) ? min(uint(bin), Bins - 1u) : slotBeyond(), p.w, p.rng);
            finishPath(p);
            return true;
        }
        p.d.z = -p.d.z; // internal reflection; the rest of the flight goes on below z = 0
        p.x = vec3(xs, 0.0) + max(s - tSurf, 0.0) * p.d;
    } else {
        p.x += s * p.d;
    }
    // interaction
    p.events += 1u;
    if (Analog) {
        if (!AlwaysScatter && rngNext(p.rng) >= SurviveAlbedo) {
            p.absorbed += p.w;
            finishPath(p);
            return true;
        }
    } else {
        float dw = p.w * AbsorbFraction;
        p.absorbed += dw;
        p.w -= dw;
        if (p.w < RouletteWeight) {
            if (rngNext(p.rng) < SurviveWeight) {
                float ws = p.w * WeightGain;
                p.loss -= ws - p.w;
                p.w = ws;
            } else {
                p.loss += p.w;
                finishPath(p);
                return true;
            }
        }
    }
    if (p.events >= MaxEvents) {
        truncatePath(p);
        return true;
    }
    p.d = deflect(p.d, sampleHgCos(G, rngUniform(p.rng)), 2.0 * PT_PI * rngUniform(p.rng));
    return false;
}

void main() {
#ifdef PT_SHARED_SLOTS
    ptSharedBegin();
#endif
    Path p;
    bool busy = false;
    uint eventsLo = 0u;
    for (uint it = 0u; it < EventBudget; ++it) {
        if (!busy) {
            uint k;
            uint kind = ptTake(k);
            if (kind == 0u) break;
            if (kind == 1u) {
                p = loadPath(k);
            } else {
                p = startPath(ptPathOf(k));
            }
            busy = true;
        }
        uint before = p.events;
        busy = !advance(p);
        eventsLo += p.events - before;
    }
    if (busy) savePath(atomicAdd(ptOutCount, 1u), p);
#ifdef PT_SHARED_SLOTS
    ptSharedFlush(Bins + 6u); // the radial bins and the six slots after them
#endif
    ptFinish(eventsLo); // eventsLo <= EventBudget
}
