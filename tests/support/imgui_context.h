// An ImGui context for tests that run real ImGui frames without a window or GL: no ini file,
// a fixed display size and frame time, and the font atlas built (NewFrame needs it). Made in a
// fixture's SetUp and destroyed with the fixture.
#pragma once

#include <imgui.h>

namespace testsupport {

class ImGuiContextForTest {
  public:
    ImGuiContextForTest(ImVec2 display, float deltaTime) {
        ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr;
        io.DisplaySize = display;
        io.DeltaTime = deltaTime;
        unsigned char* pixels = nullptr;
        int w = 0, h = 0;
        io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    }
    ~ImGuiContextForTest() { ImGui::DestroyContext(); }
    ImGuiContextForTest(const ImGuiContextForTest&) = delete;
    ImGuiContextForTest& operator=(const ImGuiContextForTest&) = delete;
};

} // namespace testsupport
