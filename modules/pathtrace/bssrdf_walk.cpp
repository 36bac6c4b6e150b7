// pathtrace/bssrdf_walk: one chunk of paths of the oblique-incidence slab walk with its three
// estimators (bssrdf_estimate.h; Dal Corso & Frisvad 2018, seed 001).
//
// The walk. The beam (one photon) hits the origin travelling toward +x at θi; the Fresnel
// reflectance R(θi) is tallied as specular, the photon enters with w₀ = 1 − R(θi) along the
// refracted ω₁₂ = (sin θt, 0, −cos θt), sin θt = sin θi / η. Flights s = −ln(1 − ξ)/σt,
// Fresnel roulette at the surface (exit, or internal reflection), collisions with implicit
// absorption and weight roulette (analog: absorption by roulette), truncation at maxEvents,
// HG scattering — the slab tracer's walk (pathtrace.h) at any θi.
//
// Histogram estimators (analog, implicit): a path that exits at x with internal direction u is
// tallied with its weight in the (folded) spatial bin of x and the cell of the refracted
// direction ω_t (cos θo = sqrt(1 − η²(1 − u_z²)), azimuth of u). With expected-value exits
// (pathtrace.h, ExpectedExits; a switch) each flight that leaves a collision upward is
// tallied instead with its probability of leaving, e^{−σt d} T₂₁, where it would leave: the
// exit's expectation given the collision (the flight reaches the surface with probability
// e^{−σt d} and passes with T₂₁), so every bin keeps its expectation, and the exits that happen
// are not tallied again. In an isotropic medium the directions are drawn from the escape cone
// (those that transmit) with the cone's share of the sphere as their weight (intoEscapeCone).
//
// Connections: derivation. Let w_p be the weight with which the walk arrives at its p-th
// collision x_p, moving along ω_p; E[Σ_p w_p δ(x − x_p)] is the collision density of the
// photon. After the collision the flux α·w_p leaves x_p with the HG intensity p(ω_p·ω) per
// steradian (α = σs/σt; the expected value is used, before the absorption decision). The part
// that reaches the surface element dA at x_o along ω₂₁ = (x_o − x_p)/d, d = |x_o − x_p|, is
// attenuated by e^{−σt d} and subtends dω = cos θ₂₁ dA / d², cos θ₂₁ = ω₂₁·n = −z_p / d. The
// surface transmits T₂₁ = 1 − R(cos θ₂₁, 1/η) of it (0 past the critical angle) along ω_t
// (Snell). Since n² cos θ dω is conserved across the interface, the flux needs no radiance
// compression factor (the seed's ω_t·n is the outside cosine, which belongs to radiance, not to
// flux). So the flux through dA, leaving along ω_t(x_o), is
//     dΦ = f_p(x_o) dA,   f_p(x) = α w_p p(ω_p·ω₂₁) e^{−σt d} T₂₁(cos θ₂₁) cos θ₂₁ / d²,
// and the flux into a spatial bin A and direction cell Ω is Φ(A, Ω) = E[Σ_p ∫_A f_p [ω_t ∈ Ω] dA].
// Every exiting photon leaves from a last collision and no light reaches the surface without
// one, so this accounts for all the light the walk's exits carry (checked per path: D below).
// The integral over A is estimated with two samples per collision (one-sample-per-technique
// multiple importance sampling with the balance heuristic, Veach 1997, §9.2):
//   (a) in every radial bin, a point in polar coordinates: r ~ U[r_lo, r_hi] (as the seed),
//       and — where the seed takes θs uniform in every sector, one point per sector — θ over
//       the whole ring from the wrapped Cauchy density w(θ) ∝ 1/d² (detail/ring_sampler.h),
//       the point going to whichever θs sector it lands in. The area density is
//       q_a(x) = w(θ) / (r Δr) on the radial bin holding x. It cancels the 1/d² of f exactly
//       along the ring, and costs one connection per ring instead of one per sector; with the
//       seed's uniform θs most points of a wide ring land far from the vertex and add nearly
//       nothing (the time to 1 % at l_d was 4x longer);
//   (b) one direction from the phase function p(ω_p·ω); if it points up it meets the surface
//       at x with area density q_p(x) = p(ω_p·ω₂₁) cos θ₂₁ / d² (0 if it points down).
// Each sample x adds f_p(x) / (q_a(x) + q_p(x)) to its bin and cell. Then
//   E = Σ_bins ∫ f_p (q_a + q_p)/(q_a + q_p) dA = Σ_bins ∫_A f_p dA   (unbiased), and
//   f/(q_a + q_p) ≤ f/q_p = α w_p e^{−σt d} T₂₁ ≤ α w_p: every term is bounded by the weight.
// Technique (a) alone (the seed's estimator) has f/q_a ∝ cos θ₂₁/d² at a vertex just below the
// surface: its tail P(X > t) ~ t^{−3/2} has a finite mean but an infinite variance, so its error
// bars would not be trustworthy.
// With technique (a) only and uniform θs this is the seed's final estimator with the Jacobians
// made explicit: f/q_a = α w_p p T₂₁ (cos θ₂₁/d²) e^{−σt d} · 2 r Δr Δθs; dividing the bin's
// flux by A = (r_hi² − r_lo²) Δθs and by the cell's projected solid angle gives S.
// Orders: MultipleOnly skips the connections (and histogram exits) of paths' first collision;
// SingleOnly connects the first collision only and ends the walk there (the histogram counts
// exits after exactly one collision).
// Connection roulette: a collision farther than d₀ = 2 mean free paths from every bin connects
// with probability e^{−σt(d_min − d₀)} and weight 1/p (connectVertex); terms stay bounded.
// Energy: per path, D = Σ_bins Φ (connections) − exit weight inside r_max (same orders), E[D] = 0.
#include "core/core.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/detail/bssrdf_chunk.h"
#include "pathtrace/detail/collision.h"
#include "pathtrace/detail/mean_stderr.h"
#include "pathtrace/detail/ring_sampler.h"
#include "pathtrace/fresnel.h"
#include "pathtrace/rng.h"
#include "pathtrace/sampling.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pathtrace {

