// MCML output files (`.mco`, MCML 1.2.2: Wang, Jacques & Zheng 1995), read and written byte for
// byte as MCML's mcmlio.c writes them (WriteResult: version line, time line, InParm, RAT, A_l,
// A_z, Rd_r, Rd_a, Tt_r, Tt_a, A_rz, Rd_ra, Tt_ra; printf formats %G, %-14.6G, %12.4G, %12.4E,
// 2D arrays r-outer with a line break after every 5th value). Units are MCML's: cm, 1/cm,
// Rd_r in 1/cm². MCML's last radial, depth and angle bins collect everything beyond the grid
// (overflow bins); the radial bin centres are (ir + 0.5) dr. Written by hand: no packaged library
// reads this format.
//   - readMco: any MCML 1.x text output (also CRLF); every error names the file and line.
//   - formatMco: the text MCML writes for the same numbers (a file read and formatted again is
//     identical to the original).
//   - mcoFromSlab: our semi-infinite slab reference as an .mco (one layer of thickness 1E+08 cm,
//     na = nz = 1; Tt = 0; A_rz is not tallied by the slab tracer and is written as 0, which the
//     time line says).
//   - slabFromMco: an .mco's diffuse reflectance R_d(r) in our units (mm, 1/mm²) without the
//     overflow bin, with standard errors from two independent runs when a second file is given.
#pragma once

#include "pathtrace/pathtrace.h"

#include <filesystem>
#include <string>
#include <vector>

namespace pathtrace {

struct McoLayer {
    double n = 1, mua = 0, mus = 0, g = 0, d = 0; // 1/cm, 1/cm, cm
};

struct McoFile {
    std::string version = "A1";
    std::string timeLine; // the "# User time: …" line as written (without its newline)
    std::string outName;  // the output file name MCML recorded
    long long photons = 0;
    double dz = 0, dr = 0; // cm
    int nz = 0, nr = 0, na = 0;
    double nAbove = 1, nBelow = 1;
    std::vector<McoLayer> layers;
    double specular = 0, diffuse = 0, absorbed = 0, transmittance = 0;
    std::vector<double> aLayer, aZ, rdR, rdA, ttR, ttA; // 1D arrays (A_l has one per layer)
    std::vector<double> aRz, rdRa, ttRa;                // 2D arrays, r outer
};

// Throws core::Error(file, line, msg) on a missing section, a value that is not a number, a
// count that does not match nz/nr/na or the layers, or a header it cannot read.
McoFile readMco(const std::filesystem::path& file);
McoFile parseMco(const std::string& text, const std::string& displayName);
std::string formatMco(const McoFile& m);

// The slab reference `r` of medium `m` traced with `s` as an .mco (see above).
McoFile mcoFromSlab(const Medium& m, const SlabSettings& s, const SlabResult& r,
                    const std::string& outName);

// The medium an .mco describes when it is one layer the slab tracer can stand for (thick enough
// to be semi-infinite, d > 1000 / (mua + mus)·, and the same n above as outside: η = n_layer /
// n_above), in 1/mm; throws core::Error naming the file otherwise.
Medium mediumOfMco(const McoFile& m, const std::string& displayName);
// R_d(r) of `a` (and `b`, a second independent run of the same input: averaged, with the
// standard error |a − b|/2 per bin and for the total) as a SlabResult in mm and 1/mm², the
// overflow bin left out. Without `b` the standard errors are 0.
SlabResult slabFromMco(const McoFile& a, const McoFile* b = nullptr);

} // namespace pathtrace
