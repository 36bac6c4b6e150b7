// The windowed loop's pacing (gui/frame_pacing.h) on a clock of the test's own: the full rate
// while anything moves and for kSettleSeconds after, a frame every kIdleWaitSeconds after that,
// and the full rate again from the first event or wake.
#include "gui/frame_pacing.h"

#include <gtest/gtest.h>

namespace {

// One turn of the loop at `now`: a wait of `took` seconds (the whole wait asked for unless an
// event came), then a frame in which `moving` held. Returns the time after it.
double turn(app::FramePacing& p, double now, bool moving, bool event = false) {
    const double asked = p.nextWait();
    const double took = event ? 0.25 * asked : asked;
    now += took;
    p.waited(asked, took, now);
    now += 0.005; // the frame
    p.framed(moving, now);
    return now;
}

} // namespace

TEST(FramePacing, FullRateWhileMovingThenIdleUntilAnEvent) {
    app::FramePacing p;
    double t = 100.0;
    EXPECT_DOUBLE_EQ(p.nextWait(), app::kFrameWaitSeconds); // the first frames at the full rate
    for (int i = 0; i < 100; ++i) {                         // work under way for ~3.5 s
        t = turn(p, t, true);
        EXPECT_DOUBLE_EQ(p.nextWait(), app::kFrameWaitSeconds) << "frame " << i;
    }
    // the work done: the full rate for kSettleSeconds more, then idle
    const double done = t;
    while (!p.idle()) {
        t = turn(p, t, false);
        ASSERT_LT(t - done, app::kSettleSeconds + 2 * app::kFrameWaitSeconds);
    }
    EXPECT_GE(t - done, app::kSettleSeconds);
    EXPECT_DOUBLE_EQ(p.nextWait(), app::kIdleWaitSeconds);
    for (int i = 0; i < 20; ++i) // nothing moves: a frame every kIdleWaitSeconds
        t = turn(p, t, false);
    EXPECT_TRUE(p.idle());
    // an event (the wait ends early) brings the full rate back for kSettleSeconds
    t = turn(p, t, false, true);
    EXPECT_FALSE(p.idle());
    EXPECT_DOUBLE_EQ(p.nextWait(), app::kFrameWaitSeconds);
    const double event = t;
    while (!p.idle())
        t = turn(p, t, false);
    EXPECT_GE(t - event, app::kSettleSeconds);
}

TEST(FramePacing, AnythingMovingInAnIdleFrameBringsTheFullRateBack) {
    app::FramePacing p;
    double t = 0;
    while (!p.idle())
        t = turn(p, t, false);
    t = turn(p, t, true); // a worker's result changed the workbench in an idle frame
    EXPECT_DOUBLE_EQ(p.nextWait(), app::kFrameWaitSeconds);
}
