// `bssrdf-workbench pointcloud` (pointcloud_command.h).
#include "cli/pointcloud_command.h"
#include "cli/command.h"
#include "cli/output.h"

#include "cli/options.h"
#include "core/core.h"
#include "core/fields.h"
#include "mesh/mesh.h"
#include "pointcloud/generate.h"

#include <cstdio>
#include <memory>

namespace app {

void addPointCloudOptions(CLI::App* cmd, PointCloudArgs& a) {
    cmd->add_option("--mesh", a.mesh, "triangle mesh (OBJ)")->required();
    addSettingOptions(cmd, a.options,
                      {{"count", "--points"}, {"method", "--method"}, {"seed", "--seed"}});
    const pointcloud::GenerateOptions d;
    addCountOption(cmd, "--iterations", a.iterations,
                   "relaxation iterations (default " + std::to_string(d.stratifiedIterations) +
                       " stratified-repulsion, " + std::to_string(d.repulsionIterations) +
                       " repulsion)",
                   core::limitsOf<pointcloud::GenerateOptions>("iterations"));
    addCountOption(cmd, "--threads", a.options.threads,
                   "worker threads, 0 … 1024 (default 0: all cores)", kThreadLimits);
    cmd->add_flag("--no-cache{false}", a.useCache, "neither read nor write the point-cloud cache");
    cmd->add_option("--out", a.out, "PLY file (x y z nx ny nz area float32, triangle uint32)")
        ->required();
    refuseIgnoredOptions(cmd, {{{"--iterations"},
                                [&a] {
                                    return a.options.method == pointcloud::Method::Elimination ||
                                           a.options.method == pointcloud::Method::Uniform;
                                },
                                "only with --method stratified-repulsion or repulsion (the "
                                "relaxations)"}});
}

int runPointCloudCli(const PointCloudArgs& a) {
    if (a.mesh.empty()) throw core::Error("--mesh", 0, "give the OBJ file to sample");
    if (a.out.empty()) throw core::Error("--out", 0, "give the PLY file to write");
    checkOutput(a.out, "--out", ".ply");
    pointcloud::GenerateOptions o = a.options;
    if (a.iterations >= 0) o.repulsionIterations = o.stratifiedIterations = a.iterations;
    pointcloud::checkOptions(o); // before the (possibly slow) mesh load
    mesh::Mesh m = mesh::loadObj(a.mesh);
    const mesh::RenderablePrep prep = mesh::prepareRenderable(m, a.mesh);
    if (prep.droppedDegenerate)
        std::fprintf(stderr, "%s: dropped %zu degenerate (zero-area) triangles\n", a.mesh.c_str(),
                     prep.droppedDegenerate);
    core::Stopwatch clock;
    const pointcloud::Generated g = pointcloud::generate(
        m, o, a.useCache ? pointcloud::defaultCacheDir() : "", [&](int done, int total) {
            if (clock.ms() < 1000) return; // runs shorter than a second print no progress
            core::progress("pointcloud: relaxation %d / %d iterations  %.1f s", done, total,
                           clock.ms() / 1000.0);
        });
    core::progressEnd();
    pointcloud::writePly(a.out, g.cloud);
    const pointcloud::Uniformity u = pointcloud::measureUniformity(g.cloud, o.threads);
    std::printf("%zu points (%s, seed %llu) on %s: area %.6g units^2, %s %.1f ms\n",
                g.cloud.points.size(), pointcloud::methodTag(o).c_str(),
                static_cast<unsigned long long>(o.seed), a.mesh.c_str(), g.cloud.totalArea,
                g.fromCache ? "read from cache in" : "generated in", g.milliseconds);
    std::printf("nearest neighbour: mean %.6g, CV %.4f, min/mean %.4f\n", u.meanNN, u.cvNN,
                u.meanNN > 0 ? u.minNN / u.meanNN : 0.0);
    std::printf("wrote %s\n", a.out.c_str());
    return 0;
}

Command pointcloudCommand() {
    return {"pointcloud", "even point cloud on a mesh (thesis 2.6.4) as binary PLY, with metrics",
            false, [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<PointCloudArgs>();
                addPointCloudOptions(&cmd, *a);
                return [a](CommandContext&) { return runPointCloudCli(*a); };
            }};
}

} // namespace app
