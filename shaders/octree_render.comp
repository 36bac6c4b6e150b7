#version 450
// Hierarchical BSSRDF evaluation on the point-cloud octree (thesis 2.6.4, 3.3.3, Algorithm 2;
// the layout and the arithmetic are specified in modules/octree/octree.h, whose CPU replica
// octree::traverse does exactly what this shader does). A model consumer template: one
// invocation per pixel of the G-buffer (shaders/render_gbuffer.*).
//
// Per pixel with a hit (GPosition.w = 1): xo = GPosition.xyz, no = GNormal.xyz (mesh units,
// used as read), and the radiant exitance
//   M(xo) = Σ contributions,  point i: E_i·A_i·Scale²·Bssrdf(Scale·p_i, n_i, Scale·xo, no)
//                             node v:  (Σ E·A)_v·Scale²·Bssrdf(Scale·P_v, no, Scale·xo, no)
//   or, with RenderSecondOrder, the node's three terms of the second-order cluster rule
//   (Σ E·A)_v·k_j·Scale²·Bssrdf(Scale·x_j, no, Scale·xo, no), j = 0, 1, 2 (octreeClusterPoint)
// summed in float in traversal order (each term ((weight·Scale²)·value), `precise`).
//   Hierarchical: Algorithm 2 — node = 0, childnum = 0; a visit (one "step") of an interior node
//     whose criterion (common/octree_layout.glsl) fails pushes node<<8|childnum (not for the
//     root; a push beyond RenderStackSize flags OCTREE_FLAG_STACK_OVERFLOW and stops) and goes
//     to the last child; otherwise the node (its one term, or its three second-order terms,
//     one per iteration; or the leaf's points, in slot order, one per iteration) is added and
//     the traversal moves to the previous sibling, popping while childnum = 0, done when the
//     stack is empty. A visit with RenderMaxSteps steps already done flags
//     OCTREE_FLAG_ITERATION_CAP and stops.
//   Brute force (RenderBruteForce): every point, slots 0 … N−1, same contribution formula,
//     no steps.
//   Radial models (BSSRDF_RADIAL) use the profile table (common/octree_profile.glsl) at
//     r = |Scale·xo − Scale·xi| unless RenderDirect is set; other models call Bssrdf(). With
//     the table, a second-order node's three terms are looked up at Scale·ρ_j directly, all in
//     the iteration that accepts the node (lookups are cheap; an iteration is not); otherwise
//     they take one iteration each at the points x_j (MODE_CLUSTER), as the replica forms them.
// Radiance towards the camera: L_o = Ft(IOR, cos θo)/π · M, cos θo = min(1, |no·ωo|),
// ωo = normalize(RenderCameraPosition − xo), Ft the exact unpolarised Fresnel transmittance
// (leaving the medium towards the camera equals entering at that angle, by reciprocity).
//
// Mesa llvmpipe stops every loop of an invocation after 65535 iterations in total (nested or
// not), so the traversal is one flat state machine — each iteration visits a node, adds one
// point, or moves to the next node (one pop) — and brute force one loop over the points; each
// runs at most RenderIterations iterations per dispatch. An unfinished pixel keeps its state
// (stack, cursor, stats, M) in buffers and the host dispatches again (RenderFirst = false)
// until RenderControl.unfinished stays 0; the result does not depend on the split. A loop
// that ends early without finishing, or a short sentinel loop after it (the driver's limit:
// e.g. loops inside the model), sets RenderControl.loopLimitHit; the host then re-renders
// with fewer iterations per dispatch.
//
// Outputs: HdrImage rgba = (L_o, 1) on a hit, 0 on a miss; RenderExitance[p] = (M, hit);
// RenderStats[p] = (steps, max stack depth, flags, evaluations). Pixel p = y·width + x, row 0
// is the top of the image (the G-buffer is rendered flipped).
//
// Bands. A frame's traversal runs over bands of rows RenderRows = [first, end), one band to its
// end before the next: the storage blocks (stats, exitance, 96 bytes of state per pixel) are
// bound from the band's first row on and hold the band only, so no block exceeds the driver's
// GL_MAX_SHADER_STORAGE_BLOCK_SIZE (2^27 bytes may be all a driver offers; NVIDIA's 2^31 - 1 is
// a 4800 x 4800 frame's state). Within the blocks p counts from the band's first pixel.
layout(local_size_x = 8, local_size_y = 8) in;

