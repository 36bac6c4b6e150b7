// Artist parameters → σ: the published mappings from a surface albedo A and a length d per
// channel (with g and η) to σa, σs, side by side in one place so that the parameterization lab
// (params_lab.h) can measure what each one really gives. Each mapping names its source and what
// its length means:
//   rdr_ld_dipole, rdr_ld_better_dipole   Jensen & Buhler 2002 (thesis 3.1.1, 3.4): α′ from the
//       model's total diffuse reflectance R_dr(α′) = A (materials/dipole.bssrdf: Jensen et al.
//       2001; better_dipole.bssrdf: d'Eon 2012), d = l_d, σ′t = 1/(l_d √(3(1 − α′))). The
//       workbench's own R_dr / l_d parametrization.
//   pbd_mfp   pbrt-v4's SubsurfaceFromDiffuse idea: the single-scattering albedo whose photon
//       beam diffusion R_dr (materials/photon_beam_diffusion.bssrdf, Habel et al. 2013) is A,
//       d = the mean free path 1/σt.
//   rdr_mfp_better_dipole   appleseed's dipoles: the albedo whose better-dipole R_dr is A, used
//       as the single-scattering albedo, d = 1/σt, g ignored.
//   van_de_hulst   the index-matched half space's albedo in closed form (van de Hulst 1980, as
//       d'Eon's similarity theory uses it): A = (1 − s)(1 − 0.139 s)/(1 + 1.17 s),
//       s = √((1 − α)/(1 − g α)), inverted by bisection; d = 1/σt; η is ignored (Blender
//       Cycles' Random Walk, appleseed's random walk).
//   exp_albedo_fit   α = 1 − exp(A(−5.09406 + A(2.61188 − 4.31805 A))), d = 1/σt (appleseed's
//       directional dipole; Cycles' random walk before 2021 with another σt).
//   cycles_anisotropic_fit   Cycles' Random Walk (Legacy) and Skin: α from A through six
//       degree-7 fits in g (Chiang et al. 2016; Wrenninge et al. 2017), d = 1/σ′t.
// The sources, with the files and commits they were read from, are in paramMappings(). Not
// here: Christensen & Burley's s(A), which scales a profile, not σ (their fit is
// normalized_diffusion.bssrdf, refitted in docs/christensen_burley.md).
#pragma once

#include "bssrdf/program_library.h"
#include "material/material.h"

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace app {

struct ParamMapping {
    std::string id;     // "rdr_ld_dipole"
    std::string name;   // "R_dr / l_d, classical dipole"
    std::string source; // the publication and, for a renderer's, the file it was read from
    std::string length; // what d means, in words
    std::string model;  // the model file whose DiffuseReflectance it inverts ("" for none)
};
const std::vector<ParamMapping>& paramMappings();
// The mapping with `id`, or nullptr.
const ParamMapping* findParamMapping(const std::string& id);

// σ from albedo A ∈ (0, 1) and length d > 0 (mm) per channel, with g and η (kept in the
// result). `model` is the loaded entry of mapping.model (nullptr for a closed form). Throws
// core::Error naming the mapping and channel when A or d is out of range or A is not reached
// (e.g. above the model's R_dr(1)).
material::MaterialParams mapArtistParams(const ParamMapping& mapping, const glm::dvec3& albedo,
                                         const glm::dvec3& d, double g, double eta,
                                         const bssrdf::ModelEntry* model);

} // namespace app
