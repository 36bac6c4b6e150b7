// Fuzzes the path-traced BSSRDF table file (.bwtable, pathtrace::readTable) and what table
// models make of a table read: the radial check, the oblique table and its GLSL, the CSV views.
#include "fuzz_common.h"

#include "bssrdf/oblique_table.h"
#include "pathtrace/bssrdf_table.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const auto path = fuzz::writeInput(data, size, "table.bwtable");
    fuzz::expectCleanError([&] {
        pathtrace::BssrdfTable t = pathtrace::readTable(path);
        (void)pathtrace::tableCsv(t);
        (void)pathtrace::tableDirCsv(t);
        (void)bssrdf::isRadialTable(t);
    });
    return 0;
}
