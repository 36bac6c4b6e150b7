// irradiance/shadow_maps: the depth maps of thesis 3.3.2 ("the model is rendered as a depth map
// from the perspective of the light source into an off-screen buffer"): a GL_DEPTH_COMPONENT32F
// 2D array texture (one layer per light), the mesh in a vertex array, the depth-only program
// (shaders/irradiance_shadow.{vert,frag}) and two comparison samplers (GL_LEQUAL,
// clamp-to-border with depth 1 = lit outside): nearest (single test) and linear (hardware PCF).
#pragma once

#include "gl/gl.h"
#include "gl/vertex_snap.h"
#include "irradiance/light_frame.h"
#include "irradiance/programs.h"
#include "mesh/mesh.h"

#include <glm/vec2.hpp>

#include <filesystem>

namespace irradiance {

class ShadowMaps {
  public:
    // program: shaders/irradiance_shadow.{vert,frag}, built by the caller.
    explicit ShadowMaps(gl::Program program);
    void setProgram(gl::Program program); // a rebuilt program (hot reload)
    void setMesh(const mesh::Mesh& m);
    // (Re)allocates when the size changes or fewer layers exist than asked for.
    void ensure(int size, int layers);
    // Depth of the mesh seen from `frame` into `layer` (restores the framebuffer binding,
    // viewport and depth/cull state it touches). `shift`: the image moved by that many texels
    // (x, y), as another rasteriser's sub-pixel precision may place it (Stage::visibilitySpread).
    void render(int layer, const LightFrame& frame, glm::vec2 shift = glm::vec2(0.0f));
    // From the next render on, another rasteriser emulated (gl/vertex_snap.h; tests).
    void setVertexSnap(const gl::VertexSnap& snap) { m_snap = snap; }
    // Binds the depth array to texture units 0 (nearest sampler) and 1 (linear sampler).
    void bind() const;
    void unbind() const; // unbinds the samplers and the depth array (units 0 and 1 are shared)
    int size() const { return m_size; }
    int layers() const { return m_layers; }
    GLuint view() const { return m_view.id(); } // GL_TEXTURE_2D view of layer 0

  private:
    gl::Program m_program;
    gl::VertexArray m_vao;
    gl::Buffer m_vertices, m_indices;
    GLsizei m_indexCount = 0;
    gl::Texture m_depth, m_view;
    gl::FramebufferId m_fbo;
    detail::Sampler m_nearest, m_linear;
    GLint m_clipFromWorld = -1, m_vertexSnap = -1, m_vertexSnapSeed = -1;
    gl::VertexSnap m_snap;
    int m_size = 0, m_layers = 0;
};

} // namespace irradiance
