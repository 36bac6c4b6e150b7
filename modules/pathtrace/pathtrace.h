// pathtrace: the unbiased volumetric reference (thesis 3.2, Algorithm 1), CPU half.
//   Homogeneous medium under a dielectric boundary. Distance sampling s = −ln(1−ξ)/σt,
//   Henyey–Greenstein phase sampling by exact inversion, exact unpolarised Fresnel with
//   reflection/transmission roulette at every boundary hit, weight roulette with bounded
//   survivors and a tallied truncation (no long-path roulette, see Termination).
//   RGB is traced one channel at a time, each channel its own medium (Medium below).
//   Randomness: one counter-based stream per path index (PCG32 seeded by (seed, path)), paths
//   tallied in fixed-size chunks merged in chunk order, so results are bitwise identical for
//   any thread count.
//   Geometry here: the semi-infinite slab z < 0 under a normally incident pencil beam at the
//   origin; tallies in the MCML convention (Wang, Jacques & Zheng 1995): R_d(r) is diffuse
//   reflectance per unit area per incident photon (1/mm²), excluding the specular reflection
//   at entry but including the Fresnel loss on entering.
//   Estimator (bssrdf_walk.cpp at θi = 0): the photon enters with weight 1 − R_sp (R_sp tallied as
//   `specular`, not sampled). Implicit absorption (default): at every interaction the weight is
//   multiplied by the albedo α = σs/σt and the expected absorbed weight w(1 − α) is tallied as
//   absorbed; Russian roulette below `rouletteWeight` (survive with `rouletteSurvival`,
//   w /= p). Estimator::Analog is Algorithm 1 as printed (absorb with probability 1 − α).
//   Boundary hits: Fresnel roulette (reflect with probability R(θ), else exit; the thesis's
//   f_t = 1 − R).
//   Termination (Termination below, shared by every tracer, CPU and GPU): only the weight
//   roulette ends a path early, and its survivors carry w/p < rouletteWeight/p, so every
//   path's weight stays bounded (≤ max(1, rouletteWeight/p)) and both the estimate and its
//   variance are sound. The thesis's long-path roulette (3.2: past 1000 events end with 90 %,
//   else ×10) is not used: its survivors' weight grows as 10^k, its variance is unbounded, and
//   in any finite run its rare survivors are never sampled, so its mean came out low (1 % for
//   albedo 0.999, 7 % for σa = 0) with too small an error bar. A path still alive after
//   `maxEvents` interactions is truncated: its weight is tallied as `truncated`, a bound on
//   the bias of R_d (that weight would have left or been absorbed). With the default 2^20
//   events this happens only for albedo within ~1e-5 of 1 (σa = 0: Spectralon), where it is
//   printed as a bound; for albedo ≤ 0.9999 the weight roulette has ended every path long
//   before (w ≤ α^(2^20) < e^−100). Per path, exactly up to rounding,
//       specular + reflected + absorbed + truncated + rouletteLoss = 1,
//   with E[rouletteLoss] = 0 (energyProblem() checks both and says so when they fail).
//   Defaults of the weight roulette (0.1, 0.5) were tuned on the reference case η 1.3,
//   σa 0.01, σs 1, g 0 (1/mm) for time to 1 % error at r = l_d and 4 l_d.
//   The CPU walk is the oblique-incidence walk of bssrdf_walk.cpp at θi = 0 (one walk for
//   tracePath, traceSlab, runSlab and `estimate`), which also offers the connection estimator
//   of seed 001 (Estimator::Connections); chunk sums are exact, so runs are bitwise
//   independent of threads and shards.
//   Files: rng.h (PCG32 streams), sampling.h (distance, HG, direction frame), fresnel.h,
//   bssrdf_walk.cpp (the path loop), slab_connections.cpp (the slab entry points),
//   tally.cpp (sums, merge, finalize), run_slab.cpp, validate.cpp.
#pragma once

#include "core/limits.h"
#include "core/relative_error.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace pathtrace {

