// How long the windowed frame loop waits for events before its next frame (gui.cpp). A frame
// costs the same whether or not anything on screen moves (llvmpipe draws the 1600x1000 window
// in ~30 ms of CPU: a window that drew every kFrameWaitSeconds kept three quarters of a core busy
// while nobody touched it), so the loop draws at that rate only while something moves, and
// otherwise once every kIdleWaitSeconds:
//   - moving: input or a wake (a save, a child's output) in the last kSettleSeconds (ImGui lays
//     out a new window over two frames and a hovered item's tooltip follows the pointer); the
//     workbench changed something in its last update or has work under way (Workbench::working:
//     a stage running, a model under its check); a text field taking input (its caret blinks);
//   - idle: still a frame every kIdleWaitSeconds, so what changes without an event (an Errors
//     entry that expires, a worker thread's result) shows within that.
// Any event or wake ends either wait at once: idling never delays an answer to the user.
// Written by hand: GLFW only offers the wait (glfwWaitEventsTimeout), not when to use it.
#pragma once

namespace app {

inline constexpr double kFrameWaitSeconds = 0.03; // the wait while anything moves
inline constexpr double kIdleWaitSeconds = 0.25;  // the wait while nothing does
inline constexpr double kSettleSeconds = 1.0;     // frames at the full rate after an event

class FramePacing {
  public:
    // The wait to ask glfwWaitEventsTimeout for before the next frame.
    double nextWait() const;
    // After that wait: `asked` seconds were asked for and `took` passed, ending at `now` (seconds
    // on any steady clock). A wait that ended before its time was ended by an event or a wake.
    void waited(double asked, double took, double now);
    // After a frame at `now`: whether anything moved in it (see above).
    void framed(bool moving, double now);
    bool idle() const { return m_idle; }

  private:
    double m_lastMove = -1e300;
    bool m_idle = false;
};

} // namespace app