namespace {

using detail::kRouletteMfp;

// Per-path accumulators of a sparse set of indices (values added are > 0).
struct PathAcc {
    std::vector<double> v;
    std::vector<int> touched;
    void resize(size_t n) { v.assign(n, 0.0); }
    void add(int i, double x) {
        if (v[size_t(i)] == 0.0) touched.push_back(i);
        v[size_t(i)] += x; // x > 0, so a touched entry never returns to 0
    }
    // Adds every touched value and its square into the sums (and the value into `batch`, the
    // sums of the path's batch, when given) and clears; returns the total.
    double flush(std::vector<double>& sum, std::vector<double>& sumSq, double* batch = nullptr) {
        double total = 0;
        std::sort(touched.begin(), touched.end()); // a fixed order for the total
        for (int i : touched) {
            const double x = v[size_t(i)];
            sum[size_t(i)] += x;
            sumSq[size_t(i)] += x * x;
            if (batch) batch[i] += x;
            total += x;
            v[size_t(i)] = 0.0;
        }
        touched.clear();
        return total;
    }
};

class Walker {
  public:
    Walker(const Medium& m, const EstimateSettings& s, double thetaIDeg)
        : m_bins(s.bins), m_est(s.estimator), m_orders(s.orders) {
        const double sigmaT = m.sigmaA + m.sigmaS;
        m_sigmaT = sigmaT;
        m_invSigmaT = 1.0 / sigmaT;
        albedo = m.sigmaS / sigmaT;
        m_g = m.g;
        m_eta = m.eta;
        m_etaOut = 1.0 / m.eta;
        const double cosI = std::cos(thetaIDeg * std::numbers::pi / 180.0);
        const double sinI = std::sin(thetaIDeg * std::numbers::pi / 180.0);
        m_specular = fresnelDielectric(std::max(cosI, 1e-300), m.eta);
        m_w0 = 1.0 - m_specular;
        const double sinT = sinI / m.eta;
        m_entry = {sinT, 0.0, -std::sqrt(std::max(0.0, 1.0 - sinT * sinT))};
        maxEvents = std::max<uint32_t>(1, s.termination.maxEvents);
        rouletteWeight = s.termination.rouletteWeight;
        rouletteSurvival = s.termination.rouletteSurvival;
        // Radial splitting (every estimator: an analog copy carries w/2^k and is still absorbed
        // by roulette, so its weight only changes where it splits or comes back).
        const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
        m_split = s.splitting.levels > 0 && std::isfinite(ld);
        if (m_split) {
            m_splitLevels = s.splitting.levels;
            m_splitStart = s.splitting.startLd * ld;
            m_splitStep = s.splitting.stepLd * ld;
            m_splitDepth = s.splitting.depth;
        }
        // The weight window: roulette below roulette_weight / 2^level.
        for (int k = 0; k <= (m_split ? m_splitLevels : 0); ++k)
            m_rouletteWeight.push_back(std::ldexp(rouletteWeight, -k));
        m_edges = m_bins.rEdges();
        m_uniformBins = m_bins.spacing == RadialSpacing::Uniform;
        m_invBinWidth = m_bins.rBins / (m_edges.back() - m_edges.front());
        m_nT = m_bins.thetaSBins;
        m_dTheta = std::numbers::pi / m_nT;
        m_nD = m_bins.dirBins();
        // Expected-value exits (pathtrace.h, ExpectedExits): the histogram walks only (the
        // connections estimator has its own phase-sampled technique).
        m_expected = s.exits.samples > 0 && m_est != BssrdfEstimator::Connections;
        m_exitSamples = std::max(1, s.exits.samples);
        m_exitDepth = s.exits.depthMfp * m_invSigmaT;
        m_exitRouletteBelow = std::exp(-kRouletteMfp);
        m_exitRouletteDepth = -kRouletteMfp * m_invSigmaT;
        m_muC = m_etaOut < 1.0 ? std::sqrt(1.0 - m_etaOut * m_etaOut) : 0.0;
        m_coneFraction = 0.5 * (1.0 - m_muC);
        m_binAcc.resize(size_t(m_bins.spatialBins()));
        if (m_nD > 1) m_dirAcc.resize(size_t(m_bins.spatialBins()) * size_t(m_nD));
    }

