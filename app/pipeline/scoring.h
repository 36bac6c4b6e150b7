// The scores of a model's pencil-beam profile against the path-traced reference, shared by
// `compare` (cli/compare_command.h) and the Scoreboard stage (scoreboard_stage.h). At normal
// incidence (θi = 0) for every number below:
//   l_d       = 1/√(3σa(σa + σs(1 − g)))                 (the channel's diffuse mean free path)
//   R_ref(r)  = R_d(r)/(1 − R_sp)                         (per unit power entering, as plotted)
//   R_m,i     = the model averaged over the reference's radial bin i as the tally counts it,
//               ∫R_m r dr / ∫r dr (core::areaAverageNodes)
//   rel_err   = the RMS relative error over ln r ∈ [0.1 l_d, 4 l_d] with the reference's noise
//               removed, and rel_err_se its standard error (core/relative_error.h)
//   ratio_1ld, ratio_4ld = Σ R_m,i A_i / Σ R_ref,i A_i over the bins whose centres lie within
//               ±5 % of 1 l_d and of 4 l_d (A_i the bins' areas), with their se; NaN (null in
//               scores.json) when the reference has no paths there
//   total_ratio = 2π∫₀^∞ R_m r dr / (R_d,total/(1 − R_sp)), the model's integral on 2048 points
//               in ln r up to 60 l_d
//   r_err5_ld = the first radius (in l_d, from 0.1 l_d) where |R_m − R_ref| exceeds both 5 % of
//               R_ref and 2 standard errors (noise is not an error); absent when none does
// Models whose rel_err differ from the best of their (preset, channel) by less than
// 2√(se_a² + se_b²) share its rank ("tie").
// At θi > 0 the rows are scored against the seed 001 estimate of the whole BSSRDF
// (scoring_oblique.h).
#pragma once

#include "bssrdf/program_library.h"
#include "capture/scores.h"
#include "gl/gl.h"
#include "pathtrace/pathtrace.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace app {

// A score as the reports print it: `digits` significant digits, "—" when not finite.
std::string formatScore(double v, int digits = 4);

using ScoreRow = capture::ScoreRow;

// The slab reference of the scores at normal incidence: [0, 4.5 l_d) in 360 bins of 0.0125 l_d
// (fine in ln r at 0.1 l_d, the lower bound of rel_err), `paths` paths, seed 1.
pathtrace::SlabSettings scoringSlabSettings(double ldMm, uint64_t paths);
// The path-traced reference of one medium, from the disk cache (compareCacheDir) or traced and
// cached; `what` prefixes its progress line on stderr. Throws core::Error when the trace fails
// its own energy check.
// The batch means a reference cache entry holds ("batch_fraction", "batch_means"; an entry
// written before them has none: `out` empty, true). False when they are malformed or not `bins`
// long (the entry is then traced again). Throws nlohmann::json's exceptions on wrong types.
bool readBatchMeans(const nlohmann::json& j, size_t bins, core::BatchMeans& out);

pathtrace::SlabResult slabReference(const pathtrace::Medium& m, const pathtrace::SlabSettings& s,
                                    const std::string& what, bool& fromCache);

// Where references are cached: $BSSRDF_WORKBENCH_CACHE/reference, else
// $XDG_CACHE_HOME/bssrdf-workbench/reference, else ~/.cache/bssrdf-workbench/reference.
std::filesystem::path compareCacheDir();

// The edges of the uniform bins whose centres are rMid (the slab tracer's histogram).
std::vector<double> binEdges(const std::vector<double>& rMid);
// The model averaged over each bin [edges[i], edges[i+1]) (R_m,i above, every channel), from one
// run of the pencil program on 4 nodes per bin; r holds the bins' centres. A model that is NaN,
// Inf or negative at a node gives profileProblem's sentence in `problem`.
bssrdf::Profile binAverageProfile(GLuint program, const bssrdf::ModelEntry& e,
                                  const bssrdf::Builtins& b, const std::vector<double>& edges,
                                  std::string& problem);
// One channel of a profile.
std::vector<double> channelOf(const bssrdf::Profile& p, int channel);

// Scores from one model's profile against one reference channel (exposed for tests):
// edges, rd, rdSe: the reference's bins; specular R_sp; totalRd, totalRdSe; model: R_m,i (the
// model's bin averages); modelTotal: 2π∫R_m r dr; rdBatches: the reference's batch means (may be
// empty: rel_err then takes its bins as independent).
ScoreRow scoreAgainstReference(const std::vector<double>& edges, const std::vector<double>& rd,
                               const std::vector<double>& rdSe, double specular, double totalRd,
                               double totalRdSe, double ldMm, const std::vector<double>& model,
                               double modelTotal, const core::BatchMeans& rdBatches = {});
// 2π∫₀^∞ R r dr of one channel of a model (the pencil program), on 2048 points in ln r from
// 1e-6 l_d to 60 l_d.
double modelTotalRd(GLuint program, const bssrdf::ModelEntry& e, const bssrdf::Builtins& b,
                    double ldMm, int channel);
// Ranks and ties within each (preset, channel, theta_i); the rows ordered by preset, channel (R,
// G, B, then others), theta_i and rank.
void rankRows(std::vector<ScoreRow>& rows);

// One model over every row of a run (every preset, channel and angle it was scored on), ranked
// rows in: how often it ranks first (ties included), its median rel_err, and its row of the
// largest rel_err. What `compare` prints and its reports open with.
struct ModelSummary {
    std::string model;
    size_t rows = 0, first = 0; // rows scored, rows where it ranks 1
    double medianRelErr = 0;    // the middle rel_err (the mean of the two middle ones)
    ScoreRow worst;             // the row of the largest rel_err
};
// In order of median rel_err (then name).
std::vector<ModelSummary> summarizeModels(const std::vector<ScoreRow>& rows);

} // namespace app