struct Medium {
    double sigmaA = 0.01; // 1/mm, >= 0
    double sigmaS = 1.0;  // 1/mm, > 0
    double g = 0.0;       // HG mean cosine, |g| < 1
    double eta = 1.3;     // relative index of refraction (medium / outside), > 0
};
// The description of Medium's members (core/fields.h).
template <class V> void fields(V& v, Medium& m) {
    v("sigma_a", m.sigmaA, "absorption coefficient, 1/mm", core::Limits{0, 1e6});
    v("sigma_s", m.sigmaS, "scattering coefficient, 1/mm", core::Limits{0, 1e6});
    v("g", m.g, "Henyey-Greenstein mean cosine", core::Limits{-1, 1});
    v("eta", m.eta, "relative index of refraction (medium / outside)", core::Limits{0.01, 100});
}
// Throws core::Error("<what>", 0, msg) naming the field.
void validate(const Medium& m, const std::string& what = "medium");

// How paths end, for every tracer (slab, sphere, mesh; CPU and GPU). See the header comment.
struct Termination {
    double rouletteWeight = 0.1;   // weight roulette below this weight (Implicit)
    double rouletteSurvival = 0.5; // its survival probability p (survivors' weight /= p)
    uint32_t maxEvents = 1u << 20; // a path alive after this many interactions is truncated
};
// The description of Termination's members (core/fields.h).
template <class V> void fields(V& v, Termination& t) {
    v("roulette_weight", t.rouletteWeight, "weight roulette below this weight", core::Limits{0, 1});
    v("roulette_survival", t.rouletteSurvival, "roulette survival probability",
      core::Limits{1e-6, 1});
    v("max_events", t.maxEvents, "interactions after which a path is truncated",
      core::Limits{1, 4294967295.0});
}
// Throws core::Error("<what>", 0, msg) naming the field: rouletteWeight not in (0, 1),
// rouletteSurvival not in (0, 1], maxEvents < 1.
void validate(const Termination& t, const std::string& what);

// Radial splitting of the slab walk (bssrdf_walk.cpp; CPU only): importance splitting by
// position (geometry splitting, Kahn & Harris 1951) with Russian roulette on the way back, so
// that the walk spends its time where the pencil profile is hardest to resolve, far from the
// beam. A collision at radius ρ from the entry point and depth |z| has level
//     k = min(levels, 1 + ⌊(ρ − depth·|z| − start·l_d) / (step·l_d)⌋)  (0 below start),
// l_d = 1/√(3σa σt') the diffusion length (σa = 0: no splitting). Importance is 2^k: a path
// that climbs from level k to k' > k goes on as 2^{k'−k} copies of weight w/2^{k'−k}; one that
// falls to k' < k survives with probability 2^{k'−k} and weight w·2^{k−k'}; the weight roulette
// compares w·2^k with roulette_weight (a weight window). Unbiased, and w·2^k never grows, so
// weights stay bounded. A path's copies belong to its history: they are tallied into the same
// per-path sums (second moments per history, so standard errors stay honest) and draw from its
// one random stream, so results stay independent of threads and shards. Analog walks split too:
// a copy carries w/2^k and absorption stays a roulette (Estimator::Analog is then Algorithm 1
// with splitting; levels 0 gives Algorithm 1 as printed). The defaults were chosen by `bench
// pathtrace`'s efficiency per radial range on the cases of its tables (docs/ARCHITECTURE.md,
// "Radial splitting").
struct Splitting {
    int levels = 5;       // 0: off
    double startLd = 0.5; // first level at ρ − depth·|z| = start·l_d
    double stepLd = 1.0;  // one level more every step·l_d
    double depth = 3.0;   // weight of depth against radius
};
template <class V> void fields(V& v, Splitting& s) {
    v("levels", s.levels, "splitting levels (importance x2 each; 0: off)", core::Limits{0, 10});
    v("start_ld", s.startLd, "first level at rho - depth*|z| = start * l_d", core::Limits{0, 1e6});
    v("step_ld", s.stepLd, "one more level every step * l_d", core::Limits{1e-3, 1e6});
    v("depth", s.depth, "weight of depth |z| against radius rho", core::Limits{0, 1e6});
}
void validate(const Splitting& s, const std::string& what);

