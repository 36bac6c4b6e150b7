// The windowed loop's pacing (frame_pacing.h).
#include "gui/frame_pacing.h"

namespace app {

double FramePacing::nextWait() const {
    return m_idle ? kIdleWaitSeconds : kFrameWaitSeconds;
}

void FramePacing::waited(double asked, double took, double now) {
    // glfwWaitEventsTimeout returns within a millisecond of its timeout when nothing came
    constexpr double kEarly = 0.002;
    if (took < asked - kEarly) m_lastMove = now;
}

void FramePacing::framed(bool moving, double now) {
    if (moving) m_lastMove = now;
    m_idle = now - m_lastMove > kSettleSeconds;
}

} // namespace app
