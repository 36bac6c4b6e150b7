// `bssrdf-workbench pointcloud` (cli_pointcloud.h).
#include "cli_pointcloud.h"

#include "core/core.h"
#include "mesh/mesh.h"
#include "pointcloud/generate.h"

#include <cstdio>

namespace app {

int runPointCloudCli(const PointCloudArgs& a) {
    if (a.mesh.empty()) throw core::Error("--mesh", 0, "give the OBJ file to sample");
    if (a.out.empty()) throw core::Error("--out", 0, "give the PLY file to write");
    pointcloud::GenerateOptions o;
    o.points = a.points;
    o.method = a.method;
    o.seed = a.seed;
    if (a.iterations >= 0) o.repulsionIterations = o.stratifiedIterations = a.iterations;
    o.threads = a.threads;
    pointcloud::checkOptions(o); // before the (possibly slow) mesh load
    mesh::Mesh m = mesh::loadObj(a.mesh);
    const mesh::RenderablePrep prep = mesh::prepareRenderable(m, a.mesh);
    if (prep.droppedDegenerate)
        std::fprintf(stderr, "%s: dropped %zu degenerate (zero-area) triangles\n", a.mesh.c_str(),
                     prep.droppedDegenerate);
    const pointcloud::Generated g =
        pointcloud::generate(m, o, a.useCache ? pointcloud::defaultCacheDir() : "");
    pointcloud::writePly(a.out, g.cloud);
    const pointcloud::Uniformity u = pointcloud::measureUniformity(g.cloud, a.threads);
    std::printf("%zu points (%s, seed %llu) on %s: area %.6g units^2, %s %.1f ms\n",
                g.cloud.points.size(), pointcloud::methodTag(o).c_str(),
                static_cast<unsigned long long>(a.seed), a.mesh.c_str(), g.cloud.totalArea,
                g.fromCache ? "read from cache in" : "generated in", g.milliseconds);
    std::printf("nearest neighbour: mean %.6g, CV %.4f, min/mean %.4f\n", u.meanNN, u.cvNN,
                u.meanNN > 0 ? u.minNN / u.meanNN : 0.0);
    std::printf("wrote %s\n", a.out.c_str());
    return 0;
}

} // namespace app
