// Where the tests find the source tree (materials, shaders, captures, test data) and the
// workbench executable: $BW_TEST_SOURCE_ROOT and $BW_TEST_EXE when set, else this build's paths.
// The GPU test bundle (./run gpu-bundle, tests/bundle/) sets them, so its tests run from any
// folder on a machine without the source tree. Force-included into every test
// (tests/CMakeLists.txt), where BW_SOURCE_ROOT and BW_EXE name these functions.
#pragma once

#include <cstdlib>
#include <string>

namespace bwtest {

inline const char* pathFromEnvironment(const char* variable, const char* built) {
    const char* v = std::getenv(variable);
    return v && *v ? v : built;
}

inline const char* sourceRoot() {
    static const std::string root =
        pathFromEnvironment("BW_TEST_SOURCE_ROOT", BW_SOURCE_ROOT_BUILT);
    return root.c_str();
}

#ifdef BW_EXE_BUILT
inline const char* exe() {
    static const std::string path = pathFromEnvironment("BW_TEST_EXE", BW_EXE_BUILT);
    return path.c_str();
}
#endif

} // namespace bwtest
