// The paths of support/test_paths.h, from this test's build definitions.
#include "test_paths.h"

#include <cstdlib>
#include <string>

namespace bwtest {

const char* pathFromEnvironment(const char* variable, const char* built) {
    const char* v = std::getenv(variable);
    return v && *v ? v : built;
}

const char* sourceRoot() {
    static const std::string root =
        pathFromEnvironment("BW_TEST_SOURCE_ROOT", BW_SOURCE_ROOT_BUILT);
    return root.c_str();
}

#ifdef BW_EXE_BUILT
const char* exe() {
    static const std::string path = pathFromEnvironment("BW_TEST_EXE", BW_EXE_BUILT);
    return path.c_str();
}
#endif

} // namespace bwtest
