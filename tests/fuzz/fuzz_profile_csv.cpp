// Fuzzes the radial profile CSV of table models (readProfileCsv) and, for a table it reads, the
// GLSL made from it.
#include "fuzz_common.h"

#include "bssrdf/table_model.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput(data, size, "profile.csv");
    fuzz::expectCleanError([&] {
        bssrdf::RadialTable t = bssrdf::readProfileCsv(path, "profile.csv");
        (void)bssrdf::radialTableGlsl(t);
    });
    return 0;
}
