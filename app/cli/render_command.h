// `bssrdf-workbench render`: the mesh rendered with a model by the hierarchical point-cloud
// method (thesis 3.3) headless, written as an OpenEXR HDR image (R, G, B = radiance L_o, A =
// coverage), with the stage times and traversal statistics on stdout. Its scene settings start
// from the GUI's defaults (SceneSettings); the options that set them are generated from their
// descriptions (options.h).
#pragma once

#include "pipeline/scene_stage.h"
#include "pipeline/texspace_stage.h"

#include <filesystem>
#include <optional>
#include <string>

namespace CLI {
class App;
}

namespace app {

struct RenderArgs {
    std::string mesh, model, preset, sigmaA, sigmaS, out, png;
    std::optional<double> g, eta, scale;
    SceneSettings scene; // the GUI's defaults, changed by the options
    std::string light;   // dir:x,y,z | ibl:FILE.exr (empty: the scene's directional light)
    bool occluded = false;
    std::optional<float> irradiance; // E0 of the directional light / env intensity
    bool useCache = true;
    // hierarchical | bruteforce (the point cloud) | texture-space (seed 004)
    std::string renderer = "hierarchical";
    TextureSpaceSettings textureSpace; // --texture-size, --samples, --sets
    std::string stageImages;           // folder for the texture-space stage images
};

// The `render` options (flags, help texts with the defaults) writing into `a`.
void addRenderOptions(CLI::App* cmd, RenderArgs& a);
int runRenderCli(const std::filesystem::path& root, const RenderArgs& a);

} // namespace app
