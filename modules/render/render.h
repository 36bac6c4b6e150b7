// render: the interactive point-cloud renderer of thesis 3.3.3 / 3.6.4 — the hierarchical
// (Jensen–Buhler, thesis 2.6.4) BSSRDF evaluation on the GPU.
//   1. G-buffer (shaders/render_gbuffer.*): the mesh rasterised with the orbit camera into
//      RGBA32F position (mesh units, w = 1 hit / 0 miss), RGBA32F normal (interpolated vertex
//      normal, normalised, not turned towards the camera) and depth.
//   2. Traversal (shaders/octree_render.comp, a model consumer): per hit pixel the octree
//      traversal of thesis Algorithm 2 exactly as modules/octree/octree.h specifies (the CPU
//      replica octree::traverse does the same), or a brute-force sum over every point; the
//      radiant exitance M and the radiance L_o = Ft(η, cos θo)/π · M. Radial models use the
//      profile table (profile_table.h) unless Settings::directBssrdf. Accepted nodes use the
//      second-order cluster rule (octree.h) unless !Settings::secondOrder.
//   3. Tone map (shaders/render_tonemap.comp): exposure (stops) and gamma into RGBA8.
// Images: pixel (x, y), y = 0 the top row; index p = y·width + x.
// A G-buffer may be given from outside (a capture's recorded one, captures/README.md): the
// traversal then reads it instead of the rasterised one, which is still drawn and kept
// (rasterisedGbuffer), so a replay on another rasteriser traces the recorded pixels.
// Mesa llvmpipe stops every loop of an invocation after 65535 iterations in total (nested
// loops included), so the traversal runs in dispatches of at most kIterationsPerDispatch loop
// iterations per pixel and resumes unfinished pixels (see the shader). If the driver's limit
// still cuts a dispatch short (a model with loops of its own), the frame is rendered again
// with half the iterations per dispatch (down to 256); below that every pixel of the frame
// gets kFlagLoopLimit.
// Every call needs the same current OpenGL 4.5 context.
#pragma once

#include "bssrdf/program.h"
#include "core/limits.h"
#include "gl/gl.h"
#include "gl/vertex_snap.h"
#include "mesh/mesh.h"
#include "octree/octree.h"
#include "render/camera.h"
#include "render/profile_table.h"
#include "shader/program.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

