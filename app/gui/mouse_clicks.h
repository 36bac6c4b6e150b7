// Mouse clicks as their events had them. ImGui 1.86 sees at most one press of a button a frame
// (its GLFW backend keeps a press as one bool until the next frame), times a double click by
// frame time, and reads the pointer once a frame. When frames take longer than a click (the scene
// rendering on llvmpipe):
// - a double click (the file dialog's, to enter a folder or open a file) was two single clicks:
//   two clicks 150 ms apart make a double click only if they fall in frames that began less
//   than io.MouseDoubleClickTime (0.3 s) apart;
// - a click right after the pointer moved onto a tab (or any item that allows overlap) was lost:
//   ImGui takes such an item's click only if the item, or nothing, was hovered in the frame
//   before, and in that frame the pointer was still where it came from.
// Written by hand, as key_taps.h is and for the same reason (Debian 12 has ImGui 1.86, without
// 1.87's input queue): a button callback in front of the backend's notes each press with its
// event time and the pointer's position then; a press is shown in a frame that follows one with
// the button up and the pointer where the press was (so a click after a move comes a frame
// later, the frame between hovering its item; a second press within one frame comes two frames
// later), at the press's position, and a press that follows another has ImGui's time of the
// first set back so that the interval it measures is the events' own.
#pragma once

#include <imgui.h>

#include <functional>

struct GLFWwindow;

namespace app {

// Puts the note-taking callback in front of the backend's (after ImGui_ImplGlfw_InitForOpenGL).
void installMouseClicks(GLFWwindow* win);
// Gives the window back the backend's callback (before ImGui_ImplGlfw_Shutdown; again: nothing)
// and forgets the presses noted.
void removeMouseClicks();
// After the GLFW backend's NewFrame and the UI scale (io.MousePos in UI units), before
// ImGui::NewFrame: each button as GLFW has it, except that a press noted since is down in this
// frame at its own position if the last frame had the button up and the pointer there; else
// this frame has the button up and the pointer there, and the press waits for the next.
// `unitsPerCoordinate`: UI units per window coordinate (the window's positions into io's).
void applyMouseClicks(GLFWwindow* win, float unitsPerCoordinate);

// The same without a window: a press of `button` at `seconds` (any clock: only differences
// count) with the pointer at `pos` (UI units), and the frame's step with `isDown` giving a
// button's state now.
void noteMousePress(int button, double seconds, ImVec2 pos);
void applyMouseClicks(const std::function<bool(int button)>& isDown);

} // namespace app
