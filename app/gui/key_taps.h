// Key taps shorter than a frame. ImGui 1.86's GLFW backend (Debian's libimgui) sets a key's
// io.KeysDown to its last event, so a key pressed and released between two frames is never seen
// down: a shortcut typed quickly (Ctrl+Q, Ctrl+O, Escape) is lost whenever a frame takes longer
// than the tap, as frames do on llvmpipe while the scene renders. The backend keeps a mouse
// button that was pressed down for one frame (its MouseJustPressed) but not a key; ImGui 1.87's
// input queue does, which Debian 12 does not have. Written by hand for that: a key callback in
// front of the backend's notes each press with its modifiers, and the next frame sees the key
// down (with those modifiers) for that frame.
#pragma once

#include <functional>

struct GLFWwindow;

namespace app {

// Puts the note-taking callback in front of the backend's (after ImGui_ImplGlfw_InitForOpenGL).
void installKeyTaps(GLFWwindow* win);
// Gives the window back the backend's callback (before ImGui_ImplGlfw_Shutdown); again: nothing.
void removeKeyTaps();
// Between ImGui_ImplGlfw_NewFrame and ImGui::NewFrame: a key pressed since the last frame is down
// in this one, with the modifiers it was pressed with; one that was down only for that reason is
// set back to GLFW's state of it in the next. A key tapped twice within a frame is down in two
// frames with one up between them: two presses.
void applyKeyTaps(GLFWwindow* win);

// What the two above do, without a window: a press (GLFW key code, GLFW_MOD_* bits) as the
// callback notes it, and the frame's step with `isDown` giving a key's state now.
void noteKeyPress(int key, int mods);
void applyKeyTaps(const std::function<bool(int key)>& isDown);

} // namespace app