    // The Consts interface of detail::absorbAndRoulette / belowEventLimit.
    double albedo = 0;
    uint32_t maxEvents = 0;
    double rouletteWeight = 0, rouletteSurvival = 0;

    // One path (with every copy radial splitting makes of it) into `t`; `record` (may be null)
    // receives its accounting.
    // `path` is the path's index: it picks its batch (detail::batchOf).
    void trace(Pcg32 rng, uint64_t path, detail::ChunkTally& t, PathRecord* record = nullptr) {
        double absorbed = 0, loss = 0, truncated = 0, exitInside = 0, exitWeight = 0, exitR = -1;
        uint32_t work = 0, longest = 0; // interactions of every copy, of the longest
        if (record) *record = PathRecord{};
        const bool analog = m_est == BssrdfEstimator::Analog;
        const bool connect = m_est == BssrdfEstimator::Connections;
        // The current copy, in locals (kept in registers; the stack holds the others).
        double x = 0, y = 0, z = 0, w = m_w0;
        Dir u = m_entry;
        uint32_t events = 0;
        int level = 0;
        m_record = record;
        bool atCollision = false; // a copy taken from the stack starts at its collision
        m_stack.clear();
        for (;;) {
            bool ended = false;
            if (!atCollision) {
                const double s = sampleDistance(1.0, rng.uniform()) * m_invSigmaT;
                if (u.z > 0.0 && z + s * u.z >= 0.0) { // boundary hit
                    const double tHit = -z / u.z;
                    x += tHit * u.x;
                    y += tHit * u.y;
                    const double f = fresnelDielectric(u.z, m_etaOut);
                    if (f < 1.0 && (f <= 0.0 || rng.uniform32() >= f)) { // exit
                        // Tallied only as they happen where the walk does not tally their
                        // expectation at the collisions (ExpectedExits).
                        if (ordered(events))
                            exitInside += exitTally(x, y, u, w, !connect && !m_expected);
                        exitWeight += w;
                        exitR = std::sqrt(x * x + y * y);
                        if (record) {
                            record->exits.emplace_back(exitR, w);
                            if (!connect && !m_expected && ordered(events))
                                record->tallied.emplace_back(exitR, w);
                        }
                        ended = true;
                    } else {
                        u.z = -u.z;
                        const double rest = std::max(0.0, s - tHit);
                        x += rest * u.x;
                        y += rest * u.y;
                        z = rest * u.z;
                    }
                } else {
                    x += s * u.x;
                    y += s * u.y;
                    z += s * u.z;
                }
                if (!ended) {
                    ++events;
                    ++work;
                    if (connect && ordered(events)) connectVertex(x, y, z, u, albedo * w, rng);
                    ended = m_orders == ScatterOrders::SingleOnly && (connect || events >= 2);
                }
                // Radial splitting (Splitting in pathtrace.h): split on the way out, roulette
                // on the way in.
                if (!ended && m_split && !inLevel(x, y, z, level)) {
                    const int k = levelOf(x, y, z);
                    if (k > level) {
                        const int n = 1 << (k - level);
                        w /= n;
                        level = k;
                        for (int i = 1; i < n; ++i)
                            m_stack.push_back({x, y, z, u, w, events, k});
                    } else if (k < level) {
                        const double survive = std::ldexp(1.0, k - level);
                        if (rng.uniform32() < survive) {
                            const double ws = w / survive;
                            loss -= ws - w;
                            w = ws;
                            level = k;
                        } else {
                            loss += w;
                            ended = true;
                        }
                    }
                }
            }
            atCollision = false;
            if (!ended) {
                if (analog) {
                    if (rng.uniform32() >= albedo) {
                        absorbed += w;
                        ended = true;
                    }
                } else {
                    rouletteWeight = m_rouletteWeight[size_t(level)];
                    ended = !detail::absorbAndRoulette(w, absorbed, loss, *this, rng);
                }
                if (!ended) ended = !detail::belowEventLimit(w, truncated, events, *this);
            }
            if (ended) {
                longest = std::max(longest, events);
                if (m_stack.empty()) break;
                const Copy& c = m_stack.back();
                x = c.x, y = c.y, z = c.z, u = c.u, w = c.w, events = c.events, level = c.level;
                m_stack.pop_back();
                atCollision = true;
                continue;
            }
            const Dir uIn = u;
            u = m_g == 0.0 ? sampleSphere(rng) : scatterHg(u, m_g, rng);
            if (m_expected && ordered(events)) expectedExits(x, y, z, uIn, u, w, rng);
        }
        t.exitSum += exitWeight;
        t.exitSumSq += exitWeight * exitWeight;
        const size_t batch = detail::batchOf(path);
        const double binTotal = m_binAcc.flush(
            t.binSum, t.binSumSq,
            t.batchSum.empty() ? nullptr : t.batchSum.data() + batch * t.binSum.size());
        ++t.batchPaths[batch];
        if (m_nD > 1) m_dirAcc.flush(t.dirSum, t.dirSumSq);
        // Single-only connections end the walk at its first collision: no exits to compare.
        const double d =
            connect && m_orders != ScatterOrders::SingleOnly ? binTotal - exitInside : 0.0;
        t.energySum += d;
        t.energySumSq += d * d;
        t.absSum += absorbed;
        t.absSumSq += absorbed * absorbed;
        t.rouletteSum += loss;
        t.rouletteSumSq += loss * loss;
        t.truncSum += truncated;
        t.truncSumSq += truncated * truncated;
        if (truncated > 0) ++t.truncatedPaths;
        t.events += work;
        ++t.paths;
        if (record) {
            record->specular = m_specular;
            record->reflected = exitWeight;
            record->absorbed = absorbed;
            record->rouletteLoss = loss;
            record->truncated = truncated;
            record->exitR = exitR;
            record->events = work;
            record->longestCopy = longest;
            record->exited = exitR >= 0;
        };
    }

