// Mouse clicks as their events had them (gui/mouse_clicks.h) with real ImGui frames and no
// window, at 0.4 s a frame (the scene rendering on llvmpipe): two clicks 0.15 s apart are a double
// click whether they fall in one frame or in two; 0.5 s apart they are two single clicks; three
// quick clicks are one double click, not two; a click right after the pointer moved from a button
// onto a tab selects the tab; a press is where it was, not where the pointer is by the frame.
#include "gui/mouse_clicks.h"

#include "../support/imgui_context.h"

#include <gtest/gtest.h>
#include <imgui.h>

#include <vector>

namespace {

class MouseClicks : public ::testing::Test {
  protected:
    static inline const ImVec2 kAt{50, 50}; // the pointer, unless a test moves it
    void SetUp() override {
        ImGui::GetIO().MousePos = kAt;
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
                app::noteMousePress(0, 100.0 + times[next++], kAt);
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

ImVec2 inside(ImVec2 itemMin) {
    return ImVec2(itemMin.x + 4, itemMin.y + 4);
}

// A window with two tabs above a button; which tab shows, and where tab B and the button are.
struct TabsAndButton {
    char shown = 0;
    ImVec2 tabB, button;
};
TabsAndButton tabsAndButton() {
    TabsAndButton t;
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(ImVec2(200, 100));
    ImGui::Begin("tabs", nullptr, ImGuiWindowFlags_NoDecoration);
    if (ImGui::BeginTabBar("bar")) {
        for (const char* name : {"A", "B"}) {
            const bool open = ImGui::BeginTabItem(name);
            if (*name == 'B') t.tabB = inside(ImGui::GetItemRectMin());
            if (open) {
                t.shown = *name;
                ImGui::EndTabItem();
            }
        }
        ImGui::EndTabBar();
    }
    ImGui::Button("button");
    t.button = inside(ImGui::GetItemRectMin());
    ImGui::End();
    ImGui::EndFrame();
    return t;
}

TEST_F(MouseClicks, AClickRightAfterMovingFromAButtonOntoATabSelectsIt) {
    ImGuiIO& io = ImGui::GetIO();
    TabsAndButton t;
    for (int f = 0; f < 3; ++f) // the tab bar laid out
        t = tabsAndButton();
    ASSERT_EQ(t.shown, 'A');
    io.MousePos = t.button; // the button hovered
    app::applyMouseClicks([](int) { return false; });
    tabsAndButton();
    // moved onto tab B and clicked there, all between two frames
    io.MousePos = t.tabB;
    app::noteMousePress(0, 100.0, t.tabB);
    for (int f = 0; f < 4; ++f) {
        app::applyMouseClicks([](int) { return false; });
        t = tabsAndButton();
    }
    EXPECT_EQ(t.shown, 'B');
}

TEST_F(MouseClicks, APressIsWhereItWasNotWhereThePointerIsByTheFrame) {
    ImGuiIO& io = ImGui::GetIO();
    app::noteMousePress(0, 100.0, kAt);
    io.MousePos = ImVec2(150, 80); // dragged on before the frame
    bool clicked = false;
    for (int f = 0; f < 3 && !clicked; ++f) {
        app::applyMouseClicks([](int) { return true; }); // still held
        ImGui::NewFrame();
        clicked = ImGui::IsMouseClicked(0);
        ImGui::EndFrame();
        if (clicked) {
            EXPECT_EQ(io.MouseClickedPos[0].x, kAt.x);
            EXPECT_EQ(io.MouseClickedPos[0].y, kAt.y);
        }
        io.MousePos = ImVec2(150, 80); // the pointer as the backend reads it
    }
    EXPECT_TRUE(clicked);
}

} // namespace
