#version 450
// GPU lit-sphere path tracer: the estimator of modules/pathtrace/sphere_tracer.h (setup and
// pixel definition: lit_sphere.h; the walk: sphere_walk.h) with the loop structure, random
// numbers and tallies of pathtrace_slab.comp (see there: flat event loop with a per-dispatch
// budget and whole-path suspension, Philox streams, 64-bit fixed-point integer tallies).
//
// Work items: item k of a round is channel k % 3 of path (round's first) + k / 3. Channel c of path
// i draws from Philox(key = Seed, counter = (i lo, i hi, block, SPHERE_STREAM + c)): its own
// stream per channel, a pure function of (seed, path, channel).
// Source: entry point uniform on the light's projected disk (radius R), polar mapping
// (r = R·√ξ1, φ = 2πξ2; the CPU rejects in the square: same distribution). The entry ray meets
// the sphere at n = a·E1 + b·E2 + √(1 − a² − b²)·Light; the Fresnel reflectance F(n·Light) is
// specular and dropped; the path refracts in with weight 1 − F. Per path power πR²/N is
// applied by the host.
// Walk (per loop iteration either one flight ending at a boundary or one collision): flight
// s = −ln ξ/σt (or the rest of a flight after an internal reflection); a flight reaching the
// sphere plays Fresnel roulette (exit with probability 1 − F, else mirror, and the rest of
// the flight continues next iteration); a collision applies implicit absorption, weight
// roulette below RouletteWeight, truncation at MaxEvents interactions (the weight tallied in
// the channel's "truncated" slot: a bound on what the image misses), then an HG deflection. An exit tallies its weight into the channel's "exited" slot and, when visible
// (z > 0), into the pixel the exit point projects into (the host ignores pixels whose centre
// ray misses the sphere). A path that meets the boundary 2^20 times ends untallied (the CPU's
// stuck-path safeguard).
layout(local_size_x = 64) in;

#include "common/pathtrace_rng.glsl"
#include "common/pathtrace_scatter.glsl"
#include "common/pathtrace_tally.glsl"

uniform uvec2 Seed;           // 64-bit seed (lo, hi)
uniform uint EventBudget;     // loop iterations per invocation and dispatch
uniform vec3 SigmaT;          // per channel: σa + σs, 1/mm
uniform vec3 AbsorbFraction;  // per channel: σa / σt
uniform vec3 G;               // per channel: HG mean cosine
uniform vec3 Eta;             // per channel: relative index (medium / outside)
uniform float Radius;         // sphere radius, mm
uniform vec3 Light;           // unit, towards the light
uniform vec3 E1;              // frame of the plane perpendicular to Light
uniform vec3 E2;
uniform float Extent;         // image half side, mm
uniform vec2 PixelSize;       // dx, dy (mm)
uniform uvec2 ImageSize;      // width, height
uniform uint MaxEvents;       // truncate a path after this many interactions
uniform float RouletteWeight; // weight roulette below this weight (< 0: never)
uniform uint SurviveWeight;   // ... survives if a word < this
uniform float WeightGain;     // ... and then w *= 2^32 / SurviveWeight

const uint SPHERE_STREAM = 0x53504830u; // 'SPH0' + channel: the counter's 4th word
const uint MAX_BOUNDARY_HITS = 1048576u;

#include "common/pathtrace_queue.glsl"
layout(std430, binding = 3) readonly buffer PtIn { uvec4 ptIn[]; };
layout(std430, binding = 4) writeonly buffer PtOut { uvec4 ptOut[]; };

struct Path {
    vec3 x, d;      // position (mm), unit direction
    float w;        // weight
    float pending;  // rest of a flight after an internal reflection (< 0: none)
    uint events;    // collisions so far
    uint hits;      // boundary hits so far
    uint channel;
    Rng rng;
};

// Slots: channel c has pixels c·(P + 2) + p, its exited total at c·(P + 2) + P and its
// truncated weight at c·(P + 2) + P + 1.
uint pixelCount() { return ImageSize.x * ImageSize.y; }
uint slotBase(uint c) { return c * (pixelCount() + 2u); }

// Starts channel c of path `index`: entry through the lit hemisphere. Returns false when the
// path carries nothing into the sphere (total reflection at entry).
bool startPath(uvec2 index, uint c, out Path p) {
    p.rng = rngInit(Seed, index, SPHERE_STREAM + c);
    p.channel = c;
    p.events = 0u;
    p.hits = 0u;
    p.pending = -1.0;
    float rho = sqrt(rngUniform(p.rng));
    float phi = 2.0 * PT_PI * rngUniform(p.rng);
    float a = rho * cos(phi), b = rho * sin(phi);
    float h = sqrt(max(0.0, 1.0 - rho * rho));
    vec3 n = normalize(a * E1 + b * E2 + h * Light);
    float cosI = min(1.0, dot(n, Light));
    float eta = Eta[c];
    float f = fresnelExit(cosI, 1.0 / eta); // reflectance seen from outside
    float sin2T = (1.0 - cosI * cosI) / (eta * eta);
    p.x = n * Radius;
    p.d = vec3(0.0);
    p.w = 1.0 - f;
    if (!(f < 1.0) || sin2T >= 1.0) return false;
    float cosT = sqrt(1.0 - sin2T);
    p.d = normalize(-Light / eta + (cosI / eta - cosT) * n);
    return true;
}

