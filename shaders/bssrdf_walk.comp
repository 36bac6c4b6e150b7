#version 450
// GPU BSSRDF estimate of the semi-infinite slab at oblique incidence: the random walk of Dal
// Corso & Frisvad ("On BSSRDF estimation", 2018; seed 001) with the estimators analog,
// implicit and connections — the same walk, bins and conventions as the CPU walk
// (modules/pathtrace/bssrdf_walk.cpp, whose header derives the connection estimator; geometry,
// bins and units in bssrdf_estimate.h). Host side: modules/pathtrace/gpu_bssrdf.cpp.
//
// Loop structure (as shaders/pathtrace_slab.comp): one flat loop per invocation whose
// iterations are the units of work of a path, EventBudget of them per dispatch; an unfinished
// path is saved whole and resumed by the next dispatch, so llvmpipe's 65535-iteration limit
// never drops a path and no other loop exists. A unit of work is either
//   a flight (free flight, surface event, collision with absorption / roulette / truncation /
//   Henyey-Greenstein scattering), or
//   one connection sample of the collision just reached (stage 1..RBins: technique (a) in
//   radial bin stage − 1; stage RBins + 1: technique (b), the phase-sampled direction, after
//   which the rest of the collision — absorption, roulette, truncation, scattering — runs).
// A connection walk thus spends RBins + 2 iterations per collision, each bounded.
//
// Random numbers: Philox(seed of the angle, path index) (common/pathtrace_rng.glsl), so a
// path's tallies are a function of its index only. Tallies (common/pathtrace_tally.glsl) are
// exact integer sums, times TallyScale (a power of two ≤ 1 that keeps every value a walk can
// tally mid-path ≤ 8: see gpu_bssrdf.h). Bin and cell slots are split into Batches batches by
// path index mod Batches (1 for the histogram estimators, whose per-path values are tallied
// with their squares); connections tally first moments only, and the host forms the standard
// errors from the batch sums (gpu_bssrdf.h derives it). Per-path values (exit weight,
// absorbed, roulette loss, truncated, the energy gap D) are tallied with their squares.
//
// Precision: float state as in the slab shader; the connection roulette tests a 32-bit word
// against floor(p·2^32) and divides by that same probability (unbiased; vertices with
// p < 2^-32, more than 22 mean free paths beyond d₀, do not connect: their terms are below
// e^-24 of the weight).
layout(local_size_x = 64) in;

#include "common/pathtrace_rng.glsl"
#include "common/pathtrace_scatter.glsl"
#include "common/pathtrace_tally.glsl"
#include "common/bssrdf_ring.glsl"

uniform uvec2 Seed;            // 64-bit seed of this incidence angle (lo, hi)
uniform uint EventBudget;      // loop iterations per invocation and dispatch
uniform int Estimator;         // 0 analog, 1 implicit, 2 connections
uniform int Orders;            // 0 all, 1 all but the first collision, 2 the first only
uniform float SigmaT;          // σa + σs, 1/mm
uniform float Albedo;          // α = σs / σt
uniform uint SurviveAlbedo;    // analog: survive a collision if a word < this (α·2^32)
uniform bool AlwaysScatter;    // analog with α = 1
uniform float G;               // HG mean cosine
uniform float Eta;             // relative index of refraction (medium / outside)
uniform float EntryWeight;     // 1 − R(θi)
uniform vec3 EntryDir;         // refracted beam direction (sin θt, 0, −cos θt)
uniform uint MaxEvents;        // truncate a path after this many collisions
uniform float RouletteWeight;  // implicit: weight roulette below this weight (< 0: never)
uniform uint SurviveWeight;    // ... survives if a word < this (p·2^32)
uniform float WeightGain;      // ... and then w *= 2^32 / SurviveWeight
uniform uint RBins;            // radial bins
uniform int RSpacing;          // first guess of a radius's bin: 0 uniform, 1 log from
uniform float RGuess0;         //   RGuess0 with RGuessScale bins per unit of ln r, 2 log
uniform float RGuessScale;     //   with the first bin [0, RGuess0)
uniform uint ThetaSBins;       // θs sectors over [0, π]
uniform uint DirCos;           // exit-direction rings (cos θo uniform)
uniform uint DirPhi;           // exit-direction sectors
uniform uint Batches;          // batches per bin and cell (a power of two)
uniform uint DirBase;          // first direction-cell slot
uniform uint ExtraBase;        // first per-path slot (see slot* below)
uniform float TallyScale;      // every value is tallied times this (a power of two)
uniform float RouletteDistance; // connection roulette distance d₀, mm

