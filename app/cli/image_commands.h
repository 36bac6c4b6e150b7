// `bssrdf-workbench sphere` / `mesh`: the path-traced lit sphere or lit mesh image (pathtrace::
// traceLitSphere / LitMesh::trace, thesis 3.2 on the setup of 3.5 / 3.6.2, pathtrace/
// lit_sphere.h) written as an OpenEXR file: channels R, G, B = radiant exitance per unit
// irradiance, varR, varG, varB = variance of the mean (pathtrace/image_io.h). No display or GL
// needed. Progress on stderr; a one-line summary on stdout.
#pragma once

#include <cstdint>
#include <string>

namespace app {

// Defaults are set by main.cpp from the GUI's LitSphereSettings and pathtrace::Medium{}, so
// `sphere` traces what the Lit spheres panel shows by default.
struct ImageArgs {
    double sigmaA[3] = {}, sigmaS[3] = {}; // 1/mm, RGB (app::parseRgb replicates a scalar)
    double g = 0, eta = 0;
    double radiusMm = 0;        // sphere radius; meshes: the longest axis is 2·radius mm
    double light[3] = {};       // towards the light (normalised on use)
    int width = 0, height = 0;  // pixels
    uint64_t spp = 0, seed = 0; // paths = spp × pixels covered by the object
    int threads = 0;            // 0: all hardware threads
    std::string mesh;           // OBJ file (runMeshCli)
    std::string out;            // EXR file to write (required)
};

// Validate (core::Error naming the argument or file: σ, g, η via pathtrace::validate per
// channel; 1 <= width, height <= 16384; 1 <= spp <= 10^7; light finite and non-zero; radius
// finite > 0; threads >= 0; --out given; the mesh missing, malformed, open, inconsistently wound
// or inward), trace, write the EXR, print the summary. Return 0, or kEnergyCheckFailed
// (common/exit_codes.h) when a channel fails its energy check (pathtrace::energyProblem).
int runSphereCli(const ImageArgs& a);
int runMeshCli(const ImageArgs& a);

} // namespace app
