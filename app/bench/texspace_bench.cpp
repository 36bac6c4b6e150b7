// bench texture-space: texture-space importance sampling (Chang 2007, seed 004) against the
// hierarchical point-cloud renderer at equal error, on the default scene (the bunny, default
// light and view, dipole), per material and model size, for N in Table 4.2's range and texture
// sizes 16² … 1024². Both are measured against the brute-force point-cloud render of the same
// scene in the same run. Times are wall clock after glFinish of what a frame costs (texture
// space: drawing the set and rendering it, plus for the hybrid its local term — computed once per
// view, counted in every frame here as a moving view would; hierarchical: the frame's G-buffer,
// profile, traversal and tone map) — GL's timer queries read 0 on llvmpipe. Asserts nothing.
#include "bench/bench.h"

#include "core/core.h"
#include "gl/gl.h"
#include "pipeline/workbench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace app {
namespace {

double frameMs(const render::Frame& f) {
    return f.gbufferMs + f.profileMs + f.traverseMs + f.tonemapMs;
}

struct HierPoint {
    float eps;
    double ms, err;
};

} // namespace

int benchTextureSpace(const std::filesystem::path& root, const TextureSpaceBenchOptions& o) {
    auto ctx = gl::createHeadlessContext(false);
    std::printf("GL: %s | %s\n", ctx->renderer().c_str(), ctx->version().c_str());
    Workbench wb(root, false, {root / "materials" / "dipole.bssrdf"});
    SceneSettings& s = wb.scene().settings();
    s.enabled = true;
    s.useCache = true;
    s.points.points = o.points;
    s.render.width = o.width;
    s.render.height = o.height;
    std::printf("scene: bunny, dipole, default light and view, %dx%d; reference: brute force over "
                "%zu points; per case %d sets (rel_rmse of one frame = √ of the mean squared "
                "error over them); ms: wall clock after glFinish per frame, median\n",
                o.width, o.height, o.points, o.sets);
    for (const std::string& preset : o.presets)
        for (double scale : o.scalesMm) {
            wb.applyPreset(wb.shared(), preset);
            wb.shared().params.scale = float(scale);
            wb.update();
            wb.finishScene();
            for (const auto& p : wb.scene().problems())
                throw core::Error(p);
            render::Renderer* r = wb.scene().renderer();
            if (!r || !wb.scene().hasFrame())
                throw core::Error("bench", 0, "the scene did not render");
            const render::Settings view = s.render;
            render::Settings bs = view;
            bs.bruteForce = true;
            core::Stopwatch clock;
            const double bruteMs = frameMs(r->render(bs));
            const render::Readback ref = r->readback();
            // the hierarchical renderer's error against time (bounding-box criterion, the
            // default second-order clusters)
            std::vector<HierPoint> hier;
            for (float eps : o.eps) {
                render::Settings hs = view;
                hs.bruteForce = false;
                hs.boundingBoxCriterion = true;
                hs.secondOrder = true;
                hs.eps = eps;
                std::vector<double> ms;
                for (int i = 0; i < 3; ++i)
                    ms.push_back(frameMs(r->render(hs)));
                std::sort(ms.begin(), ms.end());
                hier.push_back({eps, ms[1], std::sqrt(relativeMse(r->readback(), ref))});
                std::printf("preset=%s scale_mm=%g method=hierarchical eps=%g ms=%.2f "
                            "rel_rmse=%.5f (brute force %.1f ms)\n",
                            preset.c_str(), scale, double(eps), ms[1], hier.back().err, bruteMs);
                std::fflush(stdout);
            }
            // the cheapest hierarchical frame with at most this error
            auto atEqualError = [&](double err) {
                double best = -1;
                for (const HierPoint& h : hier)
                    if (h.err <= err && (best < 0 || h.ms < best)) best = h.ms;
                return best;
            };
            for (const bool hybrid : {false, true})
                for (int k : o.textures) {
                    TextureSpaceSettings& ts = wb.textureSpaceSettings();
                    ts.sampling.textureSize = k;
                    ts.sampling.samples = 1;
                    ts.sampling.sampleSets = 1;
                    ts.sampling.hybrid = false;
                    wb.finishTextureSpace(); // mesh, texels, light, model: ready to draw
                    texspace::Pipeline& p = *wb.textureSpace().pipeline();
                    for (int n : o.samples) {
                        texspace::Settings run = ts.sampling;
                        run.samples = n;
                        run.sampleSets = o.sets;
                        run.seed = 7;
                        run.hybrid = hybrid;
                        p.begin(run, view);
                        std::vector<double> ms;
                        double mse = 0;
                        for (int set = 0; set < o.sets; ++set) {
                            // one set (budget 0: advance returns after each set it finishes)
                            while (p.setsDone() == set)
                                p.advance(0);
                            // a frame: draw, render the set, and (hybrid) the local term,
                            // which is computed once per view and reused by later sets
                            ms.push_back(p.lastSampleMs() + p.lastRenderMs() +
                                         (hybrid ? p.localMs() : 0.0));
                            render::Readback one;
                            one.hdr = p.lastSetRadiance();
                            mse += relativeMse(one, ref) / o.sets;
                        }
                        std::sort(ms.begin(), ms.end());
                        const double err = std::sqrt(mse), h = atEqualError(err);
                        char hText[32];
                        if (h < 0)
                            std::snprintf(hText, sizeof hText, "none");
                        else
                            std::snprintf(hText, sizeof hText, "%.2f", h);
                        std::printf("preset=%s scale_mm=%g method=%s samples=%d texture=%d "
                                    "ms=%.2f rel_rmse=%.5f hier_ms_at_equal_error=%s\n",
                                    preset.c_str(), scale, hybrid ? "hybrid" : "texture-space", n,
                                    k, ms[ms.size() / 2], err, hText);
                        std::fflush(stdout);
                    }
                }
        }
    std::printf("hier_ms_at_equal_error: the cheapest hierarchical frame (eps above) whose error "
                "is at most the texture-space one; none: every hierarchical frame has a larger "
                "error\n");
    return 0;
}

} // namespace app