// The radial bin edges (RBins + 1 values, as BssrdfBins::rEdges() rounded to float).
layout(std430, binding = 6) readonly buffer BwEdges { float bwEdges[]; };

uint slotExit() { return ExtraBase; }
uint slotAbsorbed() { return ExtraBase + 1u; }
uint slotLossPos() { return ExtraBase + 2u; }
uint slotLossNeg() { return ExtraBase + 3u; }
uint slotTruncated() { return ExtraBase + 4u; }
uint slotTruncatedPaths() { return ExtraBase + 5u; }
uint slotEnergyPos() { return ExtraBase + 6u; }
uint slotEnergyNeg() { return ExtraBase + 7u; }

const uint BSSRDF_STREAM = 0x42535344u; // 'BSSD': the counter's 4th word for this walk

#include "common/pathtrace_queue.glsl"
layout(std430, binding = 3) readonly buffer PtIn { uvec4 ptIn[]; };
layout(std430, binding = 4) writeonly buffer PtOut { uvec4 ptOut[]; };

struct Path {
    vec3 x, d;      // position (mm); unit direction (at a pending connection: the arrival one)
    float w;        // weight
    float absorbed; // weight absorbed so far
    float loss;     // roulette loss so far
    uint events;    // collisions so far
    uint stage;     // 0: flight next; 1..RBins + 1: connection sample pending
    float gain;     // connection roulette weight 1/p of the pending connections
    float binned;   // connections: flux tallied into the bins so far
    Rng rng;
};

Path startPath(uvec2 index) {
    Path p;
    p.x = vec3(0.0);
    p.d = EntryDir;
    p.w = EntryWeight;
    p.absorbed = 0.0;
    p.loss = 0.0;
    p.events = 0u;
    p.stage = 0u;
    p.gain = 1.0;
    p.binned = 0.0;
    p.rng = rngInit(Seed, index, BSSRDF_STREAM);
    return p;
}

void savePath(uint k, Path p) {
    uint b = 5u * k;
    ptOut[b] = floatBitsToUint(vec4(p.x, p.d.x));
    ptOut[b + 1u] = floatBitsToUint(vec4(p.d.yz, p.w, p.absorbed));
    ptOut[b + 2u] = uvec4(floatBitsToUint(p.loss), p.events, p.rng.ctr.xy);
    ptOut[b + 3u] = p.rng.buf;
    ptOut[b + 4u] = uvec4(p.rng.ctr.z, p.rng.used | (p.stage << 3u), floatBitsToUint(p.gain),
                          floatBitsToUint(p.binned));
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
    p.rng = rngInit(Seed, q2.zw, BSSRDF_STREAM);
    p.rng.buf = ptIn[b + 3u];
    p.rng.ctr.z = q4.x;
    p.rng.used = q4.y & 7u;
    p.stage = q4.y >> 3u;
    p.gain = uintBitsToFloat(q4.z);
    p.binned = uintBitsToFloat(q4.w);
    return p;
}

bool connections() { return Estimator == 2; }

// Whether a collision (or an exit after `events` collisions) belongs to the tallied orders.
bool ordered(uint events) {
    if (Orders == 1) return events >= 2u;
    if (Orders == 2) return events == 1u;
    return events >= 1u;
}

// The radial bin of r, or -1 outside [edge 0, edge RBins). The closed-form guess is off by at
// most one bin from rounding; the edges decide.
int radialBin(float r) {
    if (r < bwEdges[0] || !(r < bwEdges[RBins])) return -1;
    float guess;
    if (RSpacing == 0) {
        guess = (r - bwEdges[0]) * RGuessScale;
    } else if (RSpacing == 1) {
        guess = log(r / RGuess0) * RGuessScale;
    } else {
        guess = r < RGuess0 ? 0.0 : 1.0 + log(r / RGuess0) * RGuessScale;
    }
    int last = int(RBins) - 1;
    int i = clamp(int(guess), 0, last);
    if (r < bwEdges[i]) i -= 1;
    else if (!(r < bwEdges[i + 1])) i += 1;
    return clamp(i, 0, last);
}

uint thetaBin(vec2 point) {
    float thetaS = atan(abs(point.y), point.x); // [0, π]
    return min(uint(thetaS * (float(ThetaSBins) / PT_PI)), ThetaSBins - 1u);
}

// The exit cell of flux leaving at `point` along the internal direction `dir` (dir.z > 0).
uint cellOf(vec2 point, vec3 dir) {
    float sin2 = Eta * Eta * (1.0 - dir.z * dir.z);
    float cosO = sqrt(max(0.0, 1.0 - sin2));
    float phi = atan(point.y < 0.0 ? -dir.y : dir.y, dir.x);
    if (phi < 0.0) phi += 2.0 * PT_PI;
    uint ring = uint(clamp(int(cosO * float(DirCos)), 0, int(DirCos) - 1));
    uint sector = uint(clamp(int(phi * (float(DirPhi) / (2.0 * PT_PI))), 0, int(DirPhi) - 1));
    return ring * DirPhi + sector;
}

