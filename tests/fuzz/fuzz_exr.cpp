// Fuzzes the lat-long EXR environment loader (irradiance::readEnvironment, OpenEXR underneath)
// and the validation and quadrature of an environment read.
#include "fuzz_common.h"

#include "irradiance/environment.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput(data, size, "env.exr");
    fuzz::expectCleanError([&] {
        irradiance::EnvironmentMap env = irradiance::readEnvironment(path);
        irradiance::validateEnvironment(env, "env.exr");
    });
    return 0;
}