// Expected-value exits (next-flight estimation; bssrdf_walk.cpp, CPU histogram estimators
// only). A flight that leaves a collision at depth |z| along ω (ω_z > 0) exits with probability
// e^{−σt |z|/ω_z} · T(ω_z), T = 1 − Fresnel, at the point and refracted direction where it meets
// the surface. Instead of tallying the exits that happen, the walk tallies this expectation of
// every flight: the weight times it, in the exit's bin. A path then adds to every bin it passes
// near, not only to the one it leaves through, and its actual exits (which end it, as before)
// add nothing to the table. At collisions within `depth_mfp` mean free paths of the surface the
// expectation is averaged over `samples` directions drawn from the phase function (the walk's
// own next direction and samples − 1 more), deeper ones use the walk's own direction. In an
// isotropic medium (g 0) every direction is drawn from the escape cone instead (the walk's own
// mapped into it), weighted by the cone's share of the sphere: directions outside it transmit
// nothing, so every sample tallies (at η 1.3 a phase-sampled one would in 18 % of draws). The same
// expectation per bin as the exits (each term is the exit's conditional mean given the state
// at the collision), a lower variance per path: `bench pathtrace`'s time to 1 % per bin is 1.1–2.4x
// shorter on its cases with kExpectedExitSamples (docs/ARCHITECTURE.md, "Expected-value exits").
// The energy checks per path still use the actual exits.
// On by default with kExpectedExitSamples, what `bench pathtrace` found best (2–4 within 1–2
// mean free paths were within the noise on its cases); samples 0 tallies the actual exits
// (Algorithm 1 as printed), as the GL tracers do. A path costs about twice as much (K
// directions, each with its Fresnel and exponential) and reaches 1 % per bin sooner at every
// radius measured. A path's terms make neighbouring bins positively correlated: each bin's
// standard error stays honest, and an error of a sum over bins (rel_err's,
// core/relative_error.h) takes the covariance from the batch means (kBatches below); a fit that
// weighs bins as independent wants the actual exits.
inline constexpr int kExpectedExitSamples = 2;
struct ExpectedExits {
    int samples = kExpectedExitSamples; // 0: tally the actual exits
    double depthMfp = 2.0; // collisions this close to the surface average `samples` directions
};
template <class V> void fields(V& v, ExpectedExits& e) {
    v("samples", e.samples,
      "phase directions scored per collision near the surface (0: actual exits)",
      core::Limits{0, 64});
    v("depth_mfp", e.depthMfp, "depth of the collisions scored with every sample, mean free paths",
      core::Limits{0, 1e6});
}
void validate(const ExpectedExits& e, const std::string& what);

enum class Estimator {
    Implicit,    // absorption by weight + weight roulette (efficient; the default)
    Analog,      // thesis Algorithm 1 as printed: absorption by roulette
    Connections, // the implicit walk with every collision connected to every bin (seed 001;
                 // bssrdf_estimate.h at θi = 0, slab_connections.cpp); CPU only
};
constexpr auto enumNames(Estimator) {
    return std::array{std::pair{Estimator::Implicit, "implicit"},
                      std::pair{Estimator::Analog, "analog"},
                      std::pair{Estimator::Connections, "connections"}};
}

