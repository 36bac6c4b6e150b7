// pointcloud generation front end (thesis 3.3.1: "generated point clouds are saved to disk ... to
// speed up future loading times"): one entry point that picks a method by name, checks the
// request (point count, memory estimate), and reads/writes the binary PLY cache keyed by
// cacheKey(mesh, N, method tag, seed), where the method tag includes the method's parameters.
//   methods (enum Method, names in enumNames): "stratified-repulsion" — stratified start +
//   short-range repulsion with momentum
//                                     (sampleStratifiedRepulsion), the default: the most even
//                                     clouds in the least time
//            "elimination" — weighted sample elimination (Yuksel 2015)
//            "repulsion"   — sampleUniform + Turk repulsion (the thesis' method)
//            "uniform"     — sampleUniform only (white noise, for comparison)
#pragma once

#include "core/limits.h"
#include "pointcloud/pointcloud.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>

namespace pointcloud {

enum class Method { StratifiedRepulsion, Elimination, Repulsion, Uniform };
// The methods' names (also their JSON and command-line spelling).
constexpr auto enumNames(Method) {
    return std::array{std::pair{Method::StratifiedRepulsion, "stratified-repulsion"},
                      std::pair{Method::Elimination, "elimination"},
                      std::pair{Method::Repulsion, "repulsion"},
                      std::pair{Method::Uniform, "uniform"}};
}
const char* methodName(Method m);

struct GenerateOptions {
    size_t points = 20000;
    Method method = Method::StratifiedRepulsion;
    uint64_t seed = 1;
    int repulsionIterations = 30;  // "repulsion" only
    int stratifiedIterations = 40; // "stratified-repulsion" only
    double candidateFactor = 5.0;  // "elimination" only
    int threads = 0;               // 0 = all cores; results do not depend on it
    // Requests whose estimated peak memory exceeds this are refused (bytes).
    size_t memoryCapBytes = size_t(4) << 30;
};
// The description of GenerateOptions' members (core/fields.h).
template <class V> void fields(V& v, GenerateOptions& o) {
    v("count", o.points, "number of points N", core::Limits{1, 16777216});
    v("method", o.method, "generation method");
    v("seed", o.seed, "random seed");
    v("iterations", o.repulsionIterations, "repulsion: Turk relaxation iterations",
      core::Limits{0, 100000});
    v("stratified_iterations", o.stratifiedIterations, "stratified-repulsion: iterations",
      core::Limits{0, 100000});
    v("candidate_factor", o.candidateFactor, "elimination: candidates per point",
      core::Limits{1.5, 50});
    v.skip(o.threads, "worker threads; results do not depend on it");
    v.skip(o.memoryCapBytes, "a limit of the machine, not of the result");
}

// "stratified-repulsion(it=40)", "elimination(c=5)", "repulsion(it=30)", "uniform": the method
// with its parameters.
std::string methodTag(const GenerateOptions& o);

// Peak bytes the generation of `o.points` points needs (candidates, grids, the result).
size_t estimateBytes(const GenerateOptions& o);

// Throws core::Error(argument, 0, message) for 0 points, more than 2^24 points (the octree's
// 24-bit index), iterations outside [0, 100000], a candidate factor outside
// [1.5, 50], or a memory estimate over the cap (the message gives both numbers).
void checkOptions(const GenerateOptions& o);

struct Generated {
    PointCloud cloud;
    bool fromCache = false;
    std::filesystem::path cacheFile; // empty when no cache folder was given
    double milliseconds = 0;         // generation or cache read time
};

// Generates (or reads from `cacheDir`/<cacheKey>.ply when present and valid) the point cloud of
// `m`. A cache file that fails to read is regenerated and rewritten (the failure is logged).
// cacheDir empty: no cache.
// `progress` (may be empty) is told the relaxation's iterations done and in all.
Generated generate(const mesh::Mesh& m, const GenerateOptions& o,
                   const std::filesystem::path& cacheDir = {},
                   const IterationProgress& progress = {});

// The default cache folder: $BSSRDF_WORKBENCH_CACHE, else $XDG_CACHE_HOME/bssrdf-workbench, else
// $HOME/.cache/bssrdf-workbench, with "/pointclouds" appended; empty when none is set.
std::filesystem::path defaultCacheDir();

} // namespace pointcloud
