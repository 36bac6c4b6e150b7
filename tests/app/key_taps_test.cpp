// Key taps shorter than a frame (gui/key_taps.h) with real ImGui input and no window: a tap
// (pressed and released before the frame) is a press in the next frame with its modifiers, up
// in the one after; two taps of one key within a frame are two presses with the key up between;
// a key still held stays as it is.
#include "gui/key_taps.h"

#include "../support/imgui_context.h"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>
#include <imgui.h>

#include <set>

namespace {

class KeyTaps : public ::testing::Test {
  protected:
    void SetUp() override {
        app::applyKeyTaps([](int) { return false; }); // nothing left from another test
        ImGui::NewFrame();
        ImGui::EndFrame();
    }
    testsupport::ImGuiContextForTest imgui{ImVec2(200, 100), 1.0f / 60.0f};

    struct Seen {
        bool pressed, down, ctrl;
    };
    // One frame with the keys in `held` down now; what ImGui says of `key` in it.
    Seen frame(int key) {
        app::applyKeyTaps([this](int k) { return held.count(k) > 0; });
        ImGui::NewFrame();
        const Seen s{ImGui::IsKeyPressed(key, false), ImGui::IsKeyDown(key),
                     ImGui::GetIO().KeyCtrl};
        ImGui::EndFrame();
        return s;
    }
    std::set<int> held;
};

TEST_F(KeyTaps, ATapIsAPressInTheNextFrameWithItsModifiers) {
    app::noteKeyPress(GLFW_KEY_Q, GLFW_MOD_CONTROL); // pressed and released: io never saw it
    Seen s = frame(GLFW_KEY_Q);
    EXPECT_TRUE(s.pressed);
    EXPECT_TRUE(s.ctrl);
    s = frame(GLFW_KEY_Q);
    EXPECT_FALSE(s.down);
    EXPECT_FALSE(s.ctrl);
}

TEST_F(KeyTaps, TwoTapsWithinAFrameAreTwoPresses) {
    app::noteKeyPress(GLFW_KEY_BACKSPACE, 0);
    app::noteKeyPress(GLFW_KEY_BACKSPACE, 0);
    int presses = 0;
    bool upBetween = false;
    for (int f = 0; f < 4; ++f) {
        const Seen s = frame(GLFW_KEY_BACKSPACE);
        presses += s.pressed;
        upBetween |= presses == 1 && !s.down;
    }
    EXPECT_EQ(presses, 2);
    EXPECT_TRUE(upBetween);
}

TEST_F(KeyTaps, AKeyStillHeldIsLeftAsItIs) {
    ImGui::GetIO().KeysDown[GLFW_KEY_A] = true; // as the backend sets it: pressed, not released
    held.insert(GLFW_KEY_A);
    app::noteKeyPress(GLFW_KEY_A, 0);
    EXPECT_TRUE(frame(GLFW_KEY_A).pressed);
    EXPECT_TRUE(frame(GLFW_KEY_A).down); // held: still down, and not pressed again
    EXPECT_FALSE(frame(GLFW_KEY_A).pressed);
}

} // namespace
