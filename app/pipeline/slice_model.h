// A model's BSSRDF on the bins of a path-traced estimate (pathtrace/bssrdf_estimate.h), so the
// BSSRDF slice panel compares radial and non-radial models with the same reference.
//
// Conventions. A model's Bssrdf(Xi, Wi, Xo, Wo) is R_d per unit power entering the medium
// without the Fresnel transmissions and the 1/π of a diffuse exit (materials/README.md). The
// estimate counts per incident photon, specular reflection excluded, and S per unit projected
// solid angle outside. The model's S is therefore
//     S_model(x, ω_o) = T₁₂(θi) · Bssrdf(0, ω_i, x, ω_o) · T₂₁(θo) / (π (1 − F_dr,ext)),
// T₁₂(θi) = 1 − R_Fresnel(cos θi, η) (the power that enters), T₂₁(θo) = 1 − R_Fresnel(cos θo, η)
// (the exact Fresnel transmittance of the exit direction, equal on both sides of the interface),
// and π(1 − F_dr,ext) = ∫ T₂₁ cos θo dω over the hemisphere, so that for a model that does not
// depend on ω_o the exitance is ∫ S_model cos θo dω = T₁₂ Bssrdf — the pencil plot's
// R_d/(1 − R_sp) undone. The incident direction (toward the light) is
// ω_i = (−sin θi, 0, cos θi): the beam travels toward +x, as in the estimate.
//
// Averages over a bin and a cell, as the estimate's are (midpoint rules):
//   spatial: nR radii uniform in r² (equal areas) × nθ angles in the θs sector, on both mirror
//            halves (y > 0 and y < 0; on the lower half the exit direction is mirrored too,
//            exactly as the estimate folds a point and its direction);
//   directional: nμ × nφ directions per cell, cos θo uniform (cells have equal solid angle),
//            weighted by cos θo; a model with `no_wo` is evaluated at ω_o = n once per spatial
//            sample and its cells get the factor ∫cell T₂₁ cos dω / ∫cell cos dω.
// R of a bin = Σ_cells S · ∫cell cos θo dω (the estimate's identity), i.e. T₁₂ · (bin average
// of Bssrdf) for a model without ω_o.
#pragma once

#include "bssrdf/program.h"
#include "pathtrace/bssrdf_estimate.h"

#include <vector>

namespace app {

struct SliceSampling {
    int radii = 4, angles = 3; // spatial sub-samples per bin (each on both mirror halves)
    int mu = 2, phi = 2;       // directional sub-samples per cell (models that read Wo)
};
// Fewer sub-samples for big tables: keeps bins × cells × samples ≤ `maxQueries` where it can.
SliceSampling sliceSampling(const pathtrace::BssrdfBins& b, bool readsWo,
                            size_t maxQueries = size_t(1) << 21);

// The queries of one slice, in the order modelSlice reads their values.
std::vector<bssrdf::Query> sliceQueries(const pathtrace::BssrdfBins& b, double thetaIDeg,
                                        bool readsWo, const SliceSampling& n);

struct ModelSlice {
    std::vector<double> R; // per spatial bin [ir·thetaSBins + it], 1/mm² per incident photon
    std::vector<double> S; // per [bin·dirBins + cell], 1/(mm²·sr); filled for every table
};
// `values`: one channel of Bssrdf() per query of sliceQueries(b, thetaIDeg, readsWo, n).
ModelSlice modelSlice(const pathtrace::BssrdfBins& b, double thetaIDeg, double eta, bool readsWo,
                      const SliceSampling& n, const std::vector<double>& values);

// π(1 − F_dr,ext(η)) = ∫ T₂₁ cos θo dω over the exit hemisphere, and the same over one cell.
double transmittedProjectedSolidAngle(double eta);
double cellTransmittedProjectedSolidAngle(const pathtrace::BssrdfBins& b, int cell, double eta);

} // namespace app