  private:
    // The state of one copy of a path at a collision (or, for the first, at entry).
    struct Copy {
        double x, y, z;
        Dir u;
        double w;
        uint32_t events;
        int level;
    };
    // Radial splitting's level of a point (pathtrace.h, Splitting).
    int levelOf(double x, double y, double z) const {
        const double v = std::sqrt(x * x + y * y) + m_splitDepth * z; // z <= 0
        if (!(v >= m_splitStart)) return 0;
        return int(
            std::min(double(m_splitLevels), 1.0 + std::floor((v - m_splitStart) / m_splitStep)));
    }
    // Whether (x, y, z) is still at `level`, without a square root: ρ + depth·z lies in
    // [start + (level − 1)·step, start + level·step) (the last level has no upper end).
    bool inLevel(double x, double y, double z, int level) const {
        const double rho2 = x * x + y * y, base = m_splitStart - m_splitDepth * z; // >= 0
        const double lo = level == 0 ? 0.0 : base + (level - 1) * m_splitStep;
        const double hi = base + level * m_splitStep;
        return rho2 >= lo * lo && (level == m_splitLevels || rho2 < hi * hi);
    }
    // Whether a collision (or an exit after `events` collisions) belongs to the tallied orders.
    bool ordered(uint32_t events) const {
        switch (m_orders) {
        case ScatterOrders::MultipleOnly:
            return events >= 2;
        case ScatterOrders::SingleOnly:
            return events == 1;
        default:
            return events >= 1;
        }
    }
    // The radial bin holding r (edges[i] <= r < edges[i + 1]), -1 outside the bins. Uniform
    // bins: a division, then the edges settle the rounding; others: a binary search.
    int radialBin(double r) const {
        if (!(r < m_edges.back()) || r < m_edges.front()) return -1;
        const int last = m_bins.rBins - 1;
        if (m_uniformBins) {
            int i = std::min(int((r - m_edges.front()) * m_invBinWidth), last);
            while (i > 0 && r < m_edges[size_t(i)])
                --i;
            while (i < last && r >= m_edges[size_t(i) + 1])
                ++i;
            return i;
        }
        const auto it = std::upper_bound(m_edges.begin(), m_edges.end(), r);
        return std::clamp(int(it - m_edges.begin()) - 1, 0, last);
    }
    // The θs bin of the surface point (px, py) (no arctangent when there is one bin).
    int thetaBin(double px, double py) const {
        if (m_nT == 1) return 0;
        return std::min(int(std::atan2(std::fabs(py), px) / m_dTheta), m_nT - 1);
    }

