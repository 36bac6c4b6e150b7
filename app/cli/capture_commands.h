// `bssrdf-workbench record` and `replay`: captures of the workbench state recorded and replayed
// headless (captures/capture_io.h; the format: captures/README.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace app {

struct RecordArgs {
    std::string name, preset, outDir;
    std::vector<std::string> models;
    uint64_t referencePaths = 0;      // > 0: also record the path-traced reference (per channel)
    std::optional<int> referenceBins; // default: ReferenceSettings{}.bins (the GUI's)
    uint64_t slicePaths = 0; // > 0: also record the BSSRDF slice (reference and every model)
    std::optional<double> sliceThetaI; // default: SliceSettings{}.thetaIDeg (the GUI's)
    int litSphereSize = 0;             // > 0: also record the lit-sphere images at this size
    std::string litMesh; // with litSphereSize: path trace this OBJ instead of the sphere
    std::string litSampling, litAxes; // with litSphereSize: the integration's sampling and axes
    // > 0: also record the mesh pipeline (thesis 3.3) with this many points
    size_t scenePoints = 0;
    std::string sceneMesh = "third_party/bunny/bunny.obj"; // relative to the root
    int sceneWidth = 160, sceneHeight = 90;                // a small frame keeps captures small
    int traceX = -1, traceY = -1; // traced pixel (default: the image centre)
    // > 0: with scenePoints, also record the texture-space stages (seed 004) at this K
    int textureSpace = 0;
    int textureSamples = 256, textureSets = 16;
    bool hybrid = false; // with textureSpace: the hybrid (its local term recorded too)
    bool force = false;  // replace an existing capture folder
    // the state to record, as written by the GUI (writeRecordRequest): replaces every option
    // above but --name, --out and --force
    std::string fromRequest;
};
int runRecord(const std::filesystem::path& root, const RecordArgs& a);

int runReplay(const std::filesystem::path& root, const std::string& dir, bool update);

} // namespace app
