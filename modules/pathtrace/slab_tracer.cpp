// pathtrace/slab_tracer: one path through the semi-infinite slab z < 0 (surface z = 0, outward
// normal +z) under a normally incident pencil beam at the origin — thesis Algorithm 1 (Section
// 3.2) with the MCML entry convention (Wang, Jacques & Zheng 1995); estimators and termination
// as documented in pathtrace.h:
//   entry     R_sp = ((η − 1)/(η + 1))² is tallied, the photon enters along −z with 1 − R_sp;
//   flight    s = −ln(1 − ξ)/σt (line 3); crossing z = 0 is a boundary hit (lines 4–5);
//   boundary  reflect with probability R(θ) (exact Fresnel, fresnel.h; no draw when R is 0 or
//             1), mirror u_z and travel the rest of s (lines 7–8), else exit (line 10);
//   collision Analog: absorb with probability 1 − α (line 15); Implicit: w ← αw, absorbed
//             += w(1 − α), roulette below rouletteWeight; then truncation at maxEvents (the
//             weight tallied as truncated), then an HG scattering (line 16).
#include "core/core.h"
#include "pathtrace/detail/collision.h"
#include "pathtrace/detail/slab_chunk.h"
#include "pathtrace/detail/slab_connections.h"
#include "pathtrace/fresnel.h"
#include "pathtrace/pathtrace.h"
#include "pathtrace/rng.h"
#include "pathtrace/sampling.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace pathtrace {
namespace {

struct Consts {
    double invSigmaT;
    double albedo;
    double g;
    double etaOut; // n_t / n_i when leaving the medium: 1/η
    double rsp;    // specular reflectance at normal incidence
    double w0;     // 1 − R_sp
    uint32_t maxEvents;
    double rouletteWeight, rouletteSurvival;
};

Consts makeConsts(const Medium& m, const SlabSettings& s) {
    Consts c{};
    const double sigmaT = m.sigmaA + m.sigmaS;
    c.invSigmaT = 1.0 / sigmaT;
    c.albedo = m.sigmaS / sigmaT;
    c.g = m.g;
    c.etaOut = 1.0 / m.eta;
    const double r = (m.eta - 1.0) / (m.eta + 1.0);
    c.rsp = r * r;
    c.w0 = 1.0 - c.rsp;
    c.maxEvents = std::max<uint32_t>(1, s.termination.maxEvents);
    c.rouletteWeight = s.termination.rouletteWeight;
    c.rouletteSurvival = s.termination.rouletteSurvival;
    return c;
}

template <bool Analog, bool Isotropic> PathRecord traceOne(const Consts& c, Pcg32 rng) {
    PathRecord p;
    p.specular = c.rsp;
    double w = c.w0;
    double absorbed = 0.0, loss = 0.0, truncated = 0.0;
    double x = 0.0, y = 0.0, z = 0.0;
    Dir u{0.0, 0.0, -1.0};
    uint32_t events = 0;
    for (;;) {
        const double s = sampleDistance(1.0, rng.uniform()) * c.invSigmaT;
        if (u.z > 0.0 && z + s * u.z >= 0.0) { // boundary hit
            const double tHit = -z / u.z;
            x += tHit * u.x;
            y += tHit * u.y;
            const double f = fresnelDielectric(u.z, c.etaOut);
            if (f < 1.0 && (f <= 0.0 || rng.uniform32() >= f)) { // transmitted: exit
                p.reflected = w;
                p.exitR = std::sqrt(x * x + y * y);
                p.exited = true;
                break;
            }
            u.z = -u.z; // internal reflection, then the rest of the flight
            const double rest = std::max(0.0, s - tHit);
            x += rest * u.x;
            y += rest * u.y;
            z = rest * u.z;
        } else {
            x += s * u.x;
            y += s * u.y;
            z += s * u.z;
        }
        ++events;
        if constexpr (Analog) {
            if (rng.uniform32() >= c.albedo) { // absorbed
                absorbed += w;
                break;
            }
        } else if (!detail::absorbAndRoulette(w, absorbed, loss, c, rng)) {
            break;
        }
        if (!detail::belowEventLimit(w, truncated, events, c)) break;
        if constexpr (Isotropic)
            u = sampleSphere(rng);
        else
            u = scatterHg(u, c.g, rng);
    }
    p.absorbed = absorbed;
    p.rouletteLoss = loss;
    p.truncated = truncated;
    p.events = events;
    return p;
}

template <bool Analog, bool Isotropic>
uint64_t traceRange(const Consts& c, uint64_t seed, uint64_t first, uint64_t count, PathRecord* out,
                    const std::atomic<bool>* cancel) {
    for (uint64_t i = 0; i < count; ++i) {
        if ((i & 255u) == 0 && cancel && cancel->load(std::memory_order_relaxed)) return i;
        out[i] = traceOne<Analog, Isotropic>(c, Pcg32::forPath(seed, first + i));
    }
    return count;
}

} // namespace

namespace detail {
uint64_t traceChunk(const Medium& m, const SlabSettings& s, uint64_t first, uint64_t count,
                    PathRecord* out, const std::atomic<bool>* cancel) {
    const Consts c = makeConsts(m, s);
    // Estimator::Connections walks as Implicit (its bins come from slab_connections.cpp).
    const bool analog = s.estimator == Estimator::Analog, iso = m.g == 0.0;
    if (analog && iso) return traceRange<true, true>(c, s.seed, first, count, out, cancel);
    if (analog) return traceRange<true, false>(c, s.seed, first, count, out, cancel);
    if (iso) return traceRange<false, true>(c, s.seed, first, count, out, cancel);
    return traceRange<false, false>(c, s.seed, first, count, out, cancel);
}
} // namespace detail

PathRecord tracePath(const Medium& m, const SlabSettings& s, uint64_t pathIndex) {
    validate(m);
    validate(s);
    PathRecord p;
    detail::traceChunk(m, s, pathIndex, 1, &p, nullptr);
    return p;
}

SlabTally traceSlab(const Medium& m, const SlabSettings& s, uint64_t first, uint64_t count,
                    const std::atomic<bool>* cancel) {
    validate(m);
    validate(s);
    return detail::traceSlabViaEstimate(m, s, first, count, cancel);
}

} // namespace pathtrace
