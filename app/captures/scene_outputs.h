// Captures of the mesh pipeline (thesis 3.3; capture format v1, captures/README.md): its stage
// outputs (its settings: settings_json.h) —
//   scene.mesh         csv, exact   vertices, triangles, area, hash of the prepared mesh
//   scene.pointcloud   csv, exact   count, nearest-neighbour metrics, content hash
//   scene.octree       csv, exact   node/leaf counts, depth, bytes, hash, nodes per depth
//   scene.irradiance   csv, tol     per-point E_t (GPU)
//   scene.render       exr, tol     the rendered HDR radiance (GPU)
//   scene.trace_steps  csv, exact   one pixel's traversal steps (CPU replica): node, decision,
//                                   depth, stack after each step
//   scene.trace_values csv, tol     that trace's contributions and running sums
// and with texture_space.enabled (seed 004; its render is an exr_stat stage of capture_io):
//   texture_space.texels   csv, exact   K, layout size, UVs or atlas, covered texels, triangles
//                                       with texels, largest stretch
//   texture_space.eprime   csv, tol     E′ (RGB) of every 8th covered texel (GPU irradiance)
//   texture_space.samples  csv, exact   the first 256 texels of sample set 0 (the GPU descent)
// Hashes are split into four 16-bit integers so that they compare exactly as numbers.
#pragma once

#include "capture/capture.h"
#include "pipeline/workbench.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace app {

struct SceneCaptureTable {
    std::string stage, file, key;
    capture::Table table;
    double absTol = 0, relTol = 0;
    std::string note;
};
struct SceneCaptureImage {
    std::string stage, file;
    pathtrace::Image image;
    double absTol = 0, relTol = 0;
    std::string note;
};
struct SceneCapture {
    std::vector<SceneCaptureTable> tables;
    std::optional<SceneCaptureImage> image;
};

// Runs the scene to completion and collects its outputs (empty when the scene is off).
SceneCapture sceneOutputs(Workbench& wb, int traceX, int traceY);
// x, y, R, G, B per pixel (for comparing "exr" stages).
capture::Table renderTable(const pathtrace::Image& img);

} // namespace app
