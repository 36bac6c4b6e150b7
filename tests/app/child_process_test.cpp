// Child processes (app/probe/child_process.h) wake a loop that sleeps between frames when they
// write (app/probe/output_wake.h): once per arrival, not again while nothing new comes, and not
// after the wake is cleared.
#include "probe/child_process.h"
#include "probe/output_wake.h"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace {
using namespace std::chrono_literals;

struct Wakes {
    std::mutex mutex;
    std::condition_variable cv;
    int count = 0;
    void wake() {
        {
            std::lock_guard<std::mutex> lock(mutex);
            ++count;
        }
        cv.notify_all();
    }
    // Waits (at most 20 s) for more than `seen` wakes; returns the count.
    int waitBeyond(int seen) {
        std::unique_lock<std::mutex> lock(mutex);
        cv.wait_for(lock, 20s, [&] { return count > seen; });
        return count;
    }
    int now() {
        std::lock_guard<std::mutex> lock(mutex);
        return count;
    }
};

// Polls until the child has ended (at most 20 s).
void reap(app::ChildProcess& child) {
    for (int i = 0; i < 4000 && !child.poll(); ++i)
        std::this_thread::sleep_for(5ms);
    ASSERT_TRUE(child.done());
}

TEST(ChildOutputWake, EachWriteWakesTheLoopOnceAndAnEndedChildNoMore) {
    Wakes wakes;
    app::wakeOnChildOutput([&] { wakes.wake(); });
    app::ChildProcess child({"/bin/sh", "-c", "sleep 0.3; echo first; sleep 0.3; echo second"},
                            "sh");
    const int first = wakes.waitBeyond(0);
    ASSERT_GE(first, 1) << "no wake for the child's first line";
    EXPECT_FALSE(child.poll());
    EXPECT_EQ(child.output(), "first\n");
    // nothing new until the second line: the unread-then-read pipe does not wake again
    std::this_thread::sleep_for(100ms);
    EXPECT_EQ(wakes.now(), first);

    const int second = wakes.waitBeyond(first);
    ASSERT_GT(second, first) << "no wake for the child's second line";
    reap(child);
    EXPECT_EQ(child.output(), "first\nsecond\n");
    EXPECT_EQ(child.exitCode(), 0);
    // the ended child's pipe has left the set; edge-triggered events do not repeat (an event of
    // its end may still be on its way to the thread for a moment)
    std::this_thread::sleep_for(100ms);
    const int ended = wakes.now();
    std::this_thread::sleep_for(200ms);
    EXPECT_EQ(wakes.now(), ended);

    // cleared: a child that writes wakes nothing
    app::wakeOnChildOutput({});
    app::ChildProcess quiet({"/bin/sh", "-c", "echo unheard"}, "sh");
    reap(quiet);
    EXPECT_EQ(quiet.output(), "unheard\n");
    EXPECT_EQ(wakes.now(), ended);
}

TEST(ChildOutputWake, AKilledChildWakesAndLeavesTheSet) {
    Wakes wakes;
    app::wakeOnChildOutput([&] { wakes.wake(); });
    {
        app::ChildProcess child({"/bin/sh", "-c", "echo started; exec sleep 30"}, "sh");
        ASSERT_GE(wakes.waitBeyond(0), 1);
        EXPECT_FALSE(child.poll());
        EXPECT_EQ(child.output(), "started\n");
        child.cancel();
        EXPECT_TRUE(child.done());
        EXPECT_EQ(child.exitCode(), 128 + 9);
    }
    // its pipe is closed now: the set forgets it (the kill's event may still be on its way)
    std::this_thread::sleep_for(100ms);
    const int after = wakes.now();
    std::this_thread::sleep_for(200ms);
    EXPECT_EQ(wakes.now(), after);
    app::wakeOnChildOutput({});
}

} // namespace