    // Tallies flux `v` leaving in bin (ir, it) at a surface point on the side `py` along the
    // internal direction `dir` (dir.z > 0); returns v.
    double tally(double py, const Dir& dir, double v, int ir, int it) {
        const int bin = ir * m_nT + it;
        m_binAcc.add(bin, v);
        if (m_nD > 1) {
            const double sin2 = m_eta * m_eta * (1.0 - dir.z * dir.z);
            const double cosO = std::sqrt(std::max(0.0, 1.0 - sin2));
            const double phi = std::atan2(py < 0 ? -dir.y : dir.y, dir.x);
            m_dirAcc.add(bin * m_nD + cellOf(m_bins, cosO, phi), v);
        }
        return v;
    }
    double exitTally(double px, double py, const Dir& dir, double w, bool histogram) {
        const int ir = radialBin(std::sqrt(px * px + py * py));
        if (ir < 0) return 0.0;
        if (!histogram) return w;
        return tally(py, dir, w, ir, thetaBin(px, py));
    }

    // Expected-value exits (pathtrace.h, ExpectedExits) of the flight that leaves the collision
    // at (x, y, z) with weight w along `out` (drawn from the phase function about `in`): the
    // walk's own direction, and near the surface m_exitSamples − 1 more from the same law, each
    // tallied with w e^{−σt d} T / n where it would meet the surface (d = |z| / ω_z).
    void expectedExits(double x, double y, double z, const Dir& in, const Dir& out, double w,
                       Pcg32& rng) {
        // Below d₀ every flight reaches the surface with at most top = e^{−σt|z|} < e^{−σt d₀}:
        // the collision takes one roulette first, survival top/e^{−σt d₀}, and each flight's own
        // (expectedExit) the rest, reach/top: the same survival, reach/e^{−σt d₀}, in all, at
        // one exponential for the many deep collisions that add nothing.
        double top = 1.0;
        if (z < m_exitRouletteDepth) {
            top = std::exp(m_sigmaT * z);
            if (rng.uniform32() * m_exitRouletteBelow >= top) return;
        }
        const int n = z >= -m_exitDepth ? m_exitSamples : 1;
        if (m_g == 0.0) { // isotropic: every direction from the escape cone
            const double wn = w * m_coneFraction / n;
            expectedExit(x, y, z, intoEscapeCone(out), wn, top, rng);
            for (int i = 1; i < n; ++i)
                expectedExit(x, y, z, intoEscapeCone(sampleSphere(rng)), wn, top, rng);
            return;
        }
        const double wn = w / n;
        expectedExit(x, y, z, out, wn, top, rng);
        for (int i = 1; i < n; ++i)
            expectedExit(x, y, z, scatterHg(in, m_g, rng), wn, top, rng);
    }
    // Isotropic scattering (g = 0): a uniform direction v on the sphere mapped to one uniform in
    // the escape cone ω_z in (μc, 1] (μc = √(1 − 1/η²), the critical cosine; 0 when η <= 1):
    // ω_z = μc + (1 − μc)|v_z| (|v_z| is uniform in [0, 1] and independent of v's azimuth,
    // which is kept). The sphere's other directions meet the surface under total internal
    // reflection or not at all and transmit nothing, so E[term] over the sphere is
    // m_coneFraction = (1 − μc)/2 times its mean over the cone: every sample tallies, where a
    // phase-sampled one is in the cone with probability (1 − μc)/2 (18 % at η = 1.3). The walk's
    // own direction is the first: it is uniform whatever the walk did before.
    Dir intoEscapeCone(const Dir& v) const {
        const double mu = m_muC + (1.0 - m_muC) * std::fabs(v.z);
        const double h2 = v.x * v.x + v.y * v.y;
        const double k = h2 > 0.0 ? std::sqrt(std::max(0.0, 1.0 - mu * mu) / h2) : 0.0;
        return {k * v.x, k * v.y, mu};
    }
    // One of them. A flight longer than d₀ = 2 mean free paths is tallied with probability
    // p = e^{−σt (d − d₀)} and weight 1/p (so its term is w e^{−σt d₀} T, bounded, and the
    // deep ones, which add almost nothing, cost one exponential).
    // `top`: the survival the collision's own roulette gave it, times e^{−σt d₀} (1: none).
    void expectedExit(double x, double y, double z, const Dir& v, double w, double top,
                      Pcg32& rng) {
        if (v.z <= 0.0) return;
        const double tHit = -z / v.z;
        double reach = std::exp(-m_sigmaT * tHit);
        if (reach < m_exitRouletteBelow) {
            if (rng.uniform32() * std::min(top, m_exitRouletteBelow) >= reach) return;
            reach = m_exitRouletteBelow;
        }
        const double t21 = 1.0 - fresnelDielectric(v.z, m_etaOut);
        if (t21 <= 0.0) return;
        const double px = x + tHit * v.x, py = y + tHit * v.y;
        const double r = std::sqrt(px * px + py * py);
        const int ir = radialBin(r);
        if (ir < 0) return;
        const double value = tally(py, v, w * reach * t21, ir, thetaBin(px, py));
        if (m_record) m_record->tallied.emplace_back(r, value);
    }

