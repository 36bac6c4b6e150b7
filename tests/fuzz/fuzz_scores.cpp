// Fuzzes the scoreboard's scores.json as `compare --baseline` reads it (capture::readScores).
#include "fuzz_common.h"

#include "capture/scores.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput(data, size, "scores.json");
    fuzz::expectCleanError([&] { (void)capture::readScores(path.string()); });
    return 0;
}