struct SlabSettings {
    double rMaxMm = 10.0; // histogram covers [0, rMax)
    int bins = 200;       // radial bins of equal width
    uint64_t paths = 1000000;
    uint64_t seed = 1;
    int threads = 0; // 0: all hardware threads
    Termination termination;
    Estimator estimator = Estimator::Implicit;
    Splitting splitting; // CPU walk only (the GL tracer ignores it: same expectation)
    ExpectedExits exits; // CPU histogram walks only (the GL tracer ignores it: same expectation)
};
// The description of SlabSettings' members (core/fields.h).
template <class V> void fields(V& v, SlabSettings& s) {
    v("r_max_mm", s.rMaxMm, "histogram radius, mm", core::Limits{1e-9, 1e9});
    v("bins", s.bins, "radial bins", core::Limits{1, 1e6});
    v("paths", s.paths, "photon paths", core::Limits{1, 1e18});
    v("seed", s.seed, "random seed");
    v.skip(s.threads, "worker threads; results do not depend on it");
    v("termination", s.termination, "roulette and event limit");
    v("estimator", s.estimator, "absorption estimator");
    v("splitting", s.splitting, "radial splitting (CPU)");
    v("exits", s.exits, "expected-value exits (CPU histogram walks)");
}
// Throws core::Error naming the field: rMax <= 0 or non-finite, bins < 1 or too many
// (> 1e7), paths == 0 or absurd (> 1e13), threads < 0, a bad termination (see above).
void validate(const SlabSettings& s);

// Batch means. The paths are split into kBatches batches by index (path i in batch
// i mod kBatches) and each spatial bin's sum is kept per batch besides the total: the spread of
// the batches' means gives the covariance of any linear combination of bins (rel_err's standard
// error, core/relative_error.h), which the per-bin second moments cannot where one path adds to
// several bins (expected-value exits, connections, splitting). Kept while the spatial bins are
// at most kMaxBatchedBins (the sums cost kBatches times the bins' memory).
inline constexpr size_t kBatches = 32;
inline constexpr int kMaxBatchedBins = 4096;

// Mergeable sums over paths (per-path first and second moments of every figure).
struct SlabTally {
    uint64_t paths = 0;
    // Per radial bin: Σ w, Σ w² (w: the weight a path left there; at most one bin per path).
    std::vector<double> binSum, binSumSq;
    double rdSum = 0, rdSumSq = 0;             // total diffuse reflectance
    double absSum = 0, absSumSq = 0;           // absorbed
    double specular = 0;                       // R_sp per path (deterministic, the same for all)
    double rouletteSum = 0, rouletteSumSq = 0; // weight removed by roulettes (E = 0)
    double truncSum = 0, truncSumSq = 0;       // weight of paths truncated at maxEvents
    uint64_t truncatedPaths = 0;
    uint64_t events = 0;             // interactions (scattering or absorption) traced
    double gapSum = 0, gapSumSq = 0; // Connections: Σ over paths of (Σ bins − exit in rMax)
    // Σ w per (batch, bin), batch-major (kBatches below); empty where the tracer keeps none (the
    // GL tracer, older tables): then rel_err takes the bins as independent.
    std::vector<double> batchSum;
    std::array<uint64_t, kBatches> batchPaths{}; // paths per batch
    // Adds the other's sums (bins must agree; an empty tally adopts the other's size).
    void merge(const SlabTally& other);
};

// What one path did (tracePath): the per-path accounting identity
//   specular + reflected + absorbed + truncated + rouletteLoss == 1 holds up to rounding.
// A path split by radial splitting (Splitting) is one record with all its copies: their exits,
// weights and interactions add up.
struct PathRecord {
    double specular = 0;      // R_sp
    double reflected = 0;     // weight that left through the surface (0 when it did not)
    double absorbed = 0;      // absorbed weight (expected, under Estimator::Implicit)
    double rouletteLoss = 0;  // weight removed minus weight added by roulettes
    double truncated = 0;     // weight of the path when it was truncated at maxEvents
    double exitR = -1;        // radius of the last exit point, mm (-1: did not exit)
    uint32_t events = 0;      // interactions, every copy's
    uint32_t longestCopy = 0; // interactions of its longest copy (<= maxEvents)
    bool exited = false;
    std::vector<std::pair<double, double>> exits; // (radius mm, weight) of every exit, in order
    // (radius mm, value) of every term the walk added to the histogram, in order: the exits
    // themselves, or with expected-value exits (ExpectedExits) the expectations it tallied.
    std::vector<std::pair<double, double>> tallied;
};
// Paths are tallied and merged in chunks of this many, whatever the thread count.
constexpr uint64_t kChunkPaths = 16384;