// Flux v leaving in spatial bin (ir, it) at `point` along `dir`: into the bin and, with more
// than one cell, the cell. `perPath`: v is the path's only value there (histogram), tallied
// with its square; else a first moment into the path's batch.
void tallyBin(inout Path p, vec2 point, vec3 dir, float v, int ir, uint it, bool perPath) {
    uint bin = uint(ir) * ThetaSBins + it;
    uint batch = p.rng.ctr.x & (Batches - 1u);
    float sv = v * TallyScale;
    if (perPath) ptTally(bin * Batches + batch, sv, p.rng);
    else ptTallySum(bin * Batches + batch, sv, p.rng);
    uint nD = DirCos * DirPhi;
    if (nD > 1u) {
        uint slot = DirBase + (bin * nD + cellOf(point, dir)) * Batches + batch;
        if (perPath) ptTally(slot, sv, p.rng);
        else ptTallySum(slot, sv, p.rng);
    }
}

void tallyPath(uint slot, float v, inout Rng rng) {
    ptTally(slot, v * TallyScale, rng);
}

// The path has ended; `exitInside` is its exit weight inside the bins (connections only).
void finishPath(inout Path p, float exitInside) {
    tallyPath(slotAbsorbed(), p.absorbed, p.rng);
    if (p.loss > 0.0) tallyPath(slotLossPos(), p.loss, p.rng);
    if (p.loss < 0.0) tallyPath(slotLossNeg(), -p.loss, p.rng);
    // the single-order connections end the walk at its first collision: no exits to compare
    if (connections() && Orders != 2) {
        float gap = p.binned - exitInside;
        if (gap > 0.0) tallyPath(slotEnergyPos(), gap, p.rng);
        if (gap < 0.0) tallyPath(slotEnergyNeg(), -gap, p.rng);
    }
}

// f/(q_a + q_p) of bssrdf_walk.cpp for the pending collision of p (scattered weight α·w times
// the roulette gain) to the surface point `point`, with technique (a)'s area density qa there;
// 0 when nothing is transmitted. dir receives ω₂₁.
float connection(Path p, vec2 point, float qa, out vec3 dir) {
    vec3 delta = vec3(point - p.x.xy, -p.x.z);
    float d2 = dot(delta, delta);
    float d = sqrt(d2);
    dir = delta / d;
    float t21 = 1.0 - fresnelExit(dir.z, Eta);
    if (!(t21 > 0.0)) return 0.0;
    // HG: p = (1 − g²) / (4π h^{3/2}), h = 1 + g² − 2g cos = (1 − g)² + g |u − ω₂₁|² (no
    // cancellation near the forward peak of a strongly forward medium)
    vec3 du = p.d - dir;
    float h = (1.0 - G) * (1.0 - G) + G * dot(du, du);
    float phase = (1.0 - G * G) / (4.0 * PT_PI * h * sqrt(h));
    float qp = phase * dir.z / d2;
    // f/(qa + qp) = α w gain e^{−σt d} T₂₁ · qp/(qa + qp); the ratio as 1/(1 + qa/qp) stays
    // finite even where qp overflows (a vertex right under the point)
    return Albedo * p.w * p.gain * exp(-SigmaT * d) * t21 / (1.0 + qa / qp);
}

// Technique (a) in radial bin ir: r uniform in the bin, θ ∝ 1/d² on its ring.
void connectRing(inout Path p, int ir) {
    float r0 = bwEdges[ir], r1 = bwEdges[ir + 1];
    float r = r0 + (r1 - r0) * rngUniform(p.rng);
    if (!(r > 0.0)) return; // measure zero
    Ring g = ringSetup(p.x.xy, p.x.z, r);
    vec2 e;
    float density = ringSample(g, rngOpen(p.rng), e);
    vec2 point = r * e;
    vec3 dir;
    float c = connection(p, point, density / (r * (r1 - r0)), dir);
    if (c > 0.0) {
        p.binned += c;
        tallyBin(p, point, dir, c, ir, thetaBin(point), false);
    }
}

