// Mouse clicks as their events had them (mouse_clicks.h).
#include "gui/mouse_clicks.h"

#include <GLFW/glfw3.h>

#include <cfloat>
#include <cmath>
#include <deque>

namespace app {
namespace {

constexpr int kButtons = 3; // left, right, middle: the ones the panels read

struct Press {
    double seconds; // event time
    ImVec2 pos;     // the pointer then, UI units
};

GLFWwindow* g_mouseWindow = nullptr;
GLFWmousebuttonfun g_mouseBackend = nullptr;  // the backend's callback, which this one calls first
float g_unitsPerCoordinate = 1.0f;            // as the last frame had it
std::deque<Press> g_pendingPresses[kButtons]; // presses not yet shown
double g_lastShownPress[kButtons] = {};       // the event time of the press last shown
bool g_anyPressShown[kButtons] = {};

void onButton(GLFWwindow* win, int button, int action, int mods) {
    if (g_mouseBackend) g_mouseBackend(win, button, action, mods);
    if (action != GLFW_PRESS) return;
    double x = 0, y = 0;
    glfwGetCursorPos(win, &x, &y);
    noteMousePress(button, glfwGetTime(),
                   ImVec2(float(x) * g_unitsPerCoordinate, float(y) * g_unitsPerCoordinate));
}

void forgetPresses() {
    for (int b = 0; b < kButtons; ++b) {
        g_pendingPresses[b].clear();
        g_anyPressShown[b] = false;
    }
}

// The pixel ImGui rounds a position to (it floors io.MousePos each frame).
bool samePixel(ImVec2 a, ImVec2 b) {
    return a.x > -FLT_MAX / 2 && b.x > -FLT_MAX / 2 && std::floor(a.x) == std::floor(b.x) &&
           std::floor(a.y) == std::floor(b.y);
}

} // namespace

void installMouseClicks(GLFWwindow* win) {
    g_mouseWindow = win;
    g_mouseBackend = glfwSetMouseButtonCallback(win, onButton);
    forgetPresses();
}

void removeMouseClicks() {
    forgetPresses();
    if (!g_mouseWindow) return;
    glfwSetMouseButtonCallback(g_mouseWindow, g_mouseBackend);
    g_mouseWindow = nullptr;
    g_mouseBackend = nullptr;
}

void applyMouseClicks(GLFWwindow* win, float unitsPerCoordinate) {
    g_unitsPerCoordinate = unitsPerCoordinate;
    applyMouseClicks([win](int b) { return glfwGetMouseButton(win, b) == GLFW_PRESS; });
}

void noteMousePress(int button, double seconds, ImVec2 pos) {
    if (button >= 0 && button < kButtons) g_pendingPresses[button].push_back({seconds, pos});
}

void applyMouseClicks(const std::function<bool(int button)>& isDown) {
    ImGuiIO& io = ImGui::GetIO();
    const double frameTime = ImGui::GetTime() + double(io.DeltaTime); // ImGui's time this frame
    const ImVec2 lastPos = io.MousePosPrev; // where the pointer was in the last frame
    bool placed = false;                    // the pointer put where a press was, in this frame
    for (int b = 0; b < kButtons; ++b) {
        bool down = isDown(b);
        if (!g_pendingPresses[b].empty()) {
            const Press& p = g_pendingPresses[b].front();
            const bool here = !placed || samePixel(io.MousePos, p.pos);
            if (!placed) {
                io.MousePos = p.pos;
                placed = true;
            }
            // Down in the last frame: up in this one. Elsewhere in the last frame (or where
            // another button's press is now): up here in this one, so that the press's item is
            // hovered before it is pressed.
            if (io.MouseDownDuration[b] >= 0 || !here || !samePixel(lastPos, p.pos)) {
                down = false;
            } else {
                down = true;
                // a first click ImGui still holds (it sets its time negative after a double
                // click): the interval it measures becomes the events' own
                if (g_anyPressShown[b] && io.MouseClickedTime[b] >= 0)
                    io.MouseClickedTime[b] = frameTime - (p.seconds - g_lastShownPress[b]);
                g_lastShownPress[b] = p.seconds;
                g_anyPressShown[b] = true;
                g_pendingPresses[b].pop_front();
            }
        }
        io.MouseDown[b] = down;
    }
}

} // namespace app