namespace render {

inline constexpr uint32_t kIterationsPerDispatch = 32768;
// Render-level flag in Readback::stats[p].z besides octree::kFlagStackOverflow and
// octree::kFlagIterationCap: the driver's loop limit cut the traversal short even at the
// smallest dispatch size (the frame's values are then incomplete; set on every pixel).
inline constexpr uint32_t kFlagLoopLimit = 4u;

// A radial weight on every BSSRDF evaluation of a frame (the hybrid method of seed 004 §3.3:
// its global part R_d·W_g). W_g(r) = 1 − W_l(r), W_l(r) = 1 − ½e^{(r−R_p)K} for r ≤ R_p and
// ½e^{−(r−R_p)K} beyond (texspace/hybrid.h), r = |xo − xi| in mm, R_p per channel.
struct RadialWeight {
    bool global = false; // multiply by W_g
    glm::vec3 rp{0.0f};  // R_p per channel, mm
    float k = 1.5f;      // K, 1/mm
};

struct Settings {
    int width = 640, height = 360;         // 1 … 8192 each
    Camera camera;                         // camera.aspect is replaced by width/height
    float eps = octree::defaultEps(false); // ε of the criterion (>= 0)
    bool boundingBoxCriterion = false;
    // Accepted nodes by the three-point second-order cluster rule of octree.h (three BSSRDF
    // evaluations each) instead of one evaluation at the mean position.
    bool secondOrder = true;
    bool bruteForce = false;
    bool directBssrdf = false; // radial models: call Bssrdf() instead of the profile table
    uint32_t maxSteps = octree::kDefaultMaxSteps; // >= 1
    int stackSize = octree::kStackSize;           // usable stack entries, 1 … kStackSize
    float exposure = 0.0f, gamma = 2.2f;          // stops; gamma > 0
    glm::vec3 background{0.12f, 0.12f, 0.14f};    // display colour of misses
    // Loop iterations per pixel and traversal dispatch; 0 = kIterationsPerDispatch (lowered
    // automatically when the driver's loop limit is hit). Results do not depend on it.
    uint32_t iterationsPerDispatch = 0;
    RadialWeight weight{}; // set by the hybrid renderer; none by default
    // The criterion of the CPU replica that matches these settings.
    octree::Criterion criterion() const;
};
// The description of Settings' members (core/fields.h).
template <class V> void fields(V& v, Settings& s) {
    v("width", s.width, "image width in pixels", core::Limits{1, 8192});
    v("height", s.height, "image height in pixels", core::Limits{1, 8192});
    v("camera", s.camera, "orbit camera");
    v("eps", s.eps, "criterion threshold ε (octree::defaultEps)", core::Limits{0, 1e6});
    v("bbox_criterion", s.boundingBoxCriterion, "bounding-box distance in the criterion");
    v("second_order", s.secondOrder, "accepted nodes by the second-order three-point rule");
    v("brute_force", s.bruteForce, "sum every point (no hierarchy)");
    v("direct_bssrdf", s.directBssrdf, "radial models: Bssrdf() instead of the profile table");
    v("max_steps", s.maxSteps, "traversal steps per pixel before it is cut",
      core::Limits{1, 4294967295.0});
    v("stack_size", s.stackSize, "usable traversal stack entries",
      core::Limits{1, octree::kStackSize});
    v("exposure", s.exposure, "tone mapping exposure, stops", core::Limits{-64, 64});
    v("gamma", s.gamma, "tone mapping gamma", core::Limits{0.1, 10});
    v("background", s.background, "display colour of misses", core::Limits{0, 1e3});
    v.skip(s.iterationsPerDispatch, "dispatch slicing; results do not depend on it");
    v.skip(s.weight, "set by the hybrid renderer for its global part");
}

// What the tone map pass counted in a frame's L_o (a model that returned such values): NaN
// and infinite pixels show magenta, negative ones (a component < 0) clamp to black.
struct InvalidPixels {
    uint32_t surface = 0; // pixels that show the mesh
    uint32_t nan = 0, inf = 0, negative = 0;
    bool any() const { return nan + inf + negative > 0; }
};

struct Frame {
    int width = 0, height = 0;
    GLuint ldr = 0;      // RGBA8, tone mapped
    GLuint hdr = 0;      // RGBA32F, rgb = L_o, a = 1 hit / 0 miss
    GLuint position = 0; // RGBA32F G-buffer
    GLuint normal = 0;   // RGBA32F G-buffer
    double gbufferMs = 0, profileMs = 0, traverseMs = 0, tonemapMs = 0; // CPU, after glFinish
    int dispatches = 0; // traversal dispatches of the frame
    int bands = 0;      // bands of rows they ran in (setStorageBlockLimit)
    uint32_t iterationsPerDispatch = 0;
    InvalidPixels invalid;
};

struct Readback {
    int width = 0, height = 0;
    std::vector<glm::vec4> hdr;      // L_o, hit
    std::vector<glm::vec4> exitance; // M (rgb), hit
    std::vector<glm::uvec4> stats;   // steps, max stack depth, flags, evaluations
    std::vector<glm::vec4> position; // xo (mesh units), hit
    std::vector<glm::vec4> normal;   // no, 0
    std::vector<unsigned char> ldr;  // RGBA8
    size_t index(int x, int y) const { return size_t(y) * size_t(width) + size_t(x); }
};

// A G-buffer's two images as the traversal reads them (Readback's layout).
struct Gbuffer {
    int width = 0, height = 0;
    std::vector<glm::vec4> position; // xo (mesh units), w = 1 hit / 0 miss
    std::vector<glm::vec4> normal;   // no, 0 (0 everywhere at a miss)
};

// One BSSRDF argument set in mm (positions) and unit directions.
struct BssrdfPair {
    glm::vec3 xi, wi, xo, wo;
};
// Bssrdf(xi, wi, xo, wo) for every pair on the GPU (shaders/render_pairs.comp; `program` from
// bssrdf::buildModelProgram(m, "render_pairs.comp", sources)).
std::vector<glm::vec3> evaluatePairs(GLuint program, const bssrdf::Model& m,
                                     const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                                     const std::vector<BssrdfPair>& pairs);
// Makes the driver generate the code of the traversal program `program` (built with
// bssrdf::buildModelProgram(m, "octree_render.comp", sources)) as the renderer's first dispatch
// at a width×height frame needs it, without rendering: one work group with no pixel to do and
// the renderer's images bound at that size (a driver such as llvmpipe generates code per image
// format and per power-of-two-ness of the image's sides). The model check's process does this
// so that the driver's on-disk shader cache hands the code to the workbench
// (app/probe/model_probe_process.h).
void warmTraversal(GLuint program, int width, int height);

// The pairs of a CPU replica trace, as the shader forms them: (scale·xi, wi, scale·xo, no).
std::vector<BssrdfPair> tracePairs(const octree::Trace& t, float scale);

class Renderer {
  public:
    explicit Renderer(shader::Sources src); // builds the G-buffer and tone-map programs
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    void setMesh(const mesh::Mesh& m); // normals computed when the mesh has none
    void setOctree(const octree::Octree& t);
    void updateAttributes(const octree::Octree& t); // node + point records only (same sizes)
    // Builds the traversal, pairs (and for radial models the profile) programs; on a compile
    // error throws core::Error(model file, line, …) and keeps the previous model and programs.
    // Parameter values carry over (bssrdf::carryOver) until setMaterial.
    void setModel(const bssrdf::Model& m);
    void setMaterial(const bssrdf::ParamValues& values, const bssrdf::Builtins& b);
    // Hot reload: rebuilds exactly the programs whose shader files (shaderRecords()) include
    // one of `changed`; a failed one keeps its last good program. A frame in progress must be
    // begun again by the caller when something was rebuilt.
    shader::Reloaded reloadShaders(const std::vector<std::filesystem::path>& changed);
    // "render_gbuffer", "render_tonemap.comp", and once a model is set "octree_render.comp",
    // "render_pairs.comp" (and "pencil_profile.comp" for radial models).
    const shader::Records& shaderRecords() const;

