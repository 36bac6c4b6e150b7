// pathtrace/sphere_walk: the random walk inside a closed object under a dielectric boundary,
// shared by the lit-sphere tracer (analytic sphere) and the lit-mesh tracer (Embree mesh),
// templated on the geometry. The physics and estimator are those of the slab tracer
// (bssrdf_walk.cpp, thesis 3.2 / Algorithm 1, implicit estimator):
//   flight     s = −ln(1 − ξ)/σt; if the boundary lies within s, move to it (boundary hit);
//   boundary   reflect with probability R(θ) (exact Fresnel, fresnel.h, relative index 1/η on
//              the way out; no draw when R is 0 or 1): mirror the direction and travel the rest
//              of s (checking the boundary again); else exit there with the current weight;
//   collision  implicit absorption w ← αw, absorbed += w(1 − α); weight roulette below
//              rouletteWeight (survive with rouletteSurvival, w /= p); truncation after
//              maxEvents interactions (the weight tallied as truncated, Termination in
//              pathtrace.h); then an HG scattering (uniform on the sphere for g = 0).
//   Per path: exited + absorbed + truncated + rouletteLoss + leaked = entered weight (up to
//   rounding).
// Safeguard: a path that meets the boundary kMaxBoundaryHits times (numerically stuck at a
// grazing point) ends as `leaked`, like a path that finds itself outside (meshes).
#pragma once

#include "pathtrace/camera.h"
#include "pathtrace/detail/collision.h"
#include "pathtrace/fresnel.h"
#include "pathtrace/rng.h"
#include "pathtrace/sampling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pathtrace::walk {

inline Dir add(const Dir& a, const Dir& b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Dir mul(const Dir& a, double k) {
    return {a.x * k, a.y * k, a.z * k};
}
inline Dir madd(const Dir& a, const Dir& b, double k) { // a + k·b
    return {a.x + k * b.x, a.y + k * b.y, a.z + k * b.z};
}
inline double dot(const Dir& a, const Dir& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline Dir normalized(const Dir& a) {
    return mul(a, 1.0 / std::sqrt(dot(a, a)));
}

struct Consts {
    double invSigmaT; // mean free path in the walk's length unit
    double albedo;
    double g;
    double eta;    // η = n_medium / n_outside
    double etaOut; // 1/η: relative index when leaving
    uint32_t maxEvents;
    double rouletteWeight, rouletteSurvival;
};
// `lengthUnit`: length of the walk's unit in mm (1 for mm; the mesh's scale for normalised
// units), so σ per unit = σ · lengthUnit.
inline Consts makeConsts(const Medium& m, const TraceOptions& o, double lengthUnit) {
    Consts c{};
    const double sigmaT = (m.sigmaA + m.sigmaS) * lengthUnit;
    c.invSigmaT = 1.0 / sigmaT;
    c.albedo = m.sigmaS / (m.sigmaA + m.sigmaS);
    c.g = m.g;
    c.eta = m.eta;
    c.etaOut = 1.0 / m.eta;
    c.maxEvents = std::max<uint32_t>(1, o.termination.maxEvents);
    c.rouletteWeight = o.termination.rouletteWeight;
    c.rouletteSurvival = o.termination.rouletteSurvival;
    return c;
}

// Refraction into the medium through a surface of outward unit normal n, light arriving
// along −l (l: unit, towards the light) at cos θi = n·l > 0: the transmitted unit direction.
// Returns false under total internal reflection (possible only for η < 1).
inline bool refractIn(const Dir& l, const Dir& n, double cosI, double eta, Dir& t) {
    const double sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return false;
    const double cosT = std::sqrt(1.0 - sin2T);
    // t = −l/η + (cosI/η − cosT) n
    t = normalized(madd(mul(l, -1.0 / eta), n, cosI / eta - cosT));
    return true;
}

// A boundary crossing found by the geometry.
struct Hit {
    Dir p;       // point on the surface
    Dir n;       // outward unit normal there
    double t;    // distance along the flight
    double cosI; // u·n (> 0 when leaving; <= 0: the path was outside — a leak)
};

constexpr uint32_t kMaxBoundaryHits = 1u << 20;

// Geo must provide
//   bool hit(const Dir& x, const Dir& u, double& s, Hit& h) const: the first boundary point
//       along x + t·u for t <= s (false: none; the geometry may then shorten s so that the
//       collision point stays clear of the surface, see mesh_tracer.cpp);
//   Dir reflectStart(const Hit& h) const: where to continue inside after reflecting at h.
// Walks from x (inside) along u with weight w; fills r.events/exited/absorbed/rouletteLoss/
// truncated/leaked; returns true and the exit in `out` when the path left the object.
template <bool Isotropic, class Geo>
bool walk(const Consts& c, const Geo& geo, Pcg32& rng, Dir x, Dir u, double w, ExitRecord& r,
          Hit& out) {
    double absorbed = 0.0, loss = 0.0, truncated = 0.0, pending = -1.0;
    uint32_t events = 0, boundaryHits = 0;
    bool exited = false;
    for (;;) {
        double s = pending >= 0.0 ? pending : sampleDistance(1.0, rng.uniform()) * c.invSigmaT;
        pending = -1.0;
        Hit h;
        if (geo.hit(x, u, s, h)) {
            if (!(h.cosI > 0.0) || ++boundaryHits > kMaxBoundaryHits) { // outside or stuck
                r.leaked = w;
                break;
            }
            const double f = fresnelDielectric(std::min(h.cosI, 1.0), c.etaOut);
            if (f < 1.0 && (f <= 0.0 || rng.uniform32() >= f)) { // transmitted: exit
                r.exited = w;
                out = h;
                exited = true;
                break;
            }
            u = normalized(madd(u, h.n, -2.0 * h.cosI)); // internal reflection
            x = geo.reflectStart(h);
            pending = std::max(0.0, s - h.t); // the rest of the flight
            continue;
        }
        x = madd(x, u, s);
        ++events;
        if (!detail::absorbAndRoulette(w, absorbed, loss, c, rng)) break;
        if (!detail::belowEventLimit(w, truncated, events, c)) break;
        if constexpr (Isotropic)
            u = sampleSphere(rng);
        else
            u = scatterHg(u, c.g, rng);
    }
    r.events = events;
    r.absorbed = absorbed;
    r.rouletteLoss = loss;
    r.truncated = truncated;
    return exited;
}

} // namespace pathtrace::walk
