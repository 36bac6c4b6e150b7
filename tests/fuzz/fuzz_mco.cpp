// Fuzzes the MCML output reader (pathtrace::parseMco) and what reads its result: the writer,
// the medium of a one-layer file and its R_d(r) as a slab reference.
#include "fuzz_common.h"

#include "pathtrace/mco.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::expectCleanError([&] {
        const pathtrace::McoFile m = pathtrace::parseMco(text, "input.mco");
        (void)pathtrace::formatMco(m);
        (void)pathtrace::slabFromMco(m, &m);
        (void)pathtrace::mediumOfMco(m, "input.mco");
    });
    return 0;
}