    // f/(q_a + q_p) for a connection from (x, y, z) arriving along u with scattered weight aw
    // to the surface point (px, py); 0 when nothing is transmitted. dir receives ω₂₁.
    double connection(double x, double y, double z, const Dir& u, double aw, double px, double py,
                      double qa, Dir& dir) const {
        const double dx = px - x, dy = py - y, dz = -z;
        const double d2 = dx * dx + dy * dy + dz * dz;
        const double d = std::sqrt(d2);
        const double inv = 1.0 / d;
        dir = {dx * inv, dy * inv, dz * inv};
        const double t21 = 1.0 - fresnelDielectric(dir.z, m_etaOut);
        if (t21 <= 0.0) return 0.0;
        const double phase =
            hgPdfCos(m_g, u.x * dir.x + u.y * dir.y + u.z * dir.z) / (2 * std::numbers::pi);
        const double qp = phase * dir.z / d2;
        const double f = aw * qp * std::exp(-m_sigmaT * d) * t21;
        return f / (qa + qp);
    }
    // Technique (a)'s area density at the point (r, θ) of radial bin ir: r uniform in the bin,
    // θ by the ring sampler (1/r: polar to area).
    double areaDensity(const detail::RingSampler& ring, double r, double px, double py,
                       int ir) const {
        return ring.pdf(px / r, py / r) / (r * (m_edges[size_t(ir) + 1] - m_edges[size_t(ir)]));
    }

