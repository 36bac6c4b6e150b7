// 3D inspector view (scene_view.h).
#include "gui/scene_view.h"

#include "core/core.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace app {
namespace {

const char* kPointVs = R"(#version 450
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 color;
uniform mat4 ViewProj;
uniform float PointSize;
out vec3 vColor;
void main() {
    gl_Position = ViewProj * vec4(position, 1.0);
    gl_PointSize = PointSize;
    vColor = color;
})";
const char* kPointFs = R"(#version 450
in vec3 vColor;
out vec4 fragColor;
void main() {
    vec2 q = gl_PointCoord * 2.0 - 1.0;
    if (dot(q, q) > 1.0) discard;
    fragColor = vec4(vColor, 1.0);
})";
const char* kLineVs = R"(#version 450
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 color;
uniform mat4 ViewProj;
out vec3 vColor;
void main() {
    gl_Position = ViewProj * vec4(position, 1.0);
    vColor = color;
})";
const char* kLineFs = R"(#version 450
in vec3 vColor;
out vec4 fragColor;
void main() { fragColor = vec4(vColor, 1.0); })";

void setupInterleaved(gl::VertexArray& vao, const gl::Buffer& buffer) {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    vao = gl::VertexArray(id);
    glVertexArrayVertexBuffer(id, 0, buffer.id(), 0, 6 * sizeof(float));
    for (GLuint a = 0; a < 2; ++a) {
        glEnableVertexArrayAttrib(id, a);
        glVertexArrayAttribFormat(id, a, 3, GL_FLOAT, GL_FALSE, a * 3 * sizeof(float));
        glVertexArrayAttribBinding(id, a, 0);
    }
}

} // namespace

void SceneView::ensurePrograms() {
    if (m_pointProgram) return;
    m_pointProgram =
        gl::buildProgram({{GL_VERTEX_SHADER, kPointVs}, {GL_FRAGMENT_SHADER, kPointFs}});
    m_lineProgram = gl::buildProgram({{GL_VERTEX_SHADER, kLineVs}, {GL_FRAGMENT_SHADER, kLineFs}});
}

void SceneView::setPoints(const std::vector<glm::vec3>& positions,
                          const std::vector<glm::vec3>& colors) {
    std::vector<float> data;
    data.reserve(positions.size() * 6);
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::vec3 c = i < colors.size() ? colors[i] : glm::vec3(0.8f);
        data.insert(data.end(), {positions[i].x, positions[i].y, positions[i].z, c.x, c.y, c.z});
    }
    m_pointCount = GLsizei(positions.size());
    m_pointVao.reset();
    m_pointBuffer.reset();
    if (data.empty()) return;
    m_pointBuffer = gl::createBuffer(data.size() * sizeof(float), data.data(), 0);
    setupInterleaved(m_pointVao, m_pointBuffer);
}