    bool ready() const; // mesh, octree and model set
    // G-buffer + traversal + tone map. Throws core::Error("render", 0, …) for invalid settings
    // or when not ready().
    Frame render(const Settings& s);
    Readback readback() const; // of the last frame
    // The G-buffer the traversal reads instead of the rasterised one, from the next begin() on
    // (std::nullopt: the rasterised one again). begin() throws core::Error("render", 0, …)
    // when its size is not the frame's. Readback::position/normal are the given images.
    void setGivenGbuffer(std::optional<Gbuffer> g);
    bool hasGivenGbuffer() const;
    // The last frame's rasterised G-buffer (the given one does not replace it here).
    Gbuffer rasterisedGbuffer() const;
    // The G-buffer of settings `s` rasterised apart from any frame (its own targets), its image
    // moved by `offset` pixels (+x right, +y down: each sample point moves by −offset), what
    // another rasteriser's sub-pixel placement does (render/raster_rule.h), and each vertex
    // moved on its own by `snap` (its snapping and rounding, gl/vertex_snap.h). Needs a mesh.
    Gbuffer rasteriseGbuffer(const Settings& s, glm::vec2 offset = {},
                             const gl::VertexSnap& snap = {});

    // Progressive rendering, so an interactive caller never blocks for a whole frame: begin()
    // runs the G-buffer (and profile table) and starts the traversal; advance(budgetMs) runs
    // traversal dispatches until about budgetMs have passed (at least one) and returns true
    // once the frame is complete and tone mapped. render() = begin + advance to the end; the
    // result does not depend on how the work was split (Settings::iterationsPerDispatch sets
    // the granularity). Readback of an unfinished frame shows partial sums.
    void begin(const Settings& s);
    bool advance(double budgetMs);
    bool inProgress() const;
    const Frame& currentFrame() const;
    // The traversal runs in bands of rows when a frame's per-pixel state (96 bytes a pixel)
    // would exceed the largest storage block a dispatch may bind: the driver's
    // GL_MAX_SHADER_STORAGE_BLOCK_SIZE (bytes <= 0, the default), or `bytes` (tests lower it to
    // split small frames). The result does not depend on the bands. From the next begin() on.
    void setStorageBlockLimit(int64_t bytes);

    // The current model's Bssrdf on the GPU (render_pairs.comp) with the current material.
    std::vector<glm::vec3> evaluatePairs(const std::vector<BssrdfPair>& pairs) const;
    // The profile table of the last frame that used one (empty before; radial models only).
    const ProfileTable& profileTable() const;
    // Builds the profile table for the current model, material, mesh and octree when it is not
    // current (radial models; what begin() does) and returns it.
    const ProfileTable& prepareProfileTable();
    const bssrdf::Builtins& builtins() const;

  private:
    struct State;
    std::unique_ptr<State> m; // GL objects inside
};

} // namespace render
