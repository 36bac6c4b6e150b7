#include "../support/scratch_dir.h"
#include "core/core.h"
#include "core/file_watcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <condition_variable>
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
// An empty folder of this process under the temporary directory, removed at exit.
fs::path emptyFolder(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    testsupport::removeAtExit(dir);
    return dir;
}
} // namespace

TEST(FileWatcher, SeesWriteRenameAndDelete) {
    const fs::path dir = emptyFolder("bw_watch");
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

// A write that ends with the file's close is reported without waiting for the debounce (here
// longer than the test's patience); a file still open for writing is not, until it is closed.
TEST(FileWatcher, AClosedWriteSettlesBeforeTheDebounceAnOpenOneWaitsForItsClose) {
    const fs::path dir = emptyFolder("bw_watch_close");
    core::FileWatcher w({dir}, 600000.0);
    ASSERT_TRUE(w.usingInotify());

    { std::ofstream(dir / "a.bssrdf") << "x"; }
    auto r = waitFor(w);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].filename(), "a.bssrdf");

    std::ofstream open(dir / "a.bssrdf");
    open << "partial" << std::flush;
    EXPECT_TRUE(waitFor(w, 300).empty()) << "reported while still open for writing";
    open << " and the rest" << std::flush;
    open.close();
    r = waitFor(w);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_EQ(r[0].filename(), "a.bssrdf");

    // Saved by renaming a temporary over it, and deleted: both complete at once.
    { std::ofstream(dir / "b.tmp") << "y"; }
    fs::rename(dir / "b.tmp", dir / "a.bssrdf");
    r = waitFor(w);
    ASSERT_EQ(r.size(), 1u);
    fs::remove(dir / "a.bssrdf");
    r = waitFor(w);
    ASSERT_EQ(r.size(), 1u);
    EXPECT_FALSE(fs::exists(r[0]));
    fs::remove_all(dir);
}

// setWake: a write wakes a sleeping loop from the watcher's thread, once per arrival, and the
// thread stops with the watcher (or with an empty function).
TEST(FileWatcher, AWriteWakesASleepingLoop) {
    const fs::path dir = emptyFolder("bw_watch_wake");
    core::FileWatcher w({dir});
    ASSERT_TRUE(w.usingInotify());
    std::mutex m;
    std::condition_variable cv;
    int wakes = 0;
    w.setWake([&] {
        std::lock_guard<std::mutex> lock(m);
        ++wakes;
        cv.notify_all();
    });
    const auto wokenWithin = [&](int atLeast, int ms) {
        std::unique_lock<std::mutex> lock(m);
        return cv.wait_for(lock, std::chrono::milliseconds(ms), [&] { return wakes >= atLeast; });
    };
    EXPECT_FALSE(wokenWithin(1, 100)) << "woken with nothing written";

    { std::ofstream(dir / "a.bssrdf") << "x"; }
    ASSERT_TRUE(wokenWithin(1, 5000));
    // not read yet: no second wake for the same events however long the loop sleeps
    EXPECT_FALSE(wokenWithin(2, 200));
    auto r = waitFor(w);
    ASSERT_EQ(r.size(), 1u);

    { std::ofstream(dir / "a.bssrdf") << "y"; }
    ASSERT_TRUE(wokenWithin(2, 5000));
    EXPECT_EQ(waitFor(w).size(), 1u);

    w.setWake({});
    { std::ofstream(dir / "a.bssrdf") << "z"; }
    EXPECT_FALSE(wokenWithin(3, 200)) << "woken after the wake was stopped";
    fs::remove_all(dir);
}
