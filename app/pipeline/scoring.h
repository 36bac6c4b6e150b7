// The scores of a model's pencil-beam profile against the path-traced reference, shared by
// `compare` (cli/compare_command.h) and the Scoreboard stage (scoreboard_stage.h). At normal
// incidence (θi = 0) for every number below:
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
// 2√(se_a² + se_b²) share its rank ("tie").
// At θi > 0 the rows are scored against the seed 001 estimate of the whole BSSRDF
// (scoring_oblique.h).
#pragma once

#include "bssrdf/program_library.h"
#include "capture/scores.h"
#include "gl/gl.h"

#include <filesystem>
#include <string>
#include <vector>

namespace app {

// A score as the reports print it: `digits` significant digits, "—" when not finite.
std::string formatScore(double v, int digits = 4);

using ScoreRow = capture::ScoreRow;

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

} // namespace app
