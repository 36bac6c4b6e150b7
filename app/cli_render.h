// `bssrdf-workbench render`: the mesh rendered with a model by the hierarchical point-cloud
// method (thesis 3.3) headless, written as an OpenEXR HDR image (R, G, B = radiance L_o, A =
// coverage), with the stage times and traversal statistics on stdout.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace app {

struct RenderArgs {
    std::string mesh, model, preset, sigmaA, sigmaS, out, png;
    std::optional<double> g, eta, scale;
    size_t points = 20000;
    std::string method = "stratified-repulsion";
    uint64_t seed = 1;
    std::string light = "dir:0.45,0.75,0.5"; // dir:x,y,z | ibl:FILE.exr
    bool occluded = false;
    int occludedSamples = 256;
    float irradiance = 3.0f; // E0 of the directional light / env intensity
    float eps = 0.2f;
    bool bboxCriterion = false, bruteForce = false, firstOrder = false;
    int width = 640, height = 360;
    float yaw = 0.5f, pitch = 0.2f, exposure = 0.0f;
    bool useCache = true;
};

int runRenderCli(const std::filesystem::path& root, const RenderArgs& a);

} // namespace app
