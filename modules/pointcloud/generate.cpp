// pointcloud generation front end: method dispatch, request checks, PLY cache (generate.h).
#include "pointcloud/generate.h"

#include "core/core.h"

#include <cstdio>
#include <cstdlib>

namespace pointcloud {

const char* methodName(Method m) {
    for (const auto& [v, n] : enumNames(m))
        if (v == m) return n;
    return "?";
}

std::string methodTag(const GenerateOptions& o) {
    char b[64];
    if (o.method == Method::Elimination) {
        std::snprintf(b, sizeof b, "elimination(c=%g)", o.candidateFactor);
        return b;
    }
    if (o.method == Method::Repulsion) {
        std::snprintf(b, sizeof b, "repulsion(it=%d)", o.repulsionIterations);
        return b;
    }
    if (o.method == Method::StratifiedRepulsion) {
        std::snprintf(b, sizeof b, "stratified-repulsion(it=%d)", o.stratifiedIterations);
        return b;
    }
    return methodName(o.method);
}

size_t estimateBytes(const GenerateOptions& o) {
    // The result, one double-buffered copy, and for elimination the candidate set with its
    // heap and neighbour lists (about 24 neighbours of 8 bytes each per candidate).
    const double n = double(o.points);
    double bytes = 3.0 * n * sizeof(Point);
    if (o.method == Method::Elimination)
        bytes += o.candidateFactor * n * (sizeof(Point) + 24 * 8 + 16);
    if (o.method == Method::Repulsion) bytes += n * (sizeof(Point) + 64);
    // working buffers, neighbour lists (~26 entries), grid scratch
    if (o.method == Method::StratifiedRepulsion) bytes += n * 400;
    return bytes > 1e18 ? size_t(-1) : size_t(bytes);
}

void checkOptions(const GenerateOptions& o) {
    if (o.points == 0) throw core::Error("--points", 0, "the point count must be at least 1");
    if (o.points > (size_t(1) << 24))
        throw core::Error("--points", 0,
                          "at most 16777216 points (the octree's 24-bit index), got " +
                              std::to_string(o.points));
    for (int it : {o.repulsionIterations, o.stratifiedIterations})
        if (it < 0 || it > 100000)
            throw core::Error("--iterations", 0,
                              "must lie in [0, 100000], got " + std::to_string(it));
    if (!(o.candidateFactor >= 1.5 && o.candidateFactor <= 50))
        throw core::Error("--candidates", 0, "candidate factor must lie in [1.5, 50]");
    const size_t need = estimateBytes(o);
    if (need > o.memoryCapBytes) {
        char b[160];
        std::snprintf(
            b, sizeof b, "%zu points need about %.1f MiB to generate, over the cap of %.1f MiB",
            o.points, double(need) / double(1u << 20), double(o.memoryCapBytes) / double(1u << 20));
        throw core::Error("--points", 0, b);
    }
}

namespace {

PointCloud run(const mesh::Mesh& m, const GenerateOptions& o, const IterationProgress& progress) {
    if (o.method == Method::StratifiedRepulsion) {
        StratifiedRepulsionOptions s;
        s.iterations = o.stratifiedIterations;
        s.threads = o.threads;
        s.progress = progress;
        return sampleStratifiedRepulsion(m, o.points, o.seed, s);
    }
    if (o.method == Method::Elimination) {
        EliminationOptions e;
        e.candidateFactor = o.candidateFactor;
        e.threads = o.threads;
        return sampleElimination(m, o.points, o.seed, e);
    }
    PointCloud c = sampleUniform(m, o.points, o.seed, o.threads);
    if (o.method == Method::Repulsion && o.repulsionIterations > 0) {
        RepulsionOptions r;
        r.iterations = o.repulsionIterations;
        r.threads = o.threads;
        r.progress = progress;
        c = relaxRepulsion(m, c, r);
    }
    return c;
}

} // namespace

Generated generate(const mesh::Mesh& m, const GenerateOptions& o,
                   const std::filesystem::path& cacheDir, const IterationProgress& progress) {
    checkOptions(o);
    Generated g;
    core::Stopwatch clock;
    if (!cacheDir.empty()) {
        g.cacheFile = cacheDir / (cacheKey(m, o.points, methodTag(o), o.seed) + ".ply");
        std::error_code ec;
        if (std::filesystem::exists(g.cacheFile, ec)) {
            try {
                g.cloud = readPly(g.cacheFile);
                if (g.cloud.points.size() == o.points) {
                    g.fromCache = true;
                    g.milliseconds = clock.ms();
                    return g;
                }
                core::logWarn(g.cacheFile.string() + ": wrong point count, regenerating");
            } catch (const core::Error& e) {
                core::logWarn(std::string("point cloud cache unreadable, regenerating: ") +
                              e.what());
            }
        }
    }
    g.cloud = run(m, o, progress);
    const int iterations = o.method == Method::StratifiedRepulsion ? o.stratifiedIterations
                           : o.method == Method::Repulsion         ? o.repulsionIterations
                                                                   : 0;
    if (progress && iterations > 0) progress(iterations, iterations);
    g.milliseconds = clock.ms();
    if (!g.cacheFile.empty()) {
        try {
            std::filesystem::create_directories(g.cacheFile.parent_path());
            writePly(g.cacheFile, g.cloud);
        } catch (const std::exception& e) {
            core::logWarn(std::string("could not write the point cloud cache: ") + e.what());
        }
    }
    return g;
}

std::filesystem::path defaultCacheDir() {
    if (const char* c = std::getenv("BSSRDF_WORKBENCH_CACHE"); c && *c)
        return std::filesystem::path(c) / "pointclouds";
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
        return std::filesystem::path(x) / "bssrdf-workbench" / "pointclouds";
    if (const char* h = std::getenv("HOME"); h && *h)
        return std::filesystem::path(h) / ".cache" / "bssrdf-workbench" / "pointclouds";
    return {};
}

} // namespace pointcloud
