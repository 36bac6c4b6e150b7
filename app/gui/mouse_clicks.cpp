// Mouse clicks timed by their events (mouse_clicks.h).
#include "gui/mouse_clicks.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <deque>

namespace app {
namespace {

constexpr int kButtons = 3; // left, right, middle: the ones the panels read
GLFWwindow* g_mouseWindow = nullptr;
GLFWmousebuttonfun g_mouseBackend = nullptr;   // the backend's callback, which this one calls first
std::deque<double> g_pendingPresses[kButtons]; // presses not yet shown, their event times
double g_lastShownPress[kButtons] = {};        // the event time of the press last shown
bool g_anyPressShown[kButtons] = {};

void onButton(GLFWwindow* win, int button, int action, int mods) {
    if (g_mouseBackend) g_mouseBackend(win, button, action, mods);
    if (action == GLFW_PRESS) noteMousePress(button, glfwGetTime());
}

void forgetPresses() {
    for (int b = 0; b < kButtons; ++b) {
        g_pendingPresses[b].clear();
        g_anyPressShown[b] = false;
    }
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

void applyMouseClicks(GLFWwindow* win) {
    applyMouseClicks([win](int b) { return glfwGetMouseButton(win, b) == GLFW_PRESS; });
}

void noteMousePress(int button, double seconds) {
    if (button >= 0 && button < kButtons) g_pendingPresses[button].push_back(seconds);
}

void applyMouseClicks(const std::function<bool(int button)>& isDown) {
    ImGuiIO& io = ImGui::GetIO();
    const double frameTime = ImGui::GetTime() + double(io.DeltaTime); // ImGui's time this frame
    for (int b = 0; b < kButtons; ++b) {
        bool down = isDown(b);
        if (!g_pendingPresses[b].empty()) {
            if (io.MouseDownDuration[b] >= 0) {
                down = false; // down in the last frame: up in this one, the press in the next
            } else {
                down = true;
                const double t = g_pendingPresses[b].front();
                g_pendingPresses[b].pop_front();
                // a first click ImGui still holds (it sets its time negative after a double
                // click): the interval it measures becomes the events' own
                if (g_anyPressShown[b] && io.MouseClickedTime[b] >= 0)
                    io.MouseClickedTime[b] = frameTime - (t - g_lastShownPress[b]);
                g_lastShownPress[b] = t;
                g_anyPressShown[b] = true;
            }
        }
        io.MouseDown[b] = down;
    }
}

} // namespace app