void savePath(uint k, Path p) {
    uint b = 5u * k;
    ptOut[b] = floatBitsToUint(vec4(p.x, p.d.x));
    ptOut[b + 1u] = floatBitsToUint(vec4(p.d.yz, p.w, p.pending));
    ptOut[b + 2u] = uvec4(p.events, p.hits, p.rng.ctr.xy);
    ptOut[b + 3u] = p.rng.buf;
    ptOut[b + 4u] = uvec4(p.rng.ctr.z, p.rng.used, p.channel, 0u);
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
    p.pending = q1.w;
    p.events = q2.x;
    p.hits = q2.y;
    p.channel = q4.z;
    p.rng = rngInit(Seed, q2.zw, SPHERE_STREAM + p.channel);
    p.rng.buf = ptIn[b + 3u];
    p.rng.ctr.z = q4.x;
    p.rng.used = q4.y;
    return p;
}

// The path leaves through the boundary at xs: tally its weight.
void exitPath(inout Path p, vec3 xs) {
    uint base = slotBase(p.channel);
    ptTally(base + pixelCount(), p.w, p.rng);
    if (xs.z > 0.0) { // visible to the camera (n·z > 0 on the sphere)
        float fi = (xs.x + Extent) / PixelSize.x, fj = (Extent - xs.y) / PixelSize.y;
        if (fi >= 0.0 && fj >= 0.0) {
            uint i = uint(fi), j = uint(fj);
            if (i < ImageSize.x && j < ImageSize.y) ptTally(base + j * ImageSize.x + i, p.w, p.rng);
        }
    }
}

// One loop iteration: a flight to a collision or to the boundary. Returns true when the path
// has ended (and is tallied).
bool advance(inout Path p) {
    uint c = p.channel;
    float s = p.pending >= 0.0 ? p.pending : -log(rngOpen(p.rng)) / SigmaT[c];
    p.pending = -1.0;
    // the far root of |x + t·d| = R from inside, without cancellation
    float b = dot(p.x, p.d);
    float negC = max(0.0, Radius * Radius - dot(p.x, p.x));
    float sq = sqrt(b * b + negC);
    float t = b > 0.0 ? negC / (b + sq) : sq - b;
    if (s >= t) {
        vec3 xs = p.x + t * p.d;
        xs *= Radius / length(xs); // back onto the sphere
        vec3 n = xs / Radius;
        float cosI = dot(p.d, n);
        if (!(cosI > 0.0)) cosI = sq / Radius; // grazing: the chord's cosine
        p.hits += 1u;
        if (p.hits > MAX_BOUNDARY_HITS) return true; // stuck: ends untallied (a leak)
        if (rngUniform(p.rng) >= fresnelExit(min(cosI, 1.0), Eta[c])) {
            exitPath(p, xs);
            return true;
        }
        p.d = normalize(p.d - 2.0 * cosI * n); // internal reflection
        p.x = xs;
        p.pending = max(0.0, s - t);
        return false;
    }
    p.x += s * p.d;
    p.events += 1u;
    p.w -= p.w * AbsorbFraction[c];
    if (p.w < RouletteWeight) {
        if (rngNext(p.rng) < SurviveWeight) {
            p.w *= WeightGain;
        } else {
            return true;
        }
    }
    if (p.events >= MaxEvents) {
        ptTally(slotBase(c) + pixelCount() + 1u, p.w, p.rng);
        return true;
    }
    p.d = deflect(p.d, sampleHgCos(G[c], rngUniform(p.rng)), 2.0 * PT_PI * rngUniform(p.rng));
    return false;
}

void main() {
    Path p;
    bool busy = false;
    uint eventsLo = 0u;
    for (uint it = 0u; it < EventBudget; ++it) {
        if (!busy) {
            uint item;
            uint kind = ptTake(item);
            if (kind == 0u) break;
            if (kind == 1u) {
                p = loadPath(item);
            } else {
                if (!startPath(ptPathOf(item), item % 3u, p))
                    continue; // nothing entered: the path is done
            }
            busy = true;
        }
        uint before = p.events;
        busy = !advance(p);
        eventsLo += p.events - before;
    }
    if (busy) savePath(atomicAdd(ptOutCount, 1u), p);
    ptFinish(eventsLo);
}