// Technique (b): one phase-sampled direction, if it meets the surface inside the bins.
void connectPhase(inout Path p) {
    vec3 v = deflect(p.d, sampleHgCos(G, rngUniform(p.rng)), 2.0 * PT_PI * rngUniform(p.rng));
    if (v.z <= 0.0) return;
    float tHit = -p.x.z / v.z;
    vec2 point = p.x.xy + tHit * v.xy;
    float r = length(point);
    int ir = radialBin(r);
    if (ir < 0 || !(r > 0.0)) return;
    Ring g = ringSetup(p.x.xy, p.x.z, r);
    float qa = ringPdf(g, point / r) / (r * (bwEdges[ir + 1] - bwEdges[ir]));
    vec3 dir;
    float c = connection(p, point, qa, dir);
    if (c > 0.0) {
        p.binned += c;
        tallyBin(p, point, dir, c, ir, thetaBin(point), false);
    }
}

// The rest of a collision after its connections: the single-order cut, absorption (analog:
// by roulette; else by weight, with weight roulette), truncation, scattering. Returns true
// when the path has ended (and is tallied).
bool afterCollision(inout Path p) {
    if (Orders == 2 && (connections() || p.events >= 2u)) {
        finishPath(p, 0.0);
        return true;
    }
    if (Estimator == 0) {
        if (!AlwaysScatter && rngNext(p.rng) >= SurviveAlbedo) {
            p.absorbed += p.w;
            finishPath(p, 0.0);
            return true;
        }
    } else {
        float wn = p.w * Albedo;
        p.absorbed += p.w - wn;
        p.w = wn;
        if (p.w < RouletteWeight) {
            if (rngNext(p.rng) < SurviveWeight) {
                float ws = p.w * WeightGain;
                p.loss -= ws - p.w;
                p.w = ws;
            } else {
                p.loss += p.w;
                finishPath(p, 0.0);
                return true;
            }
        }
    }
    if (p.events >= MaxEvents) {
        tallyPath(slotTruncated(), p.w, p.rng);
        ptTally(slotTruncatedPaths(), 1.0, p.rng);
        finishPath(p, 0.0);
        return true;
    }
    p.d = deflect(p.d, sampleHgCos(G, rngUniform(p.rng)), 2.0 * PT_PI * rngUniform(p.rng));
    return false;
}

// A free flight and what happens at its end. Returns true when the path has ended.
bool flight(inout Path p) {
    float s = -log(rngOpen(p.rng)) / SigmaT;
    if (p.d.z > 0.0 && s * p.d.z >= -p.x.z) {
        // the flight reaches the surface: Fresnel roulette there
        float tSurf = max(-p.x.z / p.d.z, 0.0);
        vec2 xs = p.x.xy + tSurf * p.d.xy;
        if (rngUniform(p.rng) >= fresnelExit(p.d.z, Eta)) {
            tallyPath(slotExit(), p.w, p.rng);
            float inside = 0.0;
            if (ordered(p.events)) {
                int ir = radialBin(length(xs));
                if (ir >= 0) {
                    if (connections()) inside = p.w;
                    else tallyBin(p, xs, p.d, p.w, ir, thetaBin(xs), true);
                }
            }
            finishPath(p, inside);
            return true;
        }
        p.d.z = -p.d.z; // internal reflection; the rest of the flight goes on below z = 0
        p.x = vec3(xs, 0.0) + max(s - tSurf, 0.0) * p.d;
    } else {
        p.x += s * p.d;
    }
    p.events += 1u;
    if (connections() && ordered(p.events)) {
        // connection roulette (bssrdf_walk.cpp, connectVertex): beyond d₀ from every bin the
        // vertex connects with probability p = e^{−σt (d_min − d₀)}, weight 1/p
        float rho = length(p.x.xy);
        float h = max(0.0, max(bwEdges[0] - rho, rho - bwEdges[RBins]));
        float dMin = sqrt(h * h + p.x.z * p.x.z);
        p.gain = 1.0;
        bool connect = true;
        if (dMin > RouletteDistance) {
            // floor(p·2^32), below 2^32 (a float next to 2^32 would not convert)
            float pc = exp(-SigmaT * (dMin - RouletteDistance));
            uint threshold = uint(min(pc * 4294967296.0, 4294967040.0));
            connect = rngNext(p.rng) < threshold;
            if (connect) p.gain = 4294967296.0 / float(threshold);
        }
        if (connect) {
            p.stage = 1u;
            return false;
        }
    }
    return afterCollision(p);
}

// One unit of work of a path. Returns true when the path has ended.
bool advance(inout Path p) {
    if (p.stage == 0u) return flight(p);
    if (p.stage <= RBins) {
        connectRing(p, int(p.stage) - 1);
        p.stage += 1u;
        return false;
    }
    connectPhase(p);
    p.stage = 0u;
    return afterCollision(p);
}

void main() {
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
    ptFinish(eventsLo); // eventsLo <= EventBudget
}
