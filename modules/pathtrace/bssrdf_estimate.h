// pathtrace/bssrdf_estimate: the whole BSSRDF of the semi-infinite slab at oblique incidence,
//   S(r, θs, ω_o; θi) and R(r, θs; θi), by the random walk of Dal Corso & Frisvad ("On BSSRDF
//   estimation", 2018; seed 001) with three estimators:
//     analog, implicit   the walk's exits binned by exit point and refracted exit direction (a
//                        histogram; the slab tracer's estimators at any θi),
//     connections        every scattering vertex connected to a point in every spatial bin
//                        (seed 001 §1), combined with a phase-sampled point on the surface by
//                        the balance heuristic so the variance stays finite (derivation in
//                        bssrdf_walk.cpp).
//   Geometry: surface z = 0, medium z < 0, outward normal +z; the beam enters at the origin
//   travelling toward +x at θi from the normal. Spatial bins are polar around the entry point:
//   r in [r_start, r_max) (r_start 0 by default) uniform or logarithmic, θs = atan2(|y|, x) in [0°,
//   180°] folded by the mirror symmetry y → −y (θs = 0 is forward). Directional bins split the
//   exitant hemisphere into cells of equal solid angle 2π/(dirCos·dirPhi): cos θo uniform in [0,
//   1], φo in [0°, 360°) from +x (a point folded from y < 0 has its direction mirrored, φo → −φo).
//   Units and conventions (MCML, per incident photon, specular reflection at entry excluded):
//     R = Φ_bin / A_bin in 1/mm², A_bin = (r_hi² − r_lo²)·Δθs (both mirror halves);
//     S = Φ_cell / (A_bin · ∫cell cos θo dω) in 1/(mm²·sr), so Σ_cells S·∫cos dω = R exactly.
//   Sums: each chunk of kChunkPaths paths is summed path by path in doubles, then added into
//   ExactSum accumulators (detail/exact_sum.h), so a run cut into shards (disjoint chunk ranges)
//   and merged gives bitwise the table of one run, for any thread and shard count.
//   The same walk and estimators on the GL compute tracer: gpu_bssrdf.h (its tallies have this
//   shape; the connections' second moments there come from batch means).
#pragma once

#include "core/limits.h"
#include "pathtrace/detail/exact_sum.h"
#include "pathtrace/pathtrace.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace pathtrace {

enum class BssrdfEstimator { Analog, Implicit, Connections };
constexpr auto enumNames(BssrdfEstimator) {
    return std::array{std::pair{BssrdfEstimator::Analog, "analog"},
                      std::pair{BssrdfEstimator::Implicit, "implicit"},
                      std::pair{BssrdfEstimator::Connections, "connections"}};
}
// Which scattering orders are tallied: all, all but the first (multiple scattering only), or
// the first only (single scattering only).
enum class ScatterOrders { All, MultipleOnly, SingleOnly };
constexpr auto enumNames(ScatterOrders) {
    return std::array{std::pair{ScatterOrders::All, "all"},
                      std::pair{ScatterOrders::MultipleOnly, "multiple"},
                      std::pair{ScatterOrders::SingleOnly, "single"}};
}
enum class RadialSpacing { Uniform, Log };
constexpr auto enumNames(RadialSpacing) {
    return std::array{std::pair{RadialSpacing::Uniform, "uniform"},
                      std::pair{RadialSpacing::Log, "log"}};
}

struct BssrdfBins {
    int rBins = 50;
    double rMaxMm = 10.0;
    RadialSpacing spacing = RadialSpacing::Uniform;
    double rStartMm = 0.0; // inner edge of the first bin (bins cover [rStart, rMax))
    double rMinMm = 0.0;   // Log with rStart 0: the first bin is [0, rMin); 0 picks rMax/1000
    int thetaSBins = 6;    // over [0°, 180°]
    int dirCosBins = 1;    // rings of equal solid angle (cos θo uniform)
    int dirPhiBins = 1;    // azimuth sectors over [0°, 360°)

    int spatialBins() const { return rBins * thetaSBins; }
    int dirBins() const { return dirCosBins * dirPhiBins; }
    // Edges of the radial bins (rBins + 1 values, rStart first).
    std::vector<double> rEdges() const;
};
template <class V> void fields(V& v, BssrdfBins& b) {
    v("r_bins", b.rBins, "radial bins", core::Limits{1, 1e5});
    v("r_max_mm", b.rMaxMm, "radius of the last bin edge, mm", core::Limits{1e-9, 1e9});
    v("r_spacing", b.spacing, "radial bin spacing");
    v("r_start_mm", b.rStartMm, "inner edge of the first radial bin, mm", core::Limits{0, 1e9});
    v("r_min_mm", b.rMinMm, "log spacing: outer edge of the first bin, mm (0: r_max/1000)",
      core::Limits{0, 1e9});
    v("theta_s_bins", b.thetaSBins, "bins of theta_s over [0, 180] deg", core::Limits{1, 1e4});
    v("dir_cos_bins", b.dirCosBins, "exit-direction rings (equal solid angle)",
      core::Limits{1, 1e4});
    v("dir_phi_bins", b.dirPhiBins, "exit-direction azimuth sectors", core::Limits{1, 1e4});
}

