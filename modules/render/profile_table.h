// render/profile_table: the 1D profile table of a radial BSSRDF model (attribute `radial`: it
// depends on r = |Xo − Xi| only), evaluated once per model/parameter/material change and looked
// up by shaders/octree_render.comp instead of calling Bssrdf() per evaluation.
//   Values: R(r) = Bssrdf(0, n, (r, 0, 0), n), n = (0, 0, 1), r in mm (the pencil-profile
//   consumer shaders/pencil_profile.comp, i.e. bssrdf::evaluateProfile).
//   Grid (K = kProfileEntries): r_k = rMax·(k/(K−1))², dense near 0 where the profile varies
//   most. Lookup (common/octree_profile.glsl, lookupProfile below, same float arithmetic):
//     t = sqrt(r/rMax)·(K−1); t >= K−1 (r >= rMax) → 0; else linear between entries
//     i = floor(t) and i + 1 with f = t − i.
//   rMax: the profile is probed at r = 0 and at r_j = 1e-4·10^(j/32) mm, j = 0 … 256 (to
//   10^4 mm). Per channel the reference is R_c(0) (the largest finite probe value if R_c(0) is
//   not finite and positive); rMax is the first probe radius beyond which every channel stays
//   at or below kProfileDecay·reference (dropping the tail changes M by less than that
//   fraction of the peak) and beyond which every channel holds at most kProfileEnergyTail of its
//   energy 2π∫R r dr on the probes (a profile singular at 0, R ~ 1/r as normalized diffusion's,
//   falls 10^7 below its peak long before its energy converges). rMax is then capped at `capMm` (>
//   0: the largest distance that can occur, the diagonal of the scene's bounding box in mm), so
//   that the K entries cover only distances that exist. Accuracy (tests/render: dipole and better
//   dipole, skin-like σ, 50 mm bunny): |table − direct| < 1e-3 relative (measured: 2.2e-5 at worst)
//   wherever R_c(r) >= 1e-6·R_c(0), the region that matters, against Bssrdf() itself; whole renders
//   differ by < 1e-5 relative per pixel.
#pragma once

#include "bssrdf/program.h"

#include <glm/vec3.hpp>

#include <vector>

namespace render {

inline constexpr int kProfileEntries = 4096;
inline constexpr double kProfileDecay = 1e-7;
inline constexpr double kProfileEnergyTail = 1e-6;

struct ProfileTable {
    float rMax = 0;                // mm
    std::vector<glm::vec3> values; // R(r_k), k = 0 … K−1
};

// r_k in mm (computed in double, rounded to float).
float profileRadius(float rMax, int k, int count);
// The shader's lookup on the CPU (same float operations).
glm::vec3 lookupProfile(const ProfileTable& t, float r);
// rMax from probe radii (ascending, probe[0] = 0) and values (see above); capMm <= 0: no cap.
float chooseProfileRadius(const std::vector<double>& radii, const std::vector<glm::dvec3>& values,
                          double capMm);
// Probes, chooses rMax and fills the table. `pencilProgram` from
// bssrdf::buildModelProgram(m, "pencil_profile.comp", sources).
ProfileTable buildProfileTable(GLuint pencilProgram, const bssrdf::Model& m,
                               const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                               double capMm);

} // namespace render
