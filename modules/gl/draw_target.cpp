// gl: ScopedDrawTarget (gl.h): the fixed-function state of an offscreen, opaque, depth-tested
// draw, set on entry and restored on leaving, so that no pass leaves its state to the next.
#include "gl.h"

namespace gl {

ScopedDrawTarget::ScopedDrawTarget(GLuint framebuffer, int width, int height) {
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &m_framebuffer);
    glGetIntegerv(GL_VIEWPORT, m_viewport);
    glGetIntegerv(GL_DEPTH_FUNC, &m_depthFunc);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &m_depthMask);
    m_depthTest = glIsEnabled(GL_DEPTH_TEST);
    m_cull = glIsEnabled(GL_CULL_FACE);
    m_blend = glIsEnabled(GL_BLEND);
    m_scissor = glIsEnabled(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
}

ScopedDrawTarget::~ScopedDrawTarget() {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(m_framebuffer));
    glViewport(m_viewport[0], m_viewport[1], m_viewport[2], m_viewport[3]);
    glDepthFunc(static_cast<GLenum>(m_depthFunc));
    glDepthMask(m_depthMask);
    const auto restore = [](GLenum cap, GLboolean on) { on ? glEnable(cap) : glDisable(cap); };
    restore(GL_DEPTH_TEST, m_depthTest);
    restore(GL_CULL_FACE, m_cull);
    restore(GL_BLEND, m_blend);
    restore(GL_SCISSOR_TEST, m_scissor);
}

} // namespace gl
