// Fuzzes the point-cloud cache reader (pointcloud::readPly, binary little-endian PLY).
#include "fuzz_common.h"

#include "pointcloud/pointcloud.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput(data, size, "cloud.ply");
    fuzz::expectCleanError([&] { (void)pointcloud::readPly(path); });
    return 0;
}
