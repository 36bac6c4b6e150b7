// 3D inspector view shared by the point-cloud, octree, irradiance and traversal panels: point
// splats (GL_POINTS, round, depth tested) with one colour each, axis-aligned boxes as lines
// (octree nodes by level, highlighted traversal nodes), drawn with a view-projection matrix into
// an offscreen RGBA8 target with depth. Picking is done on the CPU by projecting the points.
// Scalar attributes are coloured by core::colorRamp (core/color.h).
#pragma once

#include "gl/gl.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace app {

struct ViewBox {
    glm::vec3 lo, hi;
    glm::vec3 color;
};

class SceneView {
  public:
    void setPoints(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& colors);
    void setBoxes(const std::vector<ViewBox>& boxes);
    // Draws points then boxes into the offscreen target (resized to w × h).
    void draw(int width, int height, const glm::mat4& viewProj, float pointSizePx);
    GLuint texture() const { return m_color.id(); }
    int width() const { return m_width; }
    int height() const { return m_height; }

  private:
    void ensureTarget(int w, int h);
    void ensurePrograms();
    gl::Texture m_color, m_depth;
    gl::FramebufferId m_fbo;
    int m_width = 0, m_height = 0;
    gl::Program m_pointProgram, m_lineProgram;
    gl::VertexArray m_pointVao, m_lineVao;
    gl::Buffer m_pointBuffer, m_lineBuffer;
    GLsizei m_pointCount = 0, m_lineVertexCount = 0;
};

// Index of the point drawn at pixel (px, py) from the top left (viewProj, viewport w × h):
// among the points whose square splat of side splatPixels covers the pixel, the one nearest
// the camera, as the depth test shows it (a point on the far side of the mesh that projects a
// little closer to the click is hidden behind it); where no splat covers the pixel, the point
// whose projection is nearest within maxPixels (nearest the camera among ties); −1 if none.
int pickPoint(const std::vector<glm::vec3>& positions, const glm::mat4& viewProj, int width,
              int height, float px, float py, float splatPixels, float maxPixels = 6.0f);

} // namespace app
