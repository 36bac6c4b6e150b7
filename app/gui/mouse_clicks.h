// Mouse clicks timed by their events. ImGui 1.86 sees at most one press of a button a frame (its
// GLFW backend keeps a press as one bool until the next frame) and times a double click by frame
// time: two clicks 150 ms apart make a double click only if they fall in different frames that
// began less than io.MouseDoubleClickTime (0.3 s) apart. When frames take longer (the scene
// rendering on llvmpipe), a double click (the file dialog's, to enter a folder or open a file)
// was a single click. Written by hand, as key_taps.h is and for the same reason (Debian 12 has
// ImGui 1.86, without 1.87's input queue): a button callback in front of the backend's notes each
// press with its event time; a press is shown in a frame after one with the button up (so a
// second press within one frame comes two frames later), and a press that follows another has
// ImGui's time of the first set back so that the interval it measures is the events' own.
#pragma once

#include <functional>

struct GLFWwindow;

namespace app {

// Puts the note-taking callback in front of the backend's (after ImGui_ImplGlfw_InitForOpenGL).
void installMouseClicks(GLFWwindow* win);
// Gives the window back the backend's callback (before ImGui_ImplGlfw_Shutdown; again: nothing)
// and forgets the presses noted.
void removeMouseClicks();
// Between ImGui_ImplGlfw_NewFrame and ImGui::NewFrame: each button as GLFW has it, except that a
// press noted since is down in this frame (up first if it was down in the last).
void applyMouseClicks(GLFWwindow* win);

// The same without a window: a press of `button` at `seconds` (any clock: only differences
// count), and the frame's step with `isDown` giving a button's state now.
void noteMousePress(int button, double seconds);
void applyMouseClicks(const std::function<bool(int button)>& isDown);

} // namespace app
