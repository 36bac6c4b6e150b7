// core/relative_error.h: rel_err, the one error measure of a model against a Monte Carlo
// reference (the scoreboard, `compare`, the pencil-plot legend, the slice panel, the baseline
// gate). It is the RMS relative error over log radius,
//   e² = ∫ ((R_m − R_ref)/R_ref)² d ln r / ln(b/a)        over r ∈ [a, b] = [0.1 l_d, 4 l_d],
// which weighs every octave of radius alike (unlike ∫(R_m − R_ref)² r dr / ∫R_ref² r dr, which the
// first millimetre dominates, so that moving a bound by one fine bin moved it by half).
// On the reference's bins it is the sum
//   e² = Σ_i w_i t_i / Σ_i w_i,   w_i = the bin's measure (ln-overlap with [a, b], times its θs
//                                       width or exit solid angle where the bins have those),
//   t_i = (x_i − 1)² − c_i² (3x_i² − 2x_i),   x_i = M_i / R_i,  c_i = s_i / R_i,
// with M_i the model averaged over bin i (as the reference is: area-weighted), R_i the bin's
// reference mean and s_i its standard error. The second term removes the reference's own noise:
// for R̂ = R(1 + ε), ε ~ N(0, c²), E[(M/R̂ − 1)²] = (x − 1)² + c²(3x² − 2x) + O(c⁴), so a model
// equal to the truth scores 0 in expectation however few paths the reference has.
// Its standard error: to second order in ε, t_i = t̄_i + g ε + q(ε² − c²) with
// g = −2x(x − 1) + c²(12x² − 6x) and q = 3x² − 2x, so Var t_i = g²c² + 2q²c⁴, where (x − 1)² in g²
// is estimated by t_i itself (the raw (x̂ − 1)² would count the noise twice); the sum is kept at
// least its χ² part Σ(w_i/W)² 2q²c⁴. se(e²) = √Σ(w_i/W)² Var t_i for independent bins; where the
// reference has batch means (BatchMeans below) the linear part's variance comes from the
// batches' spread instead, so the bins' covariance counts. And, since e = √e² is not
// differentiable at 0, se(e) = √(e² + se(e²)) − e (→ se(e²)/2e for e ≫ √se(e²), → √se(e²) at 0).
// A negative e² (all the difference is noise) reports e = 0.
// Written by hand: no packaged library computes this measure.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace core {

// The radial range of rel_err in units of the channel's diffuse mean free path l_d.
inline constexpr double kRelErrFromLd = 0.1, kRelErrToLd = 4.0;

// Batch means of a Monte Carlo reference: its paths split into B batches (the slab and BSSRDF
// walks: path i in batch i mod 32), mean[b][i] the mean of bin i over batch b's paths (in the
// bins' units), fraction[b] = N_b / N, so the reference's mean is Σ_b fraction[b]·mean[b][i].
// Empty: not known.
struct BatchMeans {
    std::vector<double> fraction;
    std::vector<std::vector<double>> mean;
    bool empty() const { return fraction.empty(); }
    // The same with every mean times `factor` (a change of units, e.g. per photon entering).
    BatchMeans scaled(double factor) const {
        BatchMeans out = *this;
        for (auto& batch : out.mean)
            for (double& x : batch)
                x *= factor;
        return out;
    }
};

// One bin of the sum above: its weight w_i, the model's mean over it M_i, the reference's
// mean R_i and standard error s_i; `batch` its batch means (all bins or none).
struct ErrorBin {
    double weight = 0, model = 0, ref = 0, refSe = 0;
    std::vector<double> batch; // R_i over each batch (BatchMeans::mean[b][i]); empty: not known
};

struct RelativeError {
    double value = 0, se = 0; // e and its standard error; NaN when `problem` is set
    double squared = 0;       // e² before the clamp at 0 (may be < 0 where noise dominates):
                              // smooth through 0, what a fit minimises
    std::string problem;      // why there is no value ("" when there is)
    int badBin = -1;          // the first bin that made `problem`, if one did
    bool valid() const { return problem.empty(); }
};

// rel_err of `bins` (weights > 0 count; a counted bin whose reference is not > 0 or whose model
// is not finite sets `problem` and `badBin`; so do no counted bins). With `batchFraction` (the
// reference's BatchMeans::fraction) and every counted bin's batch means, the linear part of the
// variance, Var Σ_i k_i g_i ε_i (k_i = w_i/W, ε_i the reference's relative error in bin i), is
// taken from the batches' spread, Σ_b f_b (L_b − L̄)² / (B − 1) with L_b = Σ_i k_i g_i
// (R_i^b − R_i)/R_i: the bins' covariance counts (a path that adds to several bins, as with
// expected-value exits, makes them positively correlated; one that leaves through one bin,
// negatively). Without batches the bins are taken as independent (Σ k_i² g_i² c_i²).
RelativeError relativeError(const std::vector<ErrorBin>& bins,
                            const std::vector<double>& batchFraction = {});

// The measure of [lo, hi] within [a, b] on the log axis: ln(min(hi, b) / max(lo, a)), 0 when
// they do not overlap (lo may be 0).
double logOverlap(double lo, double hi, double a, double b);

// Nodes and weights of ∫_lo^hi f(r) r dr / ∫_lo^hi r dr ≈ Σ_k w_k f(r_k) (4-point Gauss–Legendre
// in r, the weights sum to 1): a model averaged over a radial bin as the reference tallies it.
struct BinNodes {
    std::array<double, 4> r{}, w{};
};
BinNodes areaAverageNodes(double lo, double hi);

// The noise correction above is a second-order expansion in c = s/R: good while c is small, not
// where a bin holds a handful of paths (c near 1, where 1/R̂ has a heavy tail). Radial bins
// noisier than this are merged with their neighbours (radialRelativeError).
inline constexpr double kRelErrMaxBinNoise = 0.1;

// rel_err of a radial profile: bins [edges[i], edges[i+1]) with reference means `ref` and standard
// errors `refSe` (and batch means `refBatches`, may be empty), and the model's bin averages
// `model`, over r ∈ [from, to] (the same units). A
// bin without reference paths or with c > kRelErrMaxBinNoise (far out, or a short run) is merged
// with the next ones (at the end of the range, with the previous group) into one bin whose means
// are area-weighted, so the measure stays defined and its noise correction holds; the measure
// then resolves the relative error there only as finely as the reference does. Only a range
// without any paths is a problem.
RelativeError radialRelativeError(const std::vector<double>& edges, const std::vector<double>& ref,
                                  const std::vector<double>& refSe,
                                  const std::vector<double>& model, double from, double to,
                                  const BatchMeans& refBatches = {});

// Several radial profiles on the same bin edges, each with its own weight (e.g. the θs sectors and
// exit cells of a BSSRDF slice, weighted by Δθs and solid angle): bins are merged within each
// profile as above, then one rel_err is taken over all of them.
struct RadialSeries {
    std::vector<double> ref, refSe, model;
    double weight = 1;
    BatchMeans batches; // of `ref` (all series of one reference share the fractions); may be empty
};
RelativeError radialRelativeError(const std::vector<double>& edges,
                                  const std::vector<RadialSeries>& series, double from, double to);

} // namespace core
