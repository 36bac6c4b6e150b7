// render: the Renderer's private state, shared by the files that implement it — renderer.cpp
// (programs, mesh, octree, model, profile table, the frame's targets, the traversal's resumable
// dispatches, the tone map) and gbuffer_pass.cpp (the G-buffer pass, a given G-buffer, the
// rasterisation on its own). Not part of the module's interface (render.h).
#pragma once

#include "render/render.h"

#include "bssrdf/loop_budget.h"

#include <optional>
#include <vector>

namespace render {

namespace renderer_detail {
constexpr int kMaxSide = 8192;
constexpr int kLocal = 8; // local size of the compute passes
constexpr uint32_t kMinIterations = 256;
// std430 size of RenderPixelState in octree_render.comp: uint stack[16], uvec4, uvec4.
constexpr size_t kPixelStateBytes = octree::kStackSize * 4 + 32;

// Throws core::Error("render", 0, why) for settings no frame can be made with.
void validate(const Settings& s);

// An RGBA32F texture of n texels read back into `out`.
inline void readTexels(GLuint id, size_t n, std::vector<glm::vec4>& out) {
    out.resize(n);
    glGetTextureImage(id, 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(n * sizeof(glm::vec4)),
                      out.data());
}
} // namespace renderer_detail

struct Renderer::State {
    shader::Sources src;
    shader::Records records; // by program name, see shaderRecords()
    gl::Program gbufferProgram, tonemapProgram;
    // mesh
    gl::VertexArray vao;
    gl::Buffer vbo, ebo;
    GLsizei indexCount = 0;
    glm::vec3 meshLo{0.0f}, meshHi{0.0f};
    bool hasMesh = false;
    // octree
    gl::Buffer descriptors, nodes, points;
    uint32_t nodeCount = 0, pointCount = 0;
    glm::vec3 treeLo{0.0f}, treeHi{0.0f};
    bool hasOctree = false;
    // model and material
    std::optional<bssrdf::Model> model;
    gl::Program renderProgram, pairsProgram, profileProgram;
    bssrdf::ParamValues values;
    bssrdf::Builtins builtins;
    // profile table
    ProfileTable table;
    gl::Buffer tableBuffer;
    bool tableValid = false;
    double tableCap = -1.0;
    uint32_t iterations = kIterationsPerDispatch; // lowered when the loop limit is hit
    // targets
    int width = 0, height = 0;
    gl::Texture position, normal, depth, hdr, ldr;
    // The given G-buffer (setGivenGbuffer) and, while one is given, the rasterised images
    // copied aside before it is uploaded over them.
    std::optional<Gbuffer> given;
    gl::Texture rasterPosition, rasterNormal;
    int rasterWidth = 0, rasterHeight = 0;
    bool frameGiven = false; // the last begin() uploaded the given G-buffer
    gl::FramebufferId fbo;
    // stats and exitance hold the frame, state one band of bandRows rows (octree_render.comp,
    // Bands): bandRows keeps every block a dispatch binds within the storage block limit
    gl::Buffer stats, exitance, state, control;
    int64_t storageBlockLimit = 0; // setStorageBlockLimit; 0: the driver's
    int bandRows = 0;
    bssrdf::LoopFaults loopFaults; // the model's loop budget (bssrdf/loop_budget.h)
    gl::Buffer invalidCounts;      // the tone map's counts: surface, NaN, Inf, negative pixels

    void resize(int w, int h);
    int rowsPerBand(int w, int h) const;
    // The G-buffer pass into `target` (w×h attachments: position, normal, depth), its image
    // moved by `offset` pixels.
    void gbuffer(const Settings& s, GLuint target, int w, int h, glm::vec2 offset = {},
                 const gl::VertexSnap& snap = {});
    gl::Texture auxPosition, auxNormal, auxDepth; // rasteriseGbuffer's own targets
    gl::FramebufferId auxFbo;
    int auxWidth = 0, auxHeight = 0;
    void useGiven(); // the given G-buffer over the rasterised one (that kept aside)
    void ensureProfile();
    // One traversal dispatch (uniforms set for `perDispatch` iterations): returns true when
    // every pixel finished; sets loopLimit when the driver cut a loop short.
    void bindTraverse(const Settings& s, uint32_t perDispatch, int band);
    bool dispatchOnce(const Settings& s, uint32_t perDispatch, int band, int dispatch,
                      bool& loopLimit);
    // Tone maps the frame and counts its invalid pixels.
    InvalidPixels tonemap(const Settings& s);
    // Progressive frame (begin / advance).
    struct Progress {
        bool active = false;
        Settings settings;
        Frame frame;
        int band = 0;     // the band being traversed
        int dispatch = 0; // of the band
        double traverseMs = 0;
    } progress;
};

} // namespace render