void SceneView::setBoxes(const std::vector<ViewBox>& boxes) {
    static const int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                      {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    std::vector<float> data;
    data.reserve(boxes.size() * 24 * 6);
    for (const ViewBox& b : boxes) {
        glm::vec3 corner[8];
        for (int k = 0; k < 8; ++k)
            corner[k] = {k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z};
        for (const auto& e : kEdges)
            for (int end : e)
                data.insert(data.end(), {corner[end].x, corner[end].y, corner[end].z, b.color.x,
                                         b.color.y, b.color.z});
    }
    m_lineVertexCount = GLsizei(data.size() / 6);
    m_lineVao.reset();
    m_lineBuffer.reset();
    if (data.empty()) return;
    m_lineBuffer = gl::createBuffer(data.size() * sizeof(float), data.data(), 0);
    setupInterleaved(m_lineVao, m_lineBuffer);
}

void SceneView::ensureTarget(int w, int h) {
    if (w == m_width && h == m_height && m_fbo) return;
    m_width = w;
    m_height = h;
    GLuint ids[2];
    glCreateTextures(GL_TEXTURE_2D, 2, ids);
    m_color = gl::Texture(ids[0]);
    m_depth = gl::Texture(ids[1]);
    glTextureStorage2D(ids[0], 1, GL_RGBA8, w, h);
    glTextureParameteri(ids[0], GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(ids[0], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureStorage2D(ids[1], 1, GL_DEPTH_COMPONENT32F, w, h);
    GLuint fbo = 0;
    glCreateFramebuffers(1, &fbo);
    m_fbo = gl::FramebufferId(fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, ids[0], 0);
    glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, ids[1], 0);
    if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw core::Error("scene view: incomplete framebuffer");
}

void SceneView::draw(int width, int height, const glm::mat4& viewProj, float pointSizePx) {
    width = std::max(width, 1);
    height = std::max(height, 1);
    ensurePrograms();
    ensureTarget(width, height);
    GLint prevFbo = 0, prevViewport[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prevFbo);
    glGetIntegerv(GL_VIEWPORT, prevViewport);
    const GLboolean depthWas = glIsEnabled(GL_DEPTH_TEST);
    const GLboolean pointSizeWas = glIsEnabled(GL_PROGRAM_POINT_SIZE);
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    glViewport(0, 0, width, height);
    const float bg[4] = {0.11f, 0.11f, 0.13f, 1.0f};
    const float one = 1.0f;
    glClearNamedFramebufferfv(m_fbo.id(), GL_COLOR, 0, bg);
    glClearNamedFramebufferfv(m_fbo.id(), GL_DEPTH, 0, &one);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    if (m_pointCount > 0) {
        glUseProgram(m_pointProgram.id());
        glUniformMatrix4fv(gl::uniformLocation(m_pointProgram, "ViewProj"), 1, GL_FALSE,
                           &viewProj[0][0]);
        glUniform1f(gl::uniformLocation(m_pointProgram, "PointSize"), pointSizePx);
        glBindVertexArray(m_pointVao.id());
        glDrawArrays(GL_POINTS, 0, m_pointCount);
    }
    if (m_lineVertexCount > 0) {
        glUseProgram(m_lineProgram.id());
        glUniformMatrix4fv(gl::uniformLocation(m_lineProgram, "ViewProj"), 1, GL_FALSE,
                           &viewProj[0][0]);
        glBindVertexArray(m_lineVao.id());
        glDrawArrays(GL_LINES, 0, m_lineVertexCount);
    }
    glBindVertexArray(0);
    glUseProgram(0);
    if (!depthWas) glDisable(GL_DEPTH_TEST);
    if (!pointSizeWas) glDisable(GL_PROGRAM_POINT_SIZE);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(prevFbo));
    glViewport(prevViewport[0], prevViewport[1], prevViewport[2], prevViewport[3]);
}

int pickPoint(const std::vector<glm::vec3>& positions, const glm::mat4& viewProj, int width,
              int height, float px, float py, float splatPixels, float maxPixels) {
    const float half = 0.5f * splatPixels + 0.5f; // a pixel whose centre the square touches
    int best = -1, covering = -1;
    float bestD2 = maxPixels * maxPixels, bestDepth = 2.0f, coveringDepth = 2.0f;
    for (size_t i = 0; i < positions.size(); ++i) {
        glm::vec4 c = viewProj * glm::vec4(positions[i], 1.0f);
        if (!(c.w > 0)) continue;
        const float sx = (c.x / c.w * 0.5f + 0.5f) * float(width);
        const float sy = (0.5f - c.y / c.w * 0.5f) * float(height);
        const float depth = c.z / c.w;
        if (std::abs(sx - px) <= half && std::abs(sy - py) <= half && depth < coveringDepth) {
            covering = int(i);
            coveringDepth = depth;
        }
        const float d2 = (sx - px) * (sx - px) + (sy - py) * (sy - py);
        if (d2 < bestD2 - 1.0f || (d2 <= bestD2 + 1.0f && depth < bestDepth)) {
            if (d2 > maxPixels * maxPixels) continue;
            best = int(i);
            bestD2 = std::min(d2, bestD2);
            bestDepth = depth;
        }
    }
    return covering >= 0 ? covering : best;
}

} // namespace app
