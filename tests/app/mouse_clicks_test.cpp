// Mouse clicks timed by their events (gui/mouse_clicks.h) with real ImGui frames and no window,
// at 0.4 s a frame (the scene rendering on llvmpipe): two clicks 0.15 s apart are a double click
// whether they fall in one frame or in two; 0.5 s apart they are two single clicks; three quick
// clicks are one double click, not two.
#include "gui/mouse_clicks.h"

#include "../support/imgui_context.h"

#include <gtest/gtest.h>
#include <imgui.h>

#include <vector>

namespace {

class MouseClicks : public ::testing::Test {
  protected:
    void SetUp() override {
        ImGui::GetIO().MousePos = ImVec2(50, 50);
        app::removeMouseClicks(); // nothing left from another test
        for (int f = 0; f < 3; ++f)
            frame();
    }
    testsupport::ImGuiContextForTest imgui{ImVec2(200, 100), 0.4f}; // 0.4 s a frame

    struct Seen {
        bool clicked, doubleClicked;
    };
    // One frame (0.4 s) with the left button up now (each click is pressed and released
    // between frames).
    Seen frame() {
        app::applyMouseClicks([](int) { return false; });
        ImGui::NewFrame();
        const Seen s{ImGui::IsMouseClicked(0), ImGui::IsMouseDoubleClicked(0)};
        ImGui::EndFrame();
        return s;
    }
    // Runs `frames` frames, the clicks at `times` (seconds after the first frame began) noted
    // before the frame they fall in; returns the clicks and double clicks ImGui saw.
    std::pair<int, int> run(const std::vector<double>& times, int frames) {
        int clicks = 0, doubles = 0;
        size_t next = 0;
        for (int f = 0; f < frames; ++f) {
            while (next < times.size() && times[next] < 0.4 * (f + 1))
                app::noteMousePress(0, 100.0 + times[next++]);
            const Seen s = frame();
            clicks += s.clicked;
            doubles += s.doubleClicked;
        }
        return {clicks, doubles};
    }
};

TEST_F(MouseClicks, TwoClicksWithinOneSlowFrameAreADoubleClick) {
    EXPECT_EQ(run({0.1, 0.25}, 6), std::make_pair(2, 1));
}

TEST_F(MouseClicks, TwoClicksInTwoSlowFramesAreADoubleClick) {
    EXPECT_EQ(run({0.3, 0.45}, 6), std::make_pair(2, 1));
}

TEST_F(MouseClicks, ClicksHalfASecondApartAreSingle) {
    EXPECT_EQ(run({0.1, 0.6}, 6), std::make_pair(2, 0));
}

TEST_F(MouseClicks, ThreeQuickClicksAreOneDoubleClick) {
    EXPECT_EQ(run({0.1, 0.2, 0.3}, 8), std::make_pair(3, 1));
}

} // namespace
