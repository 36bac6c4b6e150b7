// Benchmarks (`bssrdf-workbench bench NAME`): print measured numbers and ratios to targets.
// Tests never assert times; these are for people and CI logs.
#pragma once

#include "pointcloud/generate.h"
#include "render/render.h"

#include <filesystem>
#include <string>
#include <vector>

namespace app {

// bench reload: save → new pixels latency of hot reload on a 512-sample pencil plot, through
// the real watcher, parser, GLSL compile, GPU evaluation and a full headless UI frame.
int benchReload(const std::filesystem::path& root, int runs);

// bench pathtrace: per slab case (η 1.0/1.3, g 0/0.8, albedo 0.5/0.99) paths/s per core of
// the CPU tracer and paths/s of the GL compute tracer; then, for the reference case (η 1.3,
// σa 0.01, σs 1, g 0, 0.15 mm bins) and marble, the single-core time to 1 % relative standard
// error at r = l_d and 4 l_d for every estimator (with and without radial splitting and
// expected-value exits), the GL tracer's, and the efficiency per radial range. With `mcml`
// (MCML 1.2.2's binary), MCML is run on the reference case here and its time to 1 % printed beside
// ours (bench/mcml_peer.h).
int benchPathtrace(const std::filesystem::path& root, double secondsPerRun,
                   const std::filesystem::path& mcml = {});

// Σ (a − ref)² / Σ ref² of L_o over the pixels `ref` covers and RGB (the renderers' benches:
// its square root is the relative RMSE they print).
double relativeMse(const render::Readback& a, const render::Readback& ref);

struct HierarchyBenchOptions {
    size_t points = 100000;
    pointcloud::Method method = pointcloud::GenerateOptions{}.method;
    int width = 640, height = 360;
    int frames = 5, bruteFrames = 3;
    int turkIterations = 500;                           // 0: skip the Turk reference
    std::vector<float> eps{0.8f, 0.4f, 0.2f, 0.1f};     // solid-angle criterion
    std::vector<float> boxEps{12.8f, 6.4f, 3.2f, 1.6f}; // bounding-box criterion
};
// bench hierarchy: hierarchical vs brute-force render pass of the default scene (bunny,
// 100 000 points, 640x360) for several eps — one line each: eps, hier_ms, brute_ms, speedup,
// rel_rmse (RMS of the difference / RMS of brute force) — and the point-cloud generation time
// and nearest-neighbour CV against Turk's repulsion with `turkIterations` iterations.
int benchHierarchy(const std::filesystem::path& root, const HierarchyBenchOptions& o);

// bench sampling: equal-time relative RMSE of the BSSRDF-integrated lit sphere and bunny
// (Marble, Skin1) by disk importance sampling (each axis scheme) against uniform area sampling,
// against a long disk-sampled reference; one line per case (sampling_bench.cpp).
int benchSampling(const std::filesystem::path& root, double seconds, int size,
                  double referenceFactor);

struct ConvergenceBenchOptions {
    std::string preset = "Marble";
    int width = 160, height = 90;
    size_t points = 50000;
    std::vector<float> eps{16.0f, 8.0f, 4.0f, 2.0f, 1.0f}; // bounding-box criterion (default)
    int referenceSpp = 1024;
    int maxSpp = 256;
    std::string out; // folder for convergence.csv and convergence.png (empty: print only)
};
// bench convergence: relative RMSE against time of the Render panel's renderers (hierarchical
// at several eps, brute force, Monte Carlo uniform and disk with each axis scheme) on the
// default scene against a converged Monte Carlo image; a log-log plot (convergence_bench.cpp).
int benchConvergence(const std::filesystem::path& root, const ConvergenceBenchOptions& o);

struct TextureSpaceBenchOptions {
    std::vector<std::string> presets{"Marble", "Skin1"};
    std::vector<double> scalesMm{10.0, 50.0}; // model size: mm per mesh unit (longest axis)
    std::vector<int> samples{49, 100, 400, 900, 1600, 2500}; // seed 004 Table 4.2's range
    std::vector<int> textures{16, 64, 256, 1024};
    std::vector<float> eps{64.0f, 32.0f, 16.0f, 8.0f, 4.0f, 2.0f, 1.0f}; // bounding-box criterion
    size_t points = 50000;
    int width = 160, height = 90;
    int sets = 4;
};
// bench texture-space: ms per frame and relative RMSE against the brute-force point-cloud render
// of texture-space sampling for each N and texture size, beside the hierarchical renderer's time
// at equal error, per material and model size (texspace_bench.cpp).
int benchTextureSpace(const std::filesystem::path& root, const TextureSpaceBenchOptions& o);

} // namespace app
