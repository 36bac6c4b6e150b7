// `bssrdf-workbench pointcloud`: the point cloud of a mesh (thesis 2.6.4, 3.3.1) written as
// binary PLY (pointcloud/pointcloud.h), with its uniformity metrics and generation time on
// stdout. No display or GL needed.
#pragma once

#include <cstdint>
#include <string>

namespace app {

struct PointCloudArgs {
    std::string mesh;                            // OBJ (required)
    size_t points = 20000;                       // N
    std::string method = "stratified-repulsion"; // | elimination | repulsion | uniform
    uint64_t seed = 1;
    int iterations = -1; // relaxation iterations (-1: the method's default)
    int threads = 0;
    bool useCache = true; // read/write the PLY cache (pointcloud::defaultCacheDir)
    std::string out;      // PLY file (required)
};

// Loads and prepares the mesh (mesh::prepareRenderable), generates, writes, prints. Throws
// core::Error naming the argument or file for every bad input.
int runPointCloudCli(const PointCloudArgs& a);

} // namespace app
