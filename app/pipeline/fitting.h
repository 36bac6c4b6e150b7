// Fitting a model's declared parameters to the path-traced reference (`fit`): the free
// parameters (each float, or each component of a colour, within its declared range or a narrower
// one) minimise the mean over the targets (preset × channel × θi) of rel_err²
// (core/relative_error.h; unclamped, so the objective stays smooth where the error is within the
// reference's noise) of the model's pencil-beam profile at normal incidence against the slab
// reference on its bins, the model averaged over each bin as the scores do (pipeline/scoring.h).
// The optimizer is NLopt's BOBYQA (Powell 2009: bounded, derivative-free, quadratic models of the
// objective), started from the best of the model's current values and a coarse scan of the
// ranges (8 Halton points per variable, log-spaced along ranges spanning decades), so that a
// start in another valley of the objective does not decide the result; it stops at a relative
// change of the parameters below `xtolRel` or after `maxEvaluations`. A model that gives NaN, Inf
// or negative values at some parameters scores +∞ there (listed in `problems` with the values) and
// the search goes on from the best point. Cancel keeps the best point so far. The same targets and
// start give the same result (BOBYQA is deterministic).
#pragma once

#include "bssrdf/program_library.h"
#include "material/material.h"
#include "pathtrace/bssrdf_estimate.h"

#include <atomic>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace app {

// One target: a preset's channel with its slab reference (per unit power entering, as the
// pencil plot draws it) on bins [edges[i], edges[i+1]); or, at thetaI > 0, the estimate of the
// whole BSSRDF on the slice's bins (pipeline/scoring_oblique.h), where the model's rel_err over
// the plane (ln r, θs) is the term.
struct FitTarget {
    std::string preset;
    int channel = 0;
    double ldMm = 0;
    material::MaterialParams params; // the medium (the model's builtins)
    std::vector<double> edges, ref, refSe;
    core::BatchMeans refBatches;           // ref's batch means (may be empty)
    double totalRd = NAN, totalRdSe = NAN; // θi = 0: 2π∫R_ref r dr per unit power entering
    double thetaI = 0;
    pathtrace::BssrdfBins bins;   // thetaI > 0
    pathtrace::BssrdfSlice slice; // thetaI > 0: the reference
};

// One free variable: a float parameter, one component of a colour ("Albedo.g"), or a quantity
// of the medium the model is evaluated with (the reference stays the preset's own medium):
// kSigmaScale multiplies σa and σs, kMediumG replaces g.
inline constexpr const char* kSigmaScale = "medium.sigma_scale";
inline constexpr const char* kMediumG = "medium.g";
struct FitVariable {
    std::string param; // the parameter's name (or kSigmaScale, kMediumG)
    int component = 0; // 0 for a float, 0..2 for a colour's r, g, b
    std::string label; // "Multiplier", "Albedo.g"
    double lo = 0, hi = 1;
    bool medium = false; // kSigmaScale or kMediumG
};

// The free variables of `names` (NAME or NAME=LO,HI with a range inside the declared one; the
// medium's kSigmaScale in [0.1, 10] and kMediumG in [-0.95, 0.95] by default), in order. Throws
// core::Error("--params", …) naming a parameter the model does not declare, a bool, a range
// outside the declared one or empty, or a name given twice.
std::vector<FitVariable> fitVariables(const bssrdf::Model& m,
                                      const std::vector<std::string>& names);

// Sets fixed parameter values from `specs` (NAME=V, or NAME=R,G,B for a colour; a bool takes
// 0 or 1) into `values`, before a fit starts (`fit --set`). Throws core::Error("--set", …)
// naming a parameter the model does not declare, a value that is not a number or lies outside
// the declared range (with the declaration's line).
void setParameters(const bssrdf::Model& m, const std::vector<std::string>& specs,
                   bssrdf::ParamValues& values);

struct FitSettings {
    double xtolRel = 1e-4;
    int maxEvaluations = 300;
};

// The search itself, for any objective: `fn` maps the variables' values to the mean rel_err²
// (non-finite where the model is not finite, with `problem` saying why); BOBYQA from `start`
// (clamped into the ranges) with its restarts. progress and cancel as for fitModel.
using ObjectiveFn = std::function<double(const std::vector<double>& x, std::string& problem)>;
struct SearchResult {
    std::vector<double> start, best; // per variable
    double bestObjective = 0;        // mean rel_err² over the targets at `best`
    int evaluations = 0;
    std::string status;     // NLopt's stop reason, in words
    bool converged = false; // stopped by the parameter tolerance (not by the budget or a cancel)
    std::vector<std::string> problems; // parameter values where the model was not finite
};
SearchResult searchParameters(const std::vector<FitVariable>& vars,
                              const std::vector<double>& start, const FitSettings& s,
                              const ObjectiveFn& fn,
                              const std::function<void(int, double)>& progress = {},
                              const std::atomic<bool>* cancel = nullptr);
// The mean of rel_err² terms (NaN for none).
double meanSquared(const std::vector<double>& squared);

struct FitResult : SearchResult {
    double startObjective = 0;                   // mean rel_err² at the start
    std::vector<double> relErrStart, relErrBest; // per target
};

// Sets the variables' values into `values` (the model's parameter values; medium variables
// are left out).
void applyFit(const std::vector<FitVariable>& vars, const std::vector<double>& x,
              bssrdf::ParamValues& values);
// Sets the medium variables' values into `p`, the target's own medium `base` changed.
void applyMedium(const std::vector<FitVariable>& vars, const std::vector<double>& x,
                 const material::MaterialParams& base, material::MaterialParams& p);

// Runs the fit of entry `e` (its pencil program, its current values as the start). progress is
// called after each evaluation with (evaluations, best objective so far); cancel stops it.
FitResult fitModel(const bssrdf::ModelEntry& e, const std::vector<FitVariable>& vars,
                   const std::vector<FitTarget>& targets, const FitSettings& s,
                   const std::function<void(int, double)>& progress = {},
                   const std::atomic<bool>* cancel = nullptr);

// The model with `values` averaged over each bin of a radial target (θi = 0), channel t.channel;
// empty when it is not finite somewhere (`problem` says where).
std::vector<double> modelOnTarget(const bssrdf::ModelEntry& e, const bssrdf::ParamValues& values,
                                  const FitTarget& t, std::string* problem = nullptr);

// rel_err of the model with `values` on each target (NaN where the model is not finite or the
// target has no paths); `squared`, when given, receives the unclamped rel_err² of each (the
// objective's terms).
std::vector<double> relErrOnTargets(const bssrdf::ModelEntry& e, const bssrdf::ParamValues& values,
                                    const std::vector<FitTarget>& targets,
                                    std::string* problem = nullptr,
                                    std::vector<double>* squared = nullptr);

// The model file's text with the declared defaults of `values`' parameters set to them (a model
// that opens with the fitted values: its first line says so).
std::string withDefaults(const bssrdf::Model& m, const bssrdf::ParamValues& values,
                         const std::string& note);

} // namespace app
