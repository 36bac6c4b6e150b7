// `bssrdf-workbench profile` and `invert`: a model's pencil-beam profile as CSV, and σa, σs from
// R_dr / l_d (the material stage's inversion), on a headless GL context.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace app {

struct ProfileArgs {
    std::string model, preset, sigmaA, sigmaS, out;
    std::optional<double> g, eta, rMax;
    int samples = 512;
};
int runProfile(const std::filesystem::path& root, const ProfileArgs& a);

struct InvertArgs {
    std::string model, rdr, ld;
    std::optional<double> g, eta;
};
int runInvert(const std::filesystem::path& root, const InvertArgs& a);

} // namespace app
