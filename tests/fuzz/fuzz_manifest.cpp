// Fuzzes the capture manifest (capture::readManifest of a folder holding the input as
// manifest.json), and the write-back check of a manifest read.
#include "fuzz_common.h"

#include "capture/capture.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::writeInput(data, size, "manifest.json");
    fuzz::expectCleanError([&] {
        capture::Manifest m = capture::readManifest(fuzz::scratchDir());
        (void)capture::toJson(m).dump();
    });
    return 0;
}
