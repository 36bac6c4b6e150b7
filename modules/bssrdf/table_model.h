// bssrdf/table_model: models made from data instead of GLSL — a `::begin table` section that
// names a measured or externally computed radial profile (CSV `r_mm,R,G,B`, thesis 3.1.1) or
// path-traced tables (`.bwtable`, pathtrace/bssrdf_table.h). The data are embedded in a
// generated `shader` section as GLSL constant arrays, so a table model works everywhere a
// model does: pencil plot, renderer, lit spheres. Section syntax (one directive;
// `#` comments):
//   profile FILE.csv                      values in the model convention: R_d per unit power
//                                         entering, 1/mm² (materials/README.md)
//   estimate FILE.bwtable [G.bwtable B.bwtable]   one table for all channels, or one per channel
// Radial tables (θi = 0 only, one θs bin, one direction cell) and CSV profiles give a radial
// model: sorted radii and RGB values, linear interpolation in r, 0 beyond the last radius; a
// table's R is divided by 1 − R_sp (MCML → per power entering), at most kMaxTableRadii radii.
// Any other table (several θs bins, direction cells or incidence angles, or an oblique angle
// only) gives a non-radial model that depends on Wi and Wo: bssrdf/oblique_table.h defines its
// conversion S → Bssrdf and its interpolation; its attributes follow from the data.
// Paths are relative to the model file. Every problem is a core::Error naming the model file
// and section line, or the data file and its line.
#pragma once

#include "bssrdf/bssrdf.h"

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace bssrdf {

// Most radii a table model embeds (a GLSL constant array).
constexpr size_t kMaxTableRadii = 4096;

struct RadialTable {
    std::vector<double> r;                  // mm, strictly increasing, >= 0
    std::vector<std::array<double, 3>> rgb; // R_d per unit power entering, 1/mm², >= 0
};

// Reads a CSV radial profile: '#' lines and blank lines anywhere, a header `r_mm,R,G,B`, then
// rows of four finite numbers (r strictly increasing and >= 0, values >= 0), 2 to
// kMaxTableRadii rows. core::Error(displayName, line, message).
RadialTable readProfileCsv(const std::filesystem::path& file, const std::string& displayName);

// The GLSL of a radial table model: constant arrays and Bssrdf() interpolating in r.
std::string radialTableGlsl(const RadialTable& t);

// Expands m.table (when present) into m.shader, filling m.dataFiles and m.tableMedia.
// `modelDir` resolves the file names. Called by loadModel.
void expandTable(Model& m, const std::filesystem::path& modelDir);

} // namespace bssrdf
