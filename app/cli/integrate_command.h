// `bssrdf-workbench integrate`: the BSSRDF-integrated lit sphere or lit mesh (integrate/
// integrate_command.h) by uniform area sampling or disk probe-ray importance sampling (King et al.
// 2013), written as an OpenEXR file with channels R, G, B (radiant exitance per unit irradiance)
// and varR, varG, varB (variance of the mean), as `sphere` and `mesh` write the path-traced
// ones, so the two compare pixel by pixel.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace app {

struct IntegrateArgs {
    std::string mesh;               // OBJ (or --sphere)
    std::optional<double> sphereMm; // sphere radius in mm (or --mesh)
    std::optional<double> radiusMm; // mesh: half its longest axis in mm
    std::string model, preset, sigmaA, sigmaS;
    std::optional<double> g, eta;
    std::string sampling, axes; // enum names of integrate::Sampling / sampling::AxisScheme
    uint64_t spp = 0;           // samples per pixel (required)
    std::string light, size;    // x,y,z and WxH, defaults from LitSphereSettings
    uint64_t seed = 1;
    double energyLoss = 0; // eps of R_m, default integrate::Settings
    std::string out;
};

// The options (defaults from the Lit spheres panel's settings and integrate::Settings).
void addIntegrateOptions(CLI::App* cmd, IntegrateArgs& a);
// Validates (core::Error naming the argument or file), integrates with a progress line, writes
// the EXR; Ctrl-C writes the samples done so far marked partial and returns kInterrupted.
int runIntegrateCli(const std::filesystem::path& root, const IntegrateArgs& a);

} // namespace app
