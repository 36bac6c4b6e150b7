// The scoreboard at oblique incidence (θi > 0, `compare --theta-i`): the reference is the whole
// BSSRDF of the slab estimated by the random walk with connections (Dal Corso & Frisvad 2018,
// pathtrace/bssrdf_estimate.h), each model is evaluated on the same bins (slice_model.h), and
//   bins      r in [0.1 l_d, 4 l_d) in kObliqueRBins rings of equal steps in ln r ×
//             kObliqueThetaSBins θs sectors over [0°, 180°] (both mirror halves) ×
//             kObliqueDirCos · kObliquePhi exit cells of equal solid angle; A_b the area of spatial
//             bin b, Ω_c = ∫cell cos θo dω
//   rel_err   = the RMS relative error of R over (ln r, θs) (core/relative_error.h: each θs
//               sector a radial series with bin weights ln(r_hi/r_lo), its noisy rings merged;
//               the model averaged over each bin as slice_model.h does)
//   rel_err_dir = the same of S over (ln r, θs) and the exit directions (a series per sector and
//               exit cell, weighted by Ω_c)
//   each with its standard error from the bins' standard errors (bins treated as independent: the
//   connections of one path reach every bin, so this is a first-order figure)
//   ratio_1ld, ratio_4ld = ring power Σ_θs R A of the model over the reference's, at the ring
//               whose centre is nearest 1 l_d and 4 l_d
//   total_ratio = Σ_b R_m A_b / Σ_b R_ref A_b   (the power leaving the annulus, not the whole
//               surface as at θi = 0)
//   r_err5_ld = the centre (in l_d) of the first ring whose ring power is off by more than 5 %
//               and more than 2 standard errors.
// R and S are per incident photon, specular reflection excluded, as the estimate counts them;
// slice_model.h gives a model's R and S in the same units (Fresnel transmissions included).
#pragma once

#include "capture/scores.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pipeline/slice_model.h"

#include <string>

namespace app {

inline constexpr int kObliqueRBins = 16;
inline constexpr int kObliqueThetaSBins = 6;
inline constexpr int kObliqueDirCos = 2, kObliquePhi = 6;

// The estimate of one medium at one θi for the scoreboard (bins above, connections, seed 1).
pathtrace::EstimateSettings obliqueSettings(double ldMm, double thetaIDeg, uint64_t paths);

// The reference slice from the disk cache or estimated (and cached); throws core::Error when the
// estimate fails its own energy check. `what` names it in progress lines and messages.
pathtrace::BssrdfSlice obliqueReference(const pathtrace::Medium& m,
                                        const pathtrace::EstimateSettings& s,
                                        const std::string& what, bool& fromCache);

// A model's scores against the reference slice on bins `b` (exposed for tests).
capture::ScoreRow scoreSlice(const pathtrace::BssrdfBins& b, const pathtrace::BssrdfSlice& ref,
                             const ModelSlice& model, double ldMm);

} // namespace app
