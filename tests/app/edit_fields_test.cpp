// The panels' edit fields commit when the edit is done (Enter or focus loss), not per key,
// with real ImGui input (mouse, characters, keys) and no GL: typing "42" into an integer field
// changes nothing until Enter; typing and clicking elsewhere commits; the step buttons commit
// at once; a text field commits on focus loss, and Enter on an unchanged name commits too.
#include "gui/widgets.h"

#include "../support/imgui_context.h"

#include <gtest/gtest.h>

#include <imgui.h>

#include <functional>

namespace {

constexpr int kEnter = 1, kBackspace = 2, kEnd = 3; // our key codes in io.KeysDown

class Fields : public ::testing::Test {
  protected:
    void SetUp() override {
        ImGuiIO& io = ImGui::GetIO();
        io.KeyMap[ImGuiKey_Enter] = kEnter;
        io.KeyMap[ImGuiKey_KeyPadEnter] = kEnter;
        io.KeyMap[ImGuiKey_Backspace] = kBackspace;
        io.KeyMap[ImGuiKey_End] = kEnd;
    }
    testsupport::ImGuiContextForTest imgui{ImVec2(500, 300), 1.0f / 60.0f};

    // One frame drawing `body` in a window at the origin; returns the last item's rectangle.
    ImVec4 frame(const std::function<void()>& body) {
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImVec2(500, 300));
        ImGui::Begin("fields");
        body();
        const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
        ImGui::End();
        ImGui::EndFrame();
        for (bool& k : ImGui::GetIO().KeysDown)
            k = false;
        return ImVec4(a.x, a.y, b.x, b.y);
    }
    void mouse(float x, float y, bool down) {
        ImGui::GetIO().MousePos = ImVec2(x, y);
        ImGui::GetIO().MouseDown[0] = down;
    }
    void key(int k) { ImGui::GetIO().KeysDown[k] = true; }
    // A click (press, release) at (x, y), a frame each.
    void click(float x, float y, const std::function<void()>& body) {
        mouse(x, y, true);
        frame(body);
        mouse(x, y, false);
        frame(body);
    }
    void type(const char* s) { ImGui::GetIO().AddInputCharactersUTF8(s); }
};

} // namespace

TEST_F(Fields, IntegerFieldCommitsOnEnterAndFocusLossNotPerKey) {
    int value = 5, commits = 0;
    auto body = [&] {
        ImGui::SetNextItemWidth(200);
        commits += app::inputIntCommitted("n", &value, 1, 10) ? 1 : 0;
    };
    const ImVec4 r = frame(body); // the group: the text field, then the - and + buttons
    const float tx = r.x + 20, ty = (r.y + r.w) * 0.5f;
    // click into the text, go to its end, replace "5" by "42"
    click(tx, ty, body);
    key(kEnd);
    frame(body);
    key(kBackspace);
    frame(body);
    type("42");
    frame(body);
    frame(body);
    EXPECT_EQ(value, 5); // typed, not committed
    EXPECT_EQ(commits, 0);
    key(kEnter);
    frame(body);
    frame(body);
    EXPECT_EQ(value, 42);
    EXPECT_EQ(commits, 1);

    // typing then clicking elsewhere commits as well
    click(tx, ty, body);
    key(kEnd);
    frame(body);
    type("7");
    frame(body);
    EXPECT_EQ(value, 42);
    mouse(450, 250, true); // empty space of the window
    frame(body);
    mouse(450, 250, false);
    frame(body);
    frame(body);
    EXPECT_EQ(value, 427);
    EXPECT_EQ(commits, 2);

    // the + button (the right end of the 200 px wide field, before its label) commits at once
    click(r.x + 200 - 9, ty, body);
    EXPECT_EQ(value, 428);
    EXPECT_EQ(commits, 3);
}

TEST_F(Fields, TextFieldCommitsOnFocusLossAndOnEnterUnchanged) {
    char buffer[64] = "a.obj";
    int commits = 0;
    auto body = [&] {
        ImGui::SetNextItemWidth(200);
        commits += app::inputTextCommitted("mesh", buffer, sizeof buffer) ? 1 : 0;
    };
    const ImVec4 r = frame(body);
    const float tx = r.x + 100, ty = (r.y + r.w) * 0.5f;
    click(tx, ty, body);
    key(kEnd);
    frame(body);
    type("x");
    frame(body);
    EXPECT_EQ(commits, 0);
    click(450, 250, body);
    EXPECT_EQ(commits, 1);
    EXPECT_STREQ(buffer, "a.objx");
    // Enter without an edit: read the same file again
    click(tx, ty, body);
    key(kEnter);
    frame(body);
    EXPECT_EQ(commits, 2);
}
