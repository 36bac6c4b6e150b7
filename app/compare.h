// `bssrdf-workbench compare`: every model × preset × channel scored against the path-traced
// reference (the scoreboard). At normal incidence (θi = 0) for every number below:
//   l_d       = 1/√(3σa(σa + σs(1 − g)))                 (the channel's diffuse mean free path)
//   R_ref(r)  = R_d(r)/(1 − R_sp)                         (per unit power entering, as plotted)
//   rel_l2    = √(∫(R_m − R_ref)² r dr / ∫R_ref² r dr) over r ∈ [0.1 l_d, 4 l_d], the integrals
//               as sums over the reference's radial bins (bin centre r_i, width Δr)
//   rel_l2_se = the standard error of rel_l2 from the reference's bin standard errors s_i by the
//               delta method: ∂rel/∂R_ref,i = rel/2 · (−2(R_m,i − R_ref,i)/N − 2R_ref,i/D) r_i Δr
//               with N, D the two sums, so se = √Σ(∂rel/∂R_ref,i · s_i)²
//   ratio_1ld, ratio_4ld = R_m/R_ref at the bin holding 1 l_d and 4 l_d (with their se)
//   total_ratio = 2π∫₀^∞ R_m r dr / (R_d,total/(1 − R_sp)), the model's integral on 2048 points
//               in ln r up to 60 l_d
//   r_err5_ld = the first radius (in l_d, from 0.1 l_d) where |R_m − R_ref| exceeds both 5 % of
//               R_ref and 2 standard errors (noise is not an error); absent when none does
// Models whose rel_l2 differ from the best of their (preset, channel) by less than
// 2√(se_a² + se_b²) share its rank ("tie"). The reference is cached on disk by medium and
// settings (BSSRDF_WORKBENCH_CACHE, else ~/.cache/bssrdf-workbench/reference), so a second run
// costs only the models. Outputs: DIR/scores.json (schema below), DIR/report.md and
// DIR/report.html (one self-contained page, cells coloured by rel_l2).
//
// scores.json = {"schema": "bssrdf-workbench-scores", "version": 1, "theta_i": [0],
//   "paths": P, "rows": [{"model", "preset", "channel": "R"|"G"|"B", "theta_i", "ld_mm",
//   "rel_l2", "rel_l2_se", "ratio_1ld", "ratio_1ld_se", "ratio_4ld", "ratio_4ld_se",
//   "total_ratio", "total_ratio_se", "r_err5_ld" (or null), "rank", "tie"}],
//   "skipped": [{"preset", "channel", "reason"}]}   (channels with σa = 0 have no l_d)
//
// At θi > 0 (--theta-i) the rows are scored against the seed 001 estimate of the whole BSSRDF,
// over the plane and the exit directions (compare_oblique.h); such rows add "rel_l2_dir" and
// "rel_l2_dir_se" (null at θi = 0). The report adds per preset and channel the pencil plot of
// every model with the reference band, the ratio to the reference against r, and at θi > 0
// polar heatmaps of the relative difference (compare_report.cpp), drawn headless by the
// panels' own plot code.
//
// --baseline FILE --fail-if-worse PCT: exit 1 when a row's rel_l2 grew by more than PCT % over
// the baseline's same (model, preset, channel, theta_i) and by more than 3 standard errors of
// the difference, 3√(se² + se_baseline²).
#pragma once

#include "bssrdf/program_library.h"
#include "capture/scores.h"
#include "gl/gl.h"
#include "pathtrace/bssrdf_estimate.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace app {

// A score as the reports print it: `digits` significant digits, "—" when not finite.
std::string formatScore(double v, int digits = 4);

struct CompareArgs {
    std::vector<std::string> models;   // default: every materials/*.bssrdf
    std::vector<std::string> presets;  // default: every preset of presets.json
    std::vector<double> thetaI{0.0};   // incidence angles, degrees in [0, 90)
    bool plots = true;                 // PNG plots in the reports
    uint64_t paths = 200000;           // per preset and channel
    std::string baseline;              // an earlier scores.json
    std::optional<double> failIfWorse; // percent
    std::string out;                   // output folder
};

using ScoreRow = capture::ScoreRow;

// What the report draws besides the table (compare_report.cpp).
struct ProfileCurves { // θi = 0, one preset and channel
    std::string preset;
    int channel = 0;
    double ld = 0;
    std::vector<double> r, ref, refSe; // R_d/(1 − R_sp) and its standard error at bin centres
    std::vector<std::pair<std::string, std::vector<double>>> models; // name, R at r
};
struct SliceMaps { // θi > 0, one preset, channel and angle
    std::string preset;
    int channel = 0;
    double thetaI = 0, ld = 0;
    pathtrace::BssrdfBins bins;
    std::vector<double> refR, refSe;                                 // per spatial bin
    std::vector<std::pair<std::string, std::vector<double>>> models; // name, R per bin
};
struct CompareReport {
    uint64_t paths = 0;
    std::vector<double> thetaI;
    std::vector<ScoreRow> rows;
    std::vector<ProfileCurves> profiles;
    std::vector<SliceMaps> slices;
};
// report.md and report.html in `dir` (and the pictures in dir/plots when `pictures`).
void writeReports(const std::filesystem::path& dir, const CompareReport& r, bool pictures);

// Where references are cached: $BSSRDF_WORKBENCH_CACHE/reference, else
// $XDG_CACHE_HOME/bssrdf-workbench/reference, else ~/.cache/bssrdf-workbench/reference.
std::filesystem::path compareCacheDir();

// Scores from one model's profile against one reference channel (exposed for tests):
// rMid, rd, rdSe: the reference's bins; specular R_sp; totalRd, totalRdSe; model: R_m at rMid;
// modelTotal: 2π∫R_m r dr.
ScoreRow scoreAgainstReference(const std::vector<double>& rMid, const std::vector<double>& rd,
                               const std::vector<double>& rdSe, double specular, double totalRd,
                               double totalRdSe, double ldMm, const std::vector<double>& model,
                               double modelTotal);
// 2π∫₀^∞ R r dr of one channel of a model (the pencil program), on 2048 points in ln r from
// 1e-6 l_d to 60 l_d.
double modelTotalRd(GLuint program, const bssrdf::ModelEntry& e, const bssrdf::Builtins& b,
                    double ldMm, int channel);
// Ranks and ties within each (preset, channel, theta_i).
void rankRows(std::vector<ScoreRow>& rows);

int runCompareCli(const std::filesystem::path& root, const CompareArgs& a);

} // namespace app
