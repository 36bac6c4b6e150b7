// irradiance/shadow_maps: depth array, mesh upload, shadow pass, comparison samplers (see
// shadow_maps.h).
#include "irradiance/shadow_maps.h"

#include "core/core.h"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace irradiance {
namespace {
detail::Sampler makeSampler(GLenum filter) {
    GLuint id = 0;
    glCreateSamplers(1, &id);
    glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, filter);
    glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, filter);
    glSamplerParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
    glSamplerParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
    const float border[4] = {1.0f, 1.0f, 1.0f, 1.0f};
    glSamplerParameterfv(id, GL_TEXTURE_BORDER_COLOR, border);
    glSamplerParameteri(id, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glSamplerParameteri(id, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return detail::Sampler(id);
}
} // namespace

ShadowMaps::ShadowMaps(gl::Program program)
    : m_nearest(makeSampler(GL_NEAREST)), m_linear(makeSampler(GL_LINEAR)) {
    setProgram(std::move(program));
    GLuint vao = 0, fbo = 0;
    glCreateVertexArrays(1, &vao);
    m_vao = gl::VertexArray(vao);
    glCreateFramebuffers(1, &fbo);
    m_fbo = gl::FramebufferId(fbo);
    glNamedFramebufferDrawBuffer(fbo, GL_NONE);
    glNamedFramebufferReadBuffer(fbo, GL_NONE);
}

void ShadowMaps::setProgram(gl::Program program) {
    m_program = std::move(program);
    m_clipFromWorld = gl::uniformLocation(m_program, "ClipFromWorld");
    m_vertexSnap = gl::uniformLocation(m_program, "VertexSnap");
    m_vertexSnapSeed = gl::uniformLocation(m_program, "VertexSnapSeed");
}

void ShadowMaps::setMesh(const mesh::Mesh& m) {
    if (m.vertices.empty() || m.triangles.empty())
        throw core::Error("irradiance: the mesh has no triangles");
    m_vertices = gl::createBuffer(m.vertices.size() * sizeof(m.vertices[0]), m.vertices.data());
    m_indices = gl::createBuffer(m.triangles.size() * sizeof(m.triangles[0]), m.triangles.data());
    m_indexCount = static_cast<GLsizei>(3 * m.triangles.size());
    const GLuint vao = m_vao.id();
    glVertexArrayVertexBuffer(vao, 0, m_vertices.id(), 0, 3 * sizeof(float));
    glVertexArrayElementBuffer(vao, m_indices.id());
    glEnableVertexArrayAttrib(vao, 0);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, 0, 0);
}

void ShadowMaps::ensure(int size, int layers) {
    if (size == m_size && layers <= m_layers && m_depth) return;
    const int n = std::max(layers, 1);
    GLuint tex = 0, view = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &tex);
    glTextureStorage3D(tex, 1, GL_DEPTH_COMPONENT32F, size, size, n);
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    // Only shadow samplers read the array: its own state compares too, so a dispatch that finds
    // it bound without the comparison samplers (sampler 0) is still defined. NVIDIA reported
    // "a sampler (0) that has depth comparisons disabled, with a texture object (2) with a depth
    // format, by a shader that samples it with a shadow sampler" in the texture-space tests. The
    // 2D view below, which the Irradiance panel shows through ImGui's plain sampler, keeps
    // comparison off.
    glTextureParameteri(tex, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(tex, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    m_view.reset();
    m_depth = gl::Texture(tex);
    glGenTextures(1, &view); // a view needs a name without storage
    glTextureView(view, GL_TEXTURE_2D, tex, GL_DEPTH_COMPONENT32F, 0, 1, 0, 1);
    glTextureParameteri(view, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(view, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    m_view = gl::Texture(view);
    m_size = size;
    m_layers = n;
}

void ShadowMaps::render(int layer, const LightFrame& frame, glm::vec2 shift) {
    glNamedFramebufferTextureLayer(m_fbo.id(), GL_DEPTH_ATTACHMENT, m_depth.id(), 0, layer);
    const GLenum status = glCheckNamedFramebufferStatus(m_fbo.id(), GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw core::Error("irradiance: shadow-map framebuffer incomplete (status " +
                          std::to_string(status) + ")");
    const gl::ScopedDrawTarget draw(m_fbo.id(), m_size, m_size);
    // the pass's program is current before its clear: NVIDIA validates the current program's
    // sampler state at clears too, and the irradiance programs' shadow samplers have no maps on
    // their units between dispatches (docs/ARCHITECTURE.md, "State a driver validates")
    glUseProgram(m_program.id());
    const float one = 1.0f;
    glClearNamedFramebufferfv(m_fbo.id(), GL_DEPTH, 0, &one);
    glm::mat4 m = frame.clipFromWorld();
    if (shift != glm::vec2(0.0f)) { // a texel is 2/size in clip space
        glm::mat4 t(1.0f);
        t[3] = glm::vec4(2.0f * shift / float(m_size), 0.0f, 1.0f);
        m = t * m;
    }
    glUniformMatrix4fv(m_clipFromWorld, 1, GL_FALSE, glm::value_ptr(m));
    glUniform3fv(m_vertexSnap, 1, glm::value_ptr(m_snap.clipAmplitude(m_size, m_size)));
    glUniform1ui(m_vertexSnapSeed, m_snap.seed);
    glBindVertexArray(m_vao.id());
    glDrawElements(GL_TRIANGLES, m_indexCount, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
}

void ShadowMaps::bind() const {
    glBindTextureUnit(0, m_depth.id());
    glBindTextureUnit(1, m_depth.id());
    glBindSampler(0, m_nearest.id());
    glBindSampler(1, m_linear.id());
}

void ShadowMaps::unbind() const {
    glBindSampler(0, 0);
    glBindSampler(1, 0);
    glBindTextureUnit(0, 0); // no later program finds the depth array on a unit
    glBindTextureUnit(1, 0);
}

} // namespace irradiance
