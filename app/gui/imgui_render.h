// gui/imgui_render.h: ImGui's OpenGL 3 backend drawing the frame, after the barrier checks
// (gl/hazards.cpp) have looked at every texture it is about to sample: the stages write their
// pictures with image stores, and ImGui's draws read them through samplers, which needs
// GL_TEXTURE_FETCH_BARRIER_BIT in between (ImGui's backend calls GL through its own loader, so
// the checks cannot see its draws).
#pragma once

namespace app {

void renderImGuiDrawData();

} // namespace app
