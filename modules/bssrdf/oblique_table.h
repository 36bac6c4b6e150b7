// bssrdf/oblique_table: path-traced `.bwtable` tables (pathtrace/bssrdf_table.h) with several
// θs bins, several exit-direction cells or oblique incidence, as a non-radial table model.
//
// Conversion. A table holds, per incidence angle θi, spatial bin (r, θs) and exit cell, the
// MCML quantities (per incident photon, specular reflection at entry excluded): R in 1/mm² and
// S in 1/(mm²·sr) per projected solid angle, with Σ_cells S·Ω⊥_cell = R (one cell: S = R/π).
// The model convention (materials/README.md) is per unit power entering, without the exit
// Fresnel factor and the 1/π of a diffuse exit, which the consumers apply as T(θo)/π. A cell's
// value is
//   Bssrdf = π·(1 − F_dr,ext)·S_cell / ((1 − R_sp(θi))·T̄_cell),
//   T̄_cell = ∫_cell T(θo) cos θo dω / ∫_cell cos θo dω,   1 − F_dr,ext = (1/π)∫_H T cos θo dω,
// with T the exact unpolarised Fresnel transmittance between outside (index 1) and the medium
// (index η) at the outside angle θo (the same for both ways by reciprocity). So
// Bssrdf·T̄_cell/(π(1 − F_dr,ext)) is S per unit power entering, and a consumer's
// Bssrdf·T(θo)/π integrates over the cell to (1 − F_dr,ext)·S_cell·Ω⊥/(1 − R_sp): per cell
// the same relative factor 1 − F_dr,ext a diffusion model gets from T(θo)/π. T̄_cell > 0 in
// every cell (T > 0 at every outside angle below 90°), so nothing is divided by 0 at grazing.
// With one cell T̄ = 1 − F_dr,ext and Bssrdf = R/(1 − R_sp), the radial table's value.
//
// Evaluation (the generated GLSL, obliqueTableGlsl). Surface z = 0, normal +z. θi = the angle
// of Wi to +z (Wi below the surface counts as 90°); the beam travels along −Wi's tangential
// part. Xo − Xi in the beam frame gives r = |Xo − Xi| and θs = atan2(|y|, x) in [0°, 180°];
// on the y < 0 side the exit azimuth is mirrored (φo → −φo), as in the table. Wo gives the cell
// (cos θo = Wo.z clamped to [0, 1], φo from the beam axis). Interpolation: linear in r between
// bin centres (the first value below the first centre, 0 from the last centre on, as the
// radial table), linear in θs between sector centres (constant beyond the first and last
// centre), linear in θi between the table's angles (the first and last angle's values
// outside their range), nearest cell in direction. When Wi's tangential part is below 1e-6
// (normal incidence) the azimuth is undefined: the value is the mean over the θs bins, each
// taken at its sector centre with the exit azimuth measured from that bin's beam axis. When
// Wo's tangential part is below 1e-6 (exit along the normal, as the renderer and the lit
// sphere pass it) the exit azimuth is undefined: the mean over the sectors of its ring.
#pragma once

#include "pathtrace/bssrdf_table.h"

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace bssrdf {

// Most values (3 floats per entry: angles × radii × θs bins × cells × RGB) an oblique table
// model embeds as GLSL constants. Measured on Mesa llvmpipe (compile and link of one consumer
// program): 1024 entries 0.5–0.8 s, 4096 entries (this cap) 4–6 s, 8192 entries over 100 s.
constexpr size_t kMaxObliqueValues = 3 * 4096;

struct ObliqueTable {
    std::vector<double> thetaIDeg; // strictly increasing, in [0, 90)
    std::vector<double> r;         // radial bin centres, mm, increasing
    int thetaSBins = 1, dirCosBins = 1, dirPhiBins = 1;
    // Bssrdf values (model convention, 1/mm²), [((a·r.size() + ir)·thetaSBins + is)·cells + c].
    std::vector<std::array<double, 3>> value;

    int cells() const { return dirCosBins * dirPhiBins; }
    size_t index(size_t a, size_t ir, size_t is, size_t c) const {
        return ((a * r.size() + ir) * size_t(thetaSBins) + is) * size_t(cells()) + c;
    }
};

// Whether a table is radial: θi = 0 only, one θs bin, one direction cell.
bool isRadialTable(const pathtrace::BssrdfTable& t);

// 1 − F_dr,ext: the cosine-weighted hemispherical mean of T(θo) for relative index eta.
double diffuseTransmittance(double eta);
// T̄ of a ring of equal-solid-angle cells (cos θo in [ring/rings, (ring+1)/rings]).
double ringTransmittance(double eta, int ring, int rings);

// The tables of one model (one for all channels, or R G B) as an oblique table. core::Error
// naming the file (`names[i]`) when: the channels' bins, incidence angles or η differ; the
// incidence angles do not increase strictly; an angle has no paths; a value is not finite or
// negative; there are more than kMaxObliqueValues values.
ObliqueTable obliqueTable(const std::vector<pathtrace::BssrdfTable>& tables,
                          const std::vector<std::string>& names);

// The GLSL of an oblique table model: constant arrays and Bssrdf() as described above.
std::string obliqueTableGlsl(const ObliqueTable& t);

} // namespace bssrdf