#include "common/bssrdf_prelude.glsl"

#pragma bssrdf_model

#include "common/octree_layout.glsl"
#include "common/octree_profile.glsl"

layout(rgba32f, binding = 0) readonly uniform image2D GPosition;
layout(rgba32f, binding = 1) readonly uniform image2D GNormal;
layout(rgba32f, binding = 2) writeonly uniform image2D HdrImage;

struct RenderPixelState {
    uint stack[OCTREE_STACK_SIZE];
    uvec4 cursor; // node, childnum, mode, stack pointer
    uvec4 range;  // next point slot, end slot, 0, 0
};
layout(std430, binding = 3) buffer RenderStats { uvec4 renderStats[]; };
layout(std430, binding = 5) buffer RenderExitance { vec4 renderExitance[]; };
layout(std430, binding = 6) buffer RenderState { RenderPixelState renderState[]; };
layout(std430, binding = 7) buffer RenderControl {
    uint unfinished;   // pixels left unfinished by this dispatch
    uint loopLimitHit; // a loop was cut short by the driver
};

uniform ivec2 RenderSize;           // width, height
uniform ivec2 RenderRows;           // the band: rows [x, y) (see Bands)
uniform bool RenderFirst;           // first dispatch of the band: start every pixel
uniform bool RenderBruteForce;      // sum every point instead of traversing
uniform bool RenderBoundingBox;     // bounding-box criterion instead of the mean position
uniform bool RenderDirect;          // radial models: call Bssrdf() instead of the table
uniform bool RenderSecondOrder;     // nodes by the three-point second-order cluster rule
uniform float RenderEps;            // ε of the solid-angle criterion
uniform uint RenderMaxSteps;        // steps before OCTREE_FLAG_ITERATION_CAP
uniform uint RenderStackSize;       // usable stack entries (<= OCTREE_STACK_SIZE)
uniform uint RenderIterations;      // loop iterations per dispatch
uniform uint RenderPointCount;      // N (brute force)
uniform vec3 RenderCameraPosition;  // mesh units
uniform uint RenderSentinel;        // 2: a loop of this length after the traversal must run in full
// The hybrid method's global part (seed 004 §3.3, render.h RadialWeight): every evaluation
// times W_g(r) = 1 − W_l(r), W_l = 1 − ½e^{(r−R_p)K} (r <= R_p), ½e^{−(r−R_p)K} (r > R_p).
uniform bool RenderWeightGlobal;
uniform vec3 RenderWeightRp;        // R_p per channel, mm
uniform float RenderWeightK;        // K, 1/mm

const uint MODE_VISIT = 0u;  // visit `node` (one step)
const uint MODE_POINTS = 1u; // add point `range.x`, up to `range.y` (brute force: all)
const uint MODE_NEXT = 2u;   // move to the next node (pop while childnum = 0)
const uint MODE_DONE = 3u;
const uint MODE_CLUSTER = 4u; // add second-order term `range.x` (0, 1, 2) of node `node`

vec3 renderGlobalWeight(float r) {
    vec3 d = vec3(r) - RenderWeightRp;
    vec3 below = 0.5 * exp(d * RenderWeightK);  // 1 − W_l for r <= R_p
    vec3 above = 1.0 - 0.5 * exp(-d * RenderWeightK);
    return mix(below, above, greaterThan(d, vec3(0.0)));
}

// The profile table at r (mm), weighted when the hybrid's global part is rendered.
vec3 renderTable(float r) {
    vec3 v = profileLookup(r);
    return RenderWeightGlobal ? v * renderGlobalWeight(r) : v;
}

vec3 renderModel(vec3 xi, vec3 wi, vec3 sxo, vec3 no) {
    precise vec3 sxi = Scale * xi;
    vec3 dd = sxo - sxi;
#ifdef BSSRDF_RADIAL
    if (!RenderDirect) {
        return renderTable(sqrt(dot(dd, dd)));
    }
#endif
    vec3 v = Bssrdf(sxi, wi, sxo, no);
    return RenderWeightGlobal ? v * renderGlobalWeight(sqrt(dot(dd, dd))) : v;
}