// Traces path `pathIndex` (its own random stream) and returns its accounting. Validates first.
PathRecord tracePath(const Medium& m, const SlabSettings& s, uint64_t pathIndex);
// An empty tally sized for s.bins.
SlabTally makeTally(const SlabSettings& s);
// Adds path `pathIndex` to a tally (in this order every sum is formed path by path).
void accumulate(SlabTally& t, const PathRecord& p, const SlabSettings& s, uint64_t pathIndex);
// Radial bin of an exit radius, or -1 beyond rMax.
int binOf(double r, const SlabSettings& s);

struct SlabResult {
    std::vector<double> rMid;     // bin centres, mm
    std::vector<double> rd;       // R_d(r), 1/mm², MCML convention
    std::vector<double> rdStderr; // standard error of rd
    double totalRd = 0, totalRdStderr = 0;
    double specular = 0; // R_sp
    double absorbed = 0, absorbedStderr = 0;
    uint64_t paths = 0;
    double seconds = 0;
    double rouletteNet = 0, rouletteNetStderr = 0; // mean roulette loss (expected 0)
    double truncated = 0, truncatedStderr = 0;     // mean truncated weight: a bound on the bias
    uint64_t truncatedPaths = 0;
    uint64_t events = 0;
    // Connections only: mean per path of (Σ bins − exit weight inside rMax), expected 0.
    double connectionGap = 0, connectionGapStderr = 0;
    core::BatchMeans rdBatches; // rd per batch (kBatches); empty when the tally has none
};

// The reference's own energy check. Empty when it holds, else one sentence saying what failed:
//   - the accounting specular + R_d + absorbed + truncated + roulette = 1 is off by more than
//     rounding (1e-6; the GPU tally rounds floats);
//   - the mean roulette loss is inconsistent with 0: |z| > kEnergyZ (a roulette is biased);
//   - truncated weight exceeds the standard error of the total R_d: the error bars no longer
//     cover the truncation bias, so R_d may be low by up to `truncated` (raise maxEvents);
//   - connections only: the binned flux and the walk's exits inside rMax disagree, |z| > kEnergyZ.
// kEnergyZ = 5 (two-sided p 6e-7): the GUI checks every progressive snapshot of three
// channels, so a threshold for one test would raise false alarms over a long session.
constexpr double kEnergyZ = 5.0;
std::string energyProblem(const SlabResult& r);

// Traces paths [first, first + count) (deterministic per path index), summed path by path.
// `cancel` may be null; when it is set the tally covers the paths done so far (t.paths).
SlabTally traceSlab(const Medium& m, const SlabSettings& s, uint64_t first, uint64_t count,
                    const std::atomic<bool>* cancel = nullptr);
// Multi-threaded run of s.paths paths in chunks of kChunkPaths; tallies are summed path by path
// in path order, so the result is bitwise identical to traceSlab(m, s, 0, s.paths) for any
// thread count. `progress(done)` is called from the calling thread about every 50 ms. When
// `cancel` is set, the result covers the completed prefix of chunks only (fewer paths, still
// unbiased). Validates first (core::Error).
SlabResult runSlab(const Medium& m, const SlabSettings& s,
                   const std::function<void(uint64_t done)>& progress = {},
                   const std::atomic<bool>* cancel = nullptr);
// rd[i] = binSum / (paths · π(r_{i+1}² − r_i²)) in 1/mm²; standard errors from the per-path
// second moments, sqrt((ΣX²/N − (ΣX/N)²)/(N − 1)) (/ area for bins); infinite for N < 2.
SlabResult finalize(const SlabTally& t, const SlabSettings& s);

} // namespace pathtrace