struct EstimateSettings {
    std::vector<double> thetaIDeg{0.0}; // incidence angles, [0, 90)
    BssrdfBins bins;
    uint64_t paths = 100000; // per incidence angle
    uint64_t seed = 1;
    int threads = 0; // 0: all hardware threads; results do not depend on it
    Termination termination;
    BssrdfEstimator estimator = BssrdfEstimator::Connections;
    ScatterOrders orders = ScatterOrders::All;
    Splitting splitting; // CPU walk only (pathtrace.h)
    ExpectedExits exits; // CPU histogram walks only (pathtrace.h)
};
template <class V> void fields(V& v, EstimateSettings& s) {
    v("theta_i_deg", s.thetaIDeg, "incidence angles, degrees");
    v("bins", s.bins, "spatial and directional bins");
    v("paths", s.paths, "photon paths per incidence angle", core::Limits{1, 1e18});
    v("seed", s.seed, "random seed");
    v.skip(s.threads, "worker threads; results do not depend on it");
    v("termination", s.termination, "roulette and event limit");
    v("estimator", s.estimator, "estimator");
    v("orders", s.orders, "scattering orders tallied");
    v("splitting", s.splitting, "radial splitting (CPU)");
    v("exits", s.exits, "expected-value exits (CPU histogram walks)");
}
// Throws core::Error naming the setting: θi outside [0°, 90°) or not finite, no angle, bins
// < 1 or absurd (more than 1e4 radial or θs bins, 1e3 direction rings or sectors, 4e6 cells in
// all), r_max not a positive finite length, log r_min not in (0, r_max), paths 0 or > 1e13,
// threads < 0, a bad termination.
void validate(const EstimateSettings& s);

// Raw sums of one incidence angle (mergeable; exact, so order does not matter).
struct BssrdfTally {
    uint64_t paths = 0;
    std::vector<detail::ExactSum> binSum, binSumSq; // per spatial bin: Σ Φ, Σ Φ² over paths
    // Σ Φ per (batch, spatial bin), batch-major; empty when not kept (older tables, > 4096 bins)
    std::vector<detail::ExactSum> batchSum;
    std::array<uint64_t, kBatches> batchPaths{};    // paths per batch
    std::vector<detail::ExactSum> dirSum, dirSumSq; // per (spatial bin, cell); empty if 1 cell
    detail::ExactSum exitSum, exitSumSq;            // weight that left through the surface
    detail::ExactSum absSum, absSumSq;              // absorbed
    detail::ExactSum rouletteSum, rouletteSumSq;    // roulette loss (E = 0)
    detail::ExactSum truncSum, truncSumSq;          // truncated at maxEvents
    // Energy of the connections: per path D = Σ_bins Φ − (walk's exit weight inside r_max);
    // E[D] = 0 (the connections and the walk estimate the same flux).
    detail::ExactSum energySum, energySumSq;
    detail::ExactSum events;
    uint64_t truncatedPaths = 0;
    // Adds another tally of the same shape (exact). Throws core::Error when shapes differ.
    void merge(const BssrdfTally& o);
    bool operator==(const BssrdfTally& o) const = default;
};
BssrdfTally makeTally(const BssrdfBins& b);

// A finished table for one incidence angle.
struct BssrdfSlice {
    double thetaIDeg = 0;
    double specular = 0; // Fresnel reflectance at entry, R(θi)
    uint64_t paths = 0;
    std::vector<double> R, RStderr; // per spatial bin [ir·thetaSBins + it], 1/mm²
    std::vector<double> S, SStderr; // per [bin·dirBins + cell], 1/(mm²·sr); empty if 1 cell
    core::BatchMeans RBatches;      // R per batch (kBatches); empty when the tally has none
    double totalRd = 0, totalRdStderr = 0; // walk's exits (all radii)
    double absorbed = 0, absorbedStderr = 0;
    double rouletteNet = 0, rouletteNetStderr = 0;
    double truncated = 0, truncatedStderr = 0;
    uint64_t truncatedPaths = 0;
    double energyDiff = 0, energyDiffStderr = 0; // mean D (connections only), expected 0
    double eventsPerPath = 0;
};
// Bin geometry shared by the walk, finalize, and every reader of a table.
double binArea(const BssrdfBins& b, int ir);                 // one spatial bin at radius index
double cellProjectedSolidAngle(const BssrdfBins& b, int ic); // ∫ cos θo dω over the cell
// The cell of an exitant direction with cos θo in (0, 1] and azimuth φo in radians (−π, π].
int cellOf(const BssrdfBins& b, double cosThetaO, double phiO);

BssrdfSlice finalize(const BssrdfTally& t, const BssrdfBins& b, double thetaIDeg, const Medium& m);
// The slice's own energy check (as energyProblem of a SlabResult): the accounting identity,
// the roulette and truncation tests, and for connections |z| of the mean gap between binned
// flux and exits ≤ kEnergyZ. Empty when it holds. Orders other than All cut the walk, so only
// the gap is checked then.
std::string energyProblem(const BssrdfSlice& s, ScatterOrders orders);

// Traces paths [chunk·kChunkPaths …) of the chunks [firstChunk, lastChunk) for one incidence
// angle (path streams keyed by (seed + angle index, path), so each angle has its own streams).
// `progress(done)` gets the paths traced so far; when `cancel` is set the tally keeps the
// completed chunks. Validates first.
BssrdfTally estimateChunks(const Medium& m, const EstimateSettings& s, size_t angleIndex,
                           uint64_t firstChunk, uint64_t lastChunk,
                           const std::function<void(uint64_t)>& progress = {},
                           const std::atomic<bool>* cancel = nullptr);
// Number of chunks of s.paths paths.
uint64_t chunkCount(const EstimateSettings& s);
// The chunks [first, last) of shard k of n (0-based k): an even split of the chunks.
std::pair<uint64_t, uint64_t> shardChunks(const EstimateSettings& s, uint64_t k, uint64_t n);

} // namespace pathtrace