// Unpolarised Fresnel transmittance 1 − F at cos θ in [0, 1] for relative index eta.
float renderFresnelTransmittance(float cosI, float eta) {
    if (eta == 1.0) return 1.0;
    if (cosI <= 0.0) return 0.0;
    float sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return 0.0;
    float cosT = sqrt(1.0 - sin2T);
    float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
}

void main() {
    ivec2 pix = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, RenderRows.x);
    if (pix.x >= RenderSize.x || pix.y >= min(RenderRows.y, RenderSize.y)) return;
    uint p = uint((pix.y - RenderRows.x) * RenderSize.x + pix.x); // in the band's blocks
    vec4 pos = imageLoad(GPosition, pix);

    uint node, childnum, mode, sp, k, end;
    uvec4 stats;
    precise vec3 M;
    if (RenderFirst) {
        if (pos.w == 0.0) {
            imageStore(HdrImage, pix, vec4(0.0));
            renderExitance[p] = vec4(0.0);
            renderStats[p] = uvec4(0u);
            renderState[p].cursor = uvec4(0u, 0u, MODE_DONE, 0u);
            return;
        }
        node = 0u;
        childnum = 0u;
        sp = 0u;
        mode = RenderBruteForce ? MODE_POINTS : MODE_VISIT;
        k = 0u;
        end = RenderBruteForce ? RenderPointCount : 0u;
        stats = uvec4(0u);
        M = vec3(0.0);
    } else {
        uvec4 cursor = renderState[p].cursor;
        if (cursor.z == MODE_DONE) return;
        node = cursor.x;
        childnum = cursor.y;
        mode = cursor.z;
        sp = cursor.w;
        k = renderState[p].range.x;
        end = renderState[p].range.y;
        stats = renderStats[p];
        M = renderExitance[p].xyz;
    }
    // The traversal stack lives in registers / local memory during a dispatch; it is loaded
    // from and saved to the pixel's state only when a frame spans several dispatches.
    uint stack[OCTREE_STACK_SIZE];
    sp = min(sp, uint(OCTREE_STACK_SIZE)); // every loop has a bound of its own
    if (!RenderFirst)
        for (uint i = 0u; i < sp; ++i) stack[i] = renderState[p].stack[i];
    init();
    const vec3 xo = pos.xyz;
    const vec3 no = imageLoad(GNormal, pix).xyz;
    const vec3 sxo = Scale * xo;
    const float s2 = Scale * Scale;

    uint it = 0u;
    if (RenderBruteForce) {
        // slots k … N−1 (mode stays MODE_POINTS until the last one)
        for (; it < RenderIterations; ++it) {
            if (k >= end) break;
            vec4 pa = octreePoints[k].positionArea;
            M += (octreePoints[k].irradiance.xyz * pa.w) * s2 *
                 renderModel(pa.xyz, octreePoints[k].normal.xyz, sxo, no);
            stats.w += 1u;
            k += 1u;
        }
        if (k >= end) mode = MODE_DONE;
    } else {
        // Algorithm 2 as a state machine. Each iteration does at most one visit (one step) or
        // one point (or one second-order term), the evaluation it asks for, then one move
        // towards the next node (a sibling, or one pop). The evaluations are added in exactly the order of the CPU
        // replica (octree::traverse).
        for (; it < RenderIterations; ++it) {
            if (mode == MODE_DONE) break;
            bool evaluate = false;
            vec3 exi = vec3(0.0), ewi = vec3(0.0), ew = vec3(0.0);
            if (mode == MODE_VISIT) {
                if (stats.x >= RenderMaxSteps) {
                    stats.z |= OCTREE_FLAG_ITERATION_CAP;
                    mode = MODE_DONE;
                    break;
                }
                stats.x += 1u;
                uint d = octreeDescriptors[node];
                uint cc = octreeChildCount(d);
                if (cc != 0u && !octreeAccept(node, xo, RenderEps, RenderBoundingBox)) {
                    if (node != 0u) {
                        if (sp >= RenderStackSize) {
                            stats.z |= OCTREE_FLAG_STACK_OVERFLOW;
                            mode = MODE_DONE;
                            break;
                        }
                        stack[sp] = octreePackEntry(node, childnum);
                        sp += 1u;
                        stats.y = max(stats.y, sp);
                    }
                    childnum = cc - 1u;
                    node = octreeIndex(d) + childnum;
                } else if (cc == 0u) {
                    k = octreeIndex(d);
                    end = k + octreePointCount(d);
                    mode = k < end ? MODE_POINTS : MODE_NEXT;
                } else if (RenderSecondOrder) {
#ifdef BSSRDF_RADIAL
                    if (!RenderDirect) {
                        // table lookups at the three distances, all in this iteration
                        OctreeCluster c = octreeCluster(node, xo);
                        vec3 ea = octreeNodes[node].irradianceArea.xyz;
                        M += (ea * OCTREE_CLUSTER_WEIGHTS[0]) * s2 * renderTable(Scale * c.rho.x);
                        M += (ea * OCTREE_CLUSTER_WEIGHTS[1]) * s2 * renderTable(Scale * c.rho.y);
                        M += (ea * OCTREE_CLUSTER_WEIGHTS[2]) * s2 * renderTable(Scale * c.rho.z);
                        stats.w += 3u;
                        mode = MODE_NEXT;
                    } else
#endif
                    {
                        k = 0u;
                        mode = MODE_CLUSTER;
                    }
                } else {
                    evaluate = true;
                    exi = octreeNodes[node].meanPosition.xyz;
                    ewi = no;
                    ew = octreeNodes[node].irradianceArea.xyz;
                    mode = MODE_NEXT;
                }
            }
            if (mode == MODE_POINTS && !evaluate) {
                evaluate = true;
                vec4 pa = octreePoints[k].positionArea;
                exi = pa.xyz;
                ewi = octreePoints[k].normal.xyz;
                ew = octreePoints[k].irradiance.xyz * pa.w;
                k += 1u;
                if (k >= end) mode = MODE_NEXT;
            }
            if (mode == MODE_CLUSTER && !evaluate) {
                evaluate = true;
                exi = octreeClusterPoint(octreeCluster(node, xo), xo, k);
                ewi = no;
                ew = octreeNodes[node].irradianceArea.xyz * OCTREE_CLUSTER_WEIGHTS[k];
                k += 1u;
                if (k >= 3u) mode = MODE_NEXT;
            }
            if (evaluate) {
                M += ew * s2 * renderModel(exi, ewi, sxo, no);
                stats.w += 1u;
            }
            if (mode == MODE_NEXT) {
                if (childnum == 0u) {
                    if (sp == 0u) {
                        mode = MODE_DONE;
                    } else {
                        sp -= 1u;
                        uint e = stack[sp];
                        node = e >> 8u;
                        childnum = e & 0xffu;
                    }
                } else {
                    node -= 1u;
                    childnum -= 1u;
                    mode = MODE_VISIT;
                }
            }
        }
    }

    // The driver's loop limit leaves every later loop short: a traversal loop that stopped
    // early without finishing, or a cut sentinel loop, means some loop (maybe one inside the
    // model) did not run in full.
    uint sentinel = 0u;
    for (uint q = 0u; q < RenderSentinel; ++q) sentinel += 1u;
    if (sentinel != RenderSentinel || (mode != MODE_DONE && it < RenderIterations))
        atomicOr(loopLimitHit, 1u);

    renderStats[p] = stats;
    renderExitance[p] = vec4(M, 1.0);
    if (mode != MODE_DONE) {
        for (uint i = 0u; i < sp; ++i) renderState[p].stack[i] = stack[i];
        renderState[p].cursor = uvec4(node, childnum, mode, sp);
        renderState[p].range = uvec4(k, end, 0u, 0u);
        atomicAdd(unfinished, 1u);
        return;
    }
    renderState[p].cursor = uvec4(node, childnum, MODE_DONE, sp);
    vec3 wo = normalize(RenderCameraPosition - xo);
    float ft = renderFresnelTransmittance(min(abs(dot(no, wo)), 1.0), IOR);
    imageStore(HdrImage, pix, vec4((ft / PI) * M, 1.0));
}