    void connectVertex(double x, double y, double z, const Dir& u, double aw, Pcg32& rng) {
        // Connection roulette: a vertex farther than kRouletteMfp mean free paths from every
        // bin (the annulus [r_start, r_max) on the surface) connects with probability
        // p = e^{−σt (d_min − d₀)} and weight 1/p. Unbiased, and since every term carries
        // e^{−σt d} with d ≥ d_min, each stays below aw·e^{−σt d₀}: bounded. It spares the
        // deep and the far vertices, whose connections add almost nothing.
        const double rho = std::sqrt(x * x + y * y);
        const double h = std::max({0.0, m_edges.front() - rho, rho - m_edges.back()});
        const double dMin = std::sqrt(h * h + z * z), d0 = kRouletteMfp * m_invSigmaT;
        if (dMin > d0) {
            const double p = std::exp(-m_sigmaT * (dMin - d0));
            if (rng.uniform32() >= p) return;
            aw /= p;
        }
        Dir dir{};
        // (a) one point per radial bin: r uniform in the bin, θ ∝ 1/d² on its ring
        // (detail/ring_sampler.h); it lands in the θs sector it lands in.
        for (int ir = 0; ir < m_bins.rBins; ++ir) {
            const double r0 = m_edges[size_t(ir)], r1 = m_edges[size_t(ir) + 1];
            const double r = r0 + (r1 - r0) * rng.uniform32();
            if (!(r > 0.0)) continue; // measure zero
            const detail::RingSampler ring(x, y, z, r);
            double ct, st, density;
            ring.sampleRing(rng.uniform32(), ct, st, density);
            const double px = r * ct, py = r * st;
            const double c = connection(x, y, z, u, aw, px, py, density / (r * (r1 - r0)), dir);
            if (c > 0.0) tally(py, dir, c, ir, thetaBin(px, py));
        }
        // (b) one phase-sampled direction, if it meets the surface inside the bins.
        const Dir v = m_g == 0.0 ? sampleSphere(rng) : scatterHg(u, m_g, rng);
        if (v.z <= 0.0) return;
        const double tHit = -z / v.z;
        const double px = x + tHit * v.x, py = y + tHit * v.y;
        const double r = std::sqrt(px * px + py * py);
        const int ir = radialBin(r);
        if (ir < 0 || !(r > 0.0)) return;
        const detail::RingSampler ring(x, y, z, r);
        const double qa = areaDensity(ring, r, px, py, ir);
        const double c = connection(x, y, z, u, aw, px, py, qa, dir);
        if (c > 0.0) tally(py, dir, c, ir, thetaBin(px, py));
    }

    BssrdfBins m_bins;
    BssrdfEstimator m_est;
    ScatterOrders m_orders;
    double m_sigmaT = 0, m_invSigmaT = 0, m_g = 0, m_eta = 1, m_etaOut = 1;
    double m_specular = 0, m_w0 = 1;
    Dir m_entry{0, 0, -1};
    std::vector<double> m_edges;
    bool m_uniformBins = false;
    double m_invBinWidth = 0;
    int m_nT = 1, m_nD = 1;
    double m_dTheta = std::numbers::pi;
    PathAcc m_binAcc, m_dirAcc;
    bool m_split = false;
    int m_splitLevels = 0;
    double m_splitStart = 0, m_splitStep = 1, m_splitDepth = 0;
    PathRecord* m_record = nullptr; // the traced path's record (may be null)
    bool m_expected = false;        // expected-value exits
    int m_exitSamples = 1;
    double m_exitDepth = 0;                 // mm
    double m_exitRouletteBelow = 0;         // e^{−d₀σt}: roulette for flights longer than d₀
    double m_exitRouletteDepth = 0;         // −d₀: collisions below it take one roulette first
    double m_muC = 0, m_coneFraction = 0.5; // escape cone cos θc, its share of the sphere
    std::vector<double> m_rouletteWeight;   // per level
    std::vector<Copy> m_stack;              // copies waiting to be traced
};

} // namespace

namespace detail {
// Traces paths [first, first + count) into `t` (reset first). Returns the paths traced: fewer
// only when `cancel` was set.
PathRecord traceBssrdfPath(const Medium& m, const EstimateSettings& s, size_t angleIndex,
                           uint64_t path) {
    ChunkTally t;
    t.reset(s.bins, false);
    Walker walker(m, s, s.thetaIDeg[angleIndex]);
    PathRecord record;
    walker.trace(Pcg32::forPath(bssrdfStreamSeed(s.seed, angleIndex), path), path, t, &record);
    return record;
}

uint64_t traceBssrdfChunk(const Medium& m, const EstimateSettings& s, size_t angleIndex,
                          uint64_t first, uint64_t count, ChunkTally& t,
                          const std::atomic<bool>* cancel) {
    t.reset(s.bins);
    Walker walker(m, s, s.thetaIDeg[angleIndex]);
    const uint64_t seed = bssrdfStreamSeed(s.seed, angleIndex);
    for (uint64_t i = 0; i < count; ++i) {
        if ((i & 63u) == 0 && cancel && cancel->load(std::memory_order_relaxed)) return i;
        walker.trace(Pcg32::forPath(seed, first + i), first + i, t);
    }
    return count;
}
} // namespace detail

} // namespace pathtrace
