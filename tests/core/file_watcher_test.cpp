#include "../support/scratch_dir.h"
#include "core/core.h"
#include "core/file_watcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <thread>

namespace fs = std::filesystem;

namespace {
std::vector<fs::path> waitFor(core::FileWatcher& w, int ms = 2000) {
    core::Stopwatch sw;
    while (sw.ms() < ms) {
        auto r = w.poll();
        if (!r.empty()) return r;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return {};
}
} // namespace

TEST(FileWatcher, SeesWriteRenameAndDelete) {
    fs::path dir = fs::temp_directory_path() / ("bw_watch_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    testsupport::removeAtExit(dir);
    core::FileWatcher w({dir}, 30.0);
    ASSERT_TRUE(w.poll().empty());

    { std::ofstream(dir / "a.bssrdf") << "x"; }
    auto r = waitFor(w);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].filename(), "a.bssrdf");

    // Editor-style save: write a temporary, rename over the original.
    { std::ofstream(dir / ".a.bssrdf.swp") << "y"; }
    fs::rename(dir / ".a.bssrdf.swp", dir / "a.bssrdf");
    r = waitFor(w);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].filename(), "a.bssrdf");

    // A burst of writes is reported once.
    for (int i = 0; i < 10; ++i)
        std::ofstream(dir / "a.bssrdf") << i;
    r = waitFor(w);
    EXPECT_EQ(r.size(), 1u);

    fs::remove(dir / "a.bssrdf");
    r = waitFor(w);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_FALSE(fs::exists(r[0]));
    fs::remove_all(dir);
}
