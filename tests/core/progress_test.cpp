// core::progress (core.h): the progress line on stderr is rewritten in place, padded over a
// longer one before it, and ended with a newline before the log's echo or at progressEnd, so
// no message starts after a percentage. stderr is redirected to a real file for the test.
#include "core/core.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

namespace {

// Everything written to stderr while `body` runs.
template <class Body> std::string stderrOf(Body body) {
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("bw_progress_" + std::to_string(getpid()));
    std::fflush(stderr);
    const int saved = dup(fileno(stderr));
    FILE* f = std::fopen(file.c_str(), "wb");
    EXPECT_NE(f, nullptr);
    dup2(fileno(f), fileno(stderr));
    body();
    std::fflush(stderr);
    dup2(saved, fileno(stderr));
    close(saved);
    std::fclose(f);
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    std::filesystem::remove(file);
    return text.str();
}

} // namespace

TEST(Progress, LinesAreRewrittenInPlaceAndEndedBeforeTheNextMessage) {
    core::setProgressMode(core::ProgressMode::InPlace); // as on a terminal
    const std::string out = stderrOf([] {
        core::progress("slab: %5.1f%%", 50.0);
        core::progress("slab: %d%%", 7); // shorter: spaces over the rest of the last one
        core::logWarn("a warning");      // starts on a line of its own
        core::progress("render: %s", "irradiance");
        core::progressEnd();
        core::progressEnd(); // nothing open: nothing written
        core::logWarn("after the end");
    });
    EXPECT_EQ(out, "\rslab:  50.0%\rslab: 7%    \n[warning] a warning\n\rrender: irradiance\n"
                   "[warning] after the end\n");
    core::setProgressMode(core::ProgressMode::Auto);
}

// Not on a terminal (a file, as here; a pipe, a CI log): a line per update, the first of each
// phase at once, the rest of the phase at most every kProgressLineSeconds; the newest line not
// printed comes before the next phase, a log message, or at progressEnd.
TEST(Progress, ElsewhereEachUpdateIsALineAndAPhaseIsThrottled) {
    core::setProgressMode(core::ProgressMode::Auto); // stderr is the file: lines
    const std::string out = stderrOf([] {
        core::progress("slab: %5.1f%%", 10.0);
        core::progress("slab: %5.1f%%", 20.0); // within the interval: held
        core::progress("slab: %5.1f%%", 30.0);
        core::logWarn("a warning"); // the newest held line first
        core::progress("slab: %5.1f%%", 40.0);
        core::progress("render: mesh %d%%", 5); // a new phase: the held line, then this
        core::progress("render: mesh %d%%", 50);
        core::progress("render: points");                   // the phase changed again
        core::progress("render: points %g paths/s", 3e5);   // a new phase: "paths/s"
        core::progress("render: points %g paths/s", 2.5e6); // "2.5e+06": the same phase, held
        core::progress("render: points %g paths/s", 2.6e6); // held instead
        core::progressEnd();
        core::progressEnd(); // nothing held: nothing written
    });
    EXPECT_EQ(out, "slab:  10.0%\nslab:  30.0%\n[warning] a warning\nslab:  40.0%\n"
                   "render: mesh 5%\nrender: mesh 50%\nrender: points\n"
                   "render: points 300000 paths/s\nrender: points 2.6e+06 paths/s\n");
    EXPECT_EQ(out.find('\r'), std::string::npos);
}
