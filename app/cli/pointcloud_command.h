// `bssrdf-workbench pointcloud`: the point cloud of a mesh (thesis 2.6.4, 3.3.1) written as
// binary PLY (pointcloud/pointcloud.h), with its uniformity metrics and generation time on
// stdout. No display or GL needed.
#pragma once

#include "pointcloud/generate.h"

#include <string>

namespace CLI {
class App;
}

namespace app {

struct PointCloudArgs {
    std::string mesh;                    // OBJ (required)
    pointcloud::GenerateOptions options; // the GUI's defaults, changed by the options
    int iterations = -1;  // relaxation iterations of the chosen method (-1: its default)
    bool useCache = true; // read/write the PLY cache (pointcloud::defaultCacheDir)
    std::string out;      // PLY file (required)
};

// The `pointcloud` options (flags, help texts with the defaults) writing into `a`.
void addPointCloudOptions(CLI::App* cmd, PointCloudArgs& a);

// Loads and prepares the mesh (mesh::prepareRenderable), generates, writes, prints. Throws
// core::Error naming the argument or file for every bad input.
int runPointCloudCli(const PointCloudArgs& a);

} // namespace app
