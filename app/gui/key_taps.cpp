// Key taps shorter than a frame (key_taps.h).
#include "gui/key_taps.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <vector>

namespace app {
namespace {

struct Tap {
    int key = 0;
    int mods = 0; // GLFW_MOD_* at the press
};
GLFWwindow* g_window = nullptr;
GLFWkeyfun g_backend = nullptr; // the backend's callback, which this one calls first
std::vector<Tap> g_taps;        // pressed since the last frame (or waiting for their turn)
std::vector<int> g_held;        // keys down in the last frame only because of a tap
bool g_heldMods = false;        // and the modifiers with them

bool inRange(int key) {
    return key >= 0 && key < int(IM_ARRAYSIZE(ImGui::GetIO().KeysDown));
}

void onKey(GLFWwindow* win, int key, int scancode, int action, int mods) {
    if (g_backend) g_backend(win, key, scancode, action, mods);
    if (action == GLFW_PRESS) noteKeyPress(key, mods);
}

} // namespace

void installKeyTaps(GLFWwindow* win) {
    g_window = win;
    g_backend = glfwSetKeyCallback(win, onKey);
    g_taps.clear();
    g_held.clear();
    g_heldMods = false;
}

void removeKeyTaps() {
    if (!g_window) return;
    glfwSetKeyCallback(g_window, g_backend);
    g_window = nullptr;
    g_backend = nullptr;
    g_taps.clear();
    g_held.clear();
}

void applyKeyTaps(GLFWwindow* win) {
    applyKeyTaps([win](int key) { return glfwGetKey(win, key) == GLFW_PRESS; });
}

void noteKeyPress(int key, int mods) {
    if (inRange(key)) g_taps.push_back({key, mods});
}

void applyKeyTaps(const std::function<bool(int key)>& isDown) {
    ImGuiIO& io = ImGui::GetIO();
    for (int key : g_held)
        io.KeysDown[key] = isDown(key);
    const std::vector<int> released = std::move(g_held);
    g_held.clear();
    if (g_heldMods) { // as the backend sets them, from the keys' state
        io.KeyCtrl = io.KeysDown[GLFW_KEY_LEFT_CONTROL] || io.KeysDown[GLFW_KEY_RIGHT_CONTROL];
        io.KeyShift = io.KeysDown[GLFW_KEY_LEFT_SHIFT] || io.KeysDown[GLFW_KEY_RIGHT_SHIFT];
        io.KeyAlt = io.KeysDown[GLFW_KEY_LEFT_ALT] || io.KeysDown[GLFW_KEY_RIGHT_ALT];
        io.KeySuper = io.KeysDown[GLFW_KEY_LEFT_SUPER] || io.KeysDown[GLFW_KEY_RIGHT_SUPER];
        g_heldMods = false;
    }
    // A key tapped again before its last tap was shown up for a frame waits: ImGui sees a press
    // only where the key was up in the frame before.
    const auto among = [](const std::vector<int>& keys, int key) {
        return std::find(keys.begin(), keys.end(), key) != keys.end();
    };
    std::vector<Tap> later;
    for (const Tap& t : g_taps) {
        if (among(released, t.key) || among(g_held, t.key)) {
            later.push_back(t);
            continue;
        }
        if (io.KeysDown[t.key]) continue; // still down: the backend has it
        io.KeysDown[t.key] = true;
        g_held.push_back(t.key);
        io.KeyCtrl |= (t.mods & GLFW_MOD_CONTROL) != 0;
        io.KeyShift |= (t.mods & GLFW_MOD_SHIFT) != 0;
        io.KeyAlt |= (t.mods & GLFW_MOD_ALT) != 0;
        io.KeySuper |= (t.mods & GLFW_MOD_SUPER) != 0;
        g_heldMods = true;
    }
    g_taps = std::move(later);
}

} // namespace app
