// bench hierarchy: the hierarchical point-cloud render (thesis 3.3.3, Algorithm 2) against brute
// force on the default scene (the bunny, dipole, Marble), and the point-cloud generation against
// Turk's repulsion. Prints measured numbers and ratios; asserts nothing.
#include "bench/bench.h"

#include "core/core.h"
#include "core/statistics.h"
#include "gl/gl.h"
#include "pipeline/workbench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace app {
namespace {

// Median traversal time (ms) of `frames` renders; leaves the last readback in `out`.
double timeRender(render::Renderer& r, const render::Settings& s, int frames,
                  render::Readback& out) {
    std::vector<double> ms;
    for (int i = 0; i < frames; ++i)
        ms.push_back(r.render(s).traverseMs);
    out = r.readback();
    return core::median(ms);
}

} // namespace

double relativeMse(const render::Readback& a, const render::Readback& ref) {
    double num = 0, den = 0;
    for (size_t p = 0; p < ref.hdr.size(); ++p) {
        if (ref.hdr[p].w < 0.5f) continue;
        for (int c = 0; c < 3; ++c) {
            const double d = double(a.hdr[p][c]) - double(ref.hdr[p][c]);
            num += d * d;
            den += double(ref.hdr[p][c]) * double(ref.hdr[p][c]);
        }
    }
    return den > 0 ? num / den : 0.0;
}

int benchHierarchy(const std::filesystem::path& root, const HierarchyBenchOptions& o) {
    auto ctx = gl::createHeadlessContext(false);
    std::printf("GL: %s | %s\n", ctx->renderer().c_str(), ctx->version().c_str());
    Workbench wb(root, false, {root / "materials" / "dipole.bssrdf"});
    SceneSettings& s = wb.scene().settings();
    s.enabled = true;
    s.useCache = false;
    s.points.points = o.points;
    s.points.method = o.method;
    s.render.width = o.width;
    s.render.height = o.height;
    wb.update();

    // Point-cloud generation, uncached, against Turk's repulsion.
    mesh::Mesh m = mesh::loadObj(root / s.meshFile);
    mesh::prepareRenderable(m, s.meshFile);
    pointcloud::GenerateOptions g = s.points;
    core::Stopwatch clock;
    const pointcloud::Generated fast = pointcloud::generate(m, g);
    const double fastS = clock.ms() / 1000.0;
    const auto fastU = pointcloud::measureUniformity(fast.cloud);
    std::printf("pointcloud method=%s points=%zu seconds=%.2f cv=%.4f min_over_mean=%.3f\n",
                pointcloud::methodTag(g).c_str(), o.points, fastS, fastU.cvNN,
                fastU.minNN / fastU.meanNN);
    std::fflush(stdout);
    if (o.turkIterations > 0) {
        pointcloud::GenerateOptions t = g;
        t.method = pointcloud::Method::Repulsion;
        t.repulsionIterations = o.turkIterations;
        clock.reset();
        const pointcloud::Generated turk = pointcloud::generate(m, t);
        const double turkS = clock.ms() / 1000.0;
        const auto turkU = pointcloud::measureUniformity(turk.cloud);
        std::printf("pointcloud method=%s points=%zu seconds=%.2f cv=%.4f min_over_mean=%.3f\n",
                    pointcloud::methodTag(t).c_str(), o.points, turkS, turkU.cvNN,
                    turkU.minNN / turkU.meanNN);
        std::printf("pointcloud target: <= 3 s and cv <= turk's: %.2f s, cv %.4f vs %.4f -> %s\n",
                    fastS, fastU.cvNN, turkU.cvNN,
                    fastS <= 3.0 && fastU.cvNN <= turkU.cvNN ? "met" : "NOT met");
    }

    // The scene with that cloud, then the render pass at several eps.
    wb.finishScene();
    for (const auto& p : wb.scene().problems())
        throw core::Error(p);
    render::Renderer* r = wb.scene().renderer();
    if (!r || !wb.scene().hasFrame()) throw core::Error("bench", 0, "the scene did not render");
    render::Settings base = s.render;
    render::Readback brute, hier;
    render::Settings bs = base;
    bs.bruteForce = true;
    const double bruteMs = timeRender(*r, bs, o.bruteFrames, brute);
    std::printf("scene: bunny, %zu points, %dx%d, dipole Marble, scale %.0f mm; times: traversal "
                "pass after glFinish, median of %d (hierarchy) / %d (brute force) frames\n",
                o.points, o.width, o.height, double(r->builtins().scale), o.frames, o.bruteFrames);
    bool met = false;
    for (int second = 1; second >= 0; --second)
        for (int box = 0; box < 2; ++box)
            for (float eps : box ? o.boxEps : o.eps) {
                render::Settings hs = base;
                hs.eps = eps;
                hs.bruteForce = false;
                hs.boundingBoxCriterion = box == 1;
                hs.secondOrder = second == 1;
                const double hierMs = timeRender(*r, hs, o.frames, hier);
                const double err = std::sqrt(relativeMse(hier, brute));
                const double speedup = bruteMs / std::max(hierMs, 1e-6);
                met |= speedup >= 60.0 && err <= 0.01;
                std::printf("eps=%g hier_ms=%.2f brute_ms=%.2f speedup=%.1f rel_rmse=%.5f "
                            "criterion=%s clusters=%s\n",
                            double(eps), hierMs, bruteMs, speedup, err,
                            box ? "bounding-box" : "solid-angle",
                            second ? "second-order" : "first-order");
                std::fflush(stdout); // one line per case as it finishes (long runs on llvmpipe)
            }
    std::printf("target: >= 60x faster than brute force at <= 1%% relative RMSE -> %s\n",
                met ? "met" : "NOT met");
    return 0;
}

} // namespace app
