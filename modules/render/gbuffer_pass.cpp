// render: the G-buffer pass (thesis 3.3.3: the surface point and normal seen through each pixel,
// read by the traversal, shaders/octree_render.comp), the G-buffer a capture gives in its place
// (its rasterised one kept aside for the raster rule), and the rasterisation on its own at an
// offset or with vertices snapped apart (another rasteriser emulated: gl/vertex_snap.h).
#include "render/renderer_state.h"

#include "core/core.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <string>

namespace render {

using renderer_detail::readTexels;

void Renderer::State::gbuffer(const Settings& s, GLuint target, int w, int h, glm::vec2 offset,
                              const gl::VertexSnap& snap) {
    gl::ScopedStageTimer timer("render.gbuffer");
    const gl::ScopedDrawTarget draw(target, w, h);
    const float zero[4] = {0, 0, 0, 0};
    const float one = 1.0f;
    glClearNamedFramebufferfv(target, GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(target, GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(target, GL_DEPTH, 0, &one);

    Camera cam = s.camera;
    cam.aspect = float(w) / float(h);
    // y flipped so that texture row 0 is the top of the image; `offset` moves the image by that
    // many pixels (+x right, +y down), i.e. each pixel's sample point by −offset
    const glm::mat4 flip = glm::scale(glm::mat4(1.0f), glm::vec3(1.0f, -1.0f, 1.0f));
    const glm::mat4 move = glm::translate(
        glm::mat4(1.0f), glm::vec3(2.0f * offset.x / float(w), 2.0f * offset.y / float(h), 0.0f));
    const glm::mat4 vp = move * flip * cam.projection() * cam.view();
    glUseProgram(gbufferProgram.id());
    glUniformMatrix4fv(glGetUniformLocation(gbufferProgram.id(), "RenderViewProjection"), 1,
                       GL_FALSE, glm::value_ptr(vp));
    const glm::vec3 snapClip = snap.clipAmplitude(w, h); // 0 but in tests (gl/vertex_snap.h)
    glUniform3fv(glGetUniformLocation(gbufferProgram.id(), "VertexSnap"), 1,
                 glm::value_ptr(snapClip));
    glUniform1ui(glGetUniformLocation(gbufferProgram.id(), "VertexSnapSeed"), snap.seed);
    glBindVertexArray(vao.id());
    glDrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    // barrier: render_gbuffer's draw → octree_render.comp's image loads of the G-buffer (draws
    // are ordered before later commands anyway; the bits are what a shader read after one needs)
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

void Renderer::State::useGiven() {
    frameGiven = false;
    if (!given) return;
    if (given->width != width || given->height != height)
        throw core::Error("render", 0,
                          "the given G-buffer is " + std::to_string(given->width) + "x" +
                              std::to_string(given->height) + ", the frame " +
                              std::to_string(width) + "x" + std::to_string(height));
    if (rasterWidth != width || rasterHeight != height) {
        rasterPosition = gl::createTexture2D(GL_RGBA32F, width, height, GL_NEAREST);
        rasterNormal = gl::createTexture2D(GL_RGBA32F, width, height, GL_NEAREST);
        rasterWidth = width;
        rasterHeight = height;
    }
    // The draw's results are copied by later commands in order; no barrier bit covers a copy
    // after a draw, none is needed.
    glCopyImageSubData(position.id(), GL_TEXTURE_2D, 0, 0, 0, 0, rasterPosition.id(), GL_TEXTURE_2D,
                       0, 0, 0, 0, width, height, 1);
    glCopyImageSubData(normal.id(), GL_TEXTURE_2D, 0, 0, 0, 0, rasterNormal.id(), GL_TEXTURE_2D, 0,
                       0, 0, 0, width, height, 1);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(position.id(), 0, 0, 0, width, height, GL_RGBA, GL_FLOAT,
                        given->position.data());
    glTextureSubImage2D(normal.id(), 0, 0, 0, width, height, GL_RGBA, GL_FLOAT,
                        given->normal.data());
    // barrier: the uploads → octree_render.comp's image loads (client updates are ordered
    // before later commands; stated for the reader, as after the draw)
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    frameGiven = true;
}

void Renderer::setGivenGbuffer(std::optional<Gbuffer> g) {
    if (g) {
        const size_t n = size_t(std::max(g->width, 0)) * size_t(std::max(g->height, 0));
        if (g->width < 1 || g->height < 1 || g->position.size() != n || g->normal.size() != n)
            throw core::Error("render", 0, "the given G-buffer's images do not match its size");
    }
    m->given = std::move(g);
}

bool Renderer::hasGivenGbuffer() const {
    return m->given.has_value();
}

Gbuffer Renderer::rasteriseGbuffer(const Settings& s, glm::vec2 offset,
                                   const gl::VertexSnap& snap) {
    renderer_detail::validate(s);
    if (!m->hasMesh) throw core::Error("render", 0, "not ready: no mesh");
    State& st = *m;
    if (st.auxWidth != s.width || st.auxHeight != s.height || !st.auxFbo) {
        st.auxPosition = gl::createTexture2D(GL_RGBA32F, s.width, s.height, GL_NEAREST);
        st.auxNormal = gl::createTexture2D(GL_RGBA32F, s.width, s.height, GL_NEAREST);
        st.auxDepth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, s.width, s.height, GL_NEAREST);
        GLuint id = 0;
        glCreateFramebuffers(1, &id);
        st.auxFbo = gl::FramebufferId(id);
        glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT0, st.auxPosition.id(), 0);
        glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT1, st.auxNormal.id(), 0);
        glNamedFramebufferTexture(id, GL_DEPTH_ATTACHMENT, st.auxDepth.id(), 0);
        const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glNamedFramebufferDrawBuffers(id, 2, buffers);
        st.auxWidth = s.width;
        st.auxHeight = s.height;
    }
    st.gbuffer(s, st.auxFbo.id(), s.width, s.height, offset, snap);
    // barrier: none for glGetTextureImage after a draw (GL_TEXTURE_UPDATE_BARRIER_BIT orders
    // shader image stores; a draw's framebuffer writes are complete for later commands)
    Gbuffer g;
    g.width = s.width;
    g.height = s.height;
    const size_t n = size_t(g.width) * size_t(g.height);
    readTexels(st.auxPosition.id(), n, g.position);
    readTexels(st.auxNormal.id(), n, g.normal);
    return g;
}

Gbuffer Renderer::rasterisedGbuffer() const {
    Gbuffer g;
    if (!m->fbo) return g;
    g.width = m->width;
    g.height = m->height;
    const size_t n = size_t(g.width) * size_t(g.height);
    const bool aside = m->frameGiven;
    readTexels(aside ? m->rasterPosition.id() : m->position.id(), n, g.position);
    readTexels(aside ? m->rasterNormal.id() : m->normal.id(), n, g.normal);
    return g;
}

} // namespace render
