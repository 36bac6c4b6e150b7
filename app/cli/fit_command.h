// `bssrdf-workbench fit` (fit_command.cpp): a model's declared parameters fitted to the
// path-traced reference over presets, and (fit_sweep.cpp) the same fit repeated at each albedo
// of a sweep, which turns a parameter into a table over albedo (a function fit, e.g.
// Christensen & Burley's s(A)).
#pragma once

#include "pipeline/fitting.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace app {

class Workbench;

struct FitArgs {
    std::string model, out;
    std::vector<std::string> params, presets{"Marble"}, channels{"R", "G", "B"};
    std::vector<std::string> set;    // NAME=VALUE held fixed (setParameters)
    std::vector<double> thetaI{0.0}; // 0: the radial profile; > 0: the whole BSSRDF's slice
    uint64_t paths = 1000000;
    int maxEvaluations = FitSettings{}.maxEvaluations;
    double xtolRel = FitSettings{}.xtolRel;
    bool uncertainty = true;
    bool plots = true; // before/after pictures in the report
    // --albedo-sweep: reduced albedos α′ = σ′s/σ′t of a medium with σ′t = 1/mm, g and η below
    std::vector<double> albedoSweep;
    double sweepG = material::MaterialParams{}.g, sweepEta = material::MaterialParams{}.eta;
    std::vector<std::string> published; // CSV files of published curves (A, parameter)
};

// One medium of the targets: a preset's (or a sweep point's) medium and the channels to fit.
struct FitMedium {
    std::string name;
    material::MaterialParams params;
    std::vector<int> channels;
};

// The targets of every medium × channel × θi against references of `paths` paths with `seed`
// (cached, pipeline/scoring.h); `what` ends their progress lines.
std::vector<FitTarget> makeTargets(const std::vector<FitMedium>& media,
                                   const std::vector<double>& thetaI, uint64_t paths, uint64_t seed,
                                   const std::string& what);

// One progress line on stderr, rewritten at most four times a second.
std::function<void(int, double)> fitProgress(const std::string& what);

// The fit and its uncertainty from refits on two independent half references (seeds 2 and 3):
// each half fit scatters √2 times the full one, their difference 2 times, so the statistical
// part is |x_A − x_B| / 2. rel_err weights each bin by 1/R_ref², and a noisy R_ref in a
// denominator biases the fit by an amount ∝ se² ∝ 1/paths: the halves carry twice the full
// fit's bias, so x_full − (x_A + x_B)/2 estimates the full fit's bias. σ = √(stat² + bias²).
inline constexpr const char* kUncertaintyNote =
    "sqrt(stat^2 + bias^2) with stat = |x_A - x_B| / 2 from fits to two independent half "
    "references (seeds 2 and 3) and bias = x - (x_A + x_B) / 2 (the fit's shift with the "
    "reference's size, which halves when the paths double)";
struct FitOutcome {
    FitResult result;
    std::vector<double> sigma;        // per variable, NaN when not computed
    std::vector<double> halfA, halfB; // the two half fits' values (empty when not computed)
    std::vector<FitTarget> targets;   // the full references the fit was made on
};
FitOutcome fitWithUncertainty(const bssrdf::ModelEntry& e, const std::vector<FitVariable>& vars,
                              const std::vector<FitMedium>& media, const FitArgs& a,
                              const FitSettings& s, const std::string& what);

// The sweep (fit_sweep.cpp): fits at each albedo of a.albedoSweep, each from the previous
// albedo's result; writes sweep.csv, fit.json and report.md with the fitted values against the
// reference's total diffuse reflectance A (and a.published curves beside them). e's values are
// the start and are left at the last fit.
int runFitSweep(bssrdf::ModelEntry& e, const std::vector<FitVariable>& vars, const FitArgs& a,
                const FitSettings& s);

} // namespace app
