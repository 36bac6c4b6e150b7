// The mesh rendering pipeline of thesis 3.3 as a stage graph (docs/ARCHITECTURE.md):
//   mesh (.obj) ─► point cloud ─► octree ─┐
//   light ─► irradiance per point ─► octree sums ─► traversal (render) ─► HDR image
// Each stage keeps a key of its inputs and re-runs only when it changes:
//   mesh file / point count / method / seed → everything; light → irradiance + render;
//   model, material, parameters, render settings, camera → render only.
// A stage that fails keeps its last good result on screen and reports the problem (Errors
// panel); the point cloud is generated in a background thread (the previous scene stays until
// the new one is ready; a new request supersedes a running one); occluded IBL advances a few
// environment samples per update. Renders use half resolution while the user interacts and
// full resolution at rest. The traversal debugger (debugPixel) replays one pixel with the CPU
// replica (octree::traverse) on the G-buffer of the last frame. A second renderer
// (scene_comparison.h) renders the brute-force pass and the A/B view's B side of the shown frame.
#pragma once

#include "pipeline/scene_comparison.h"
#include "pipeline/stage.h"

#include "bssrdf/program_library.h"
#include "core/core.h"
#include "irradiance/irradiance.h"
#include "mesh/mesh.h"
#include "octree/octree.h"
#include "pathtrace/lit_sphere.h"
#include "pointcloud/generate.h"
#include "render/render.h"

#include <atomic>
#include <filesystem>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace app {

// The scene's defaults are the ones of the GUI, the `render` command and captures (README
// "Defaults"); where they differ from the modules' own they are set here.
// The HDR radiance L_o of a read-back frame as an image (no variance: the render is
// deterministic), for EXR export (CLI render, the Render panel).
pathtrace::Image hdrImage(const render::Readback& rb);

struct SceneSettings {
    bool enabled = true;
    std::string meshFile = "third_party/bunny/bunny.obj"; // relative to the root, or absolute
    std::string pointCloudFile; // non-empty: read this PLY instead of generating
    pointcloud::GenerateOptions points;
    irradiance::Settings light{
        .direction = {0.45f, 0.75f, 0.5f}, .irradiance = glm::vec3(2.5f), .shadowMapSize = 1024};
    std::string environmentFile = "materials/env/default_sky.exr";
    std::string projectedTextureFile; // empty: the checkerboard
    // Bounding-box criterion with second-order clusters: ~0.5 % relative RMSE against brute
    // force on the default scene at ~70x less GPU time (README, bench hierarchy).
    render::Settings render{.width = 480,
                            .height = 270,
                            .camera = {.yaw = 0.5f, .pitch = 0.2f},
                            .eps = octree::defaultEps(true),
                            .boundingBoxCriterion = true,
                            .secondOrder = true};
    bool halfResolutionWhileChanging = true;
    bool useCache = true; // point-cloud PLY cache (pointcloud::defaultCacheDir)
    std::string model;    // display path of the rendered model; empty: the first visible one
};
// The description of SceneSettings' members (core/fields.h).
template <class V> void fields(V& v, SceneSettings& s) {
    v("enabled", s.enabled, "run the mesh pipeline");
    v("mesh", s.meshFile, "OBJ, relative to the root or absolute");
    v("point_cloud_file", s.pointCloudFile, "PLY to read instead of generating (empty: generate)");
    v("points", s.points, "point-cloud generation");
    v("light", s.light, "lighting");
    v("environment", s.environmentFile, "environment map (EXR) of the IBL modes");
    v("projected_texture", s.projectedTextureFile,
      "texture of the filtered light (empty: checker)");
    v("render", s.render, "hierarchical render");
    v("model", s.model, "display path of the rendered model (empty: the first visible)");
    v("half_resolution_while_changing", s.halfResolutionWhileChanging,
      "interactive frames at half resolution");
    v.skip(s.useCache, "where the point cloud comes from, not what it is");
}

struct StageStat {
    double ms = 0;      // last run, CPU wall clock (GPU work included: stages end in glFinish)
    long long runs = 0; // how often it ran
};

// What the render uses besides the scene: the model and its material (Workbench::sourceModel).
struct SceneModelInput {
    const bssrdf::ModelEntry* entry = nullptr;
    bssrdf::Builtins builtins;
    std::string materialKey;
    // The model check's server is still generating the code of this model's traversal program
    // (app::rendererCodePending): a changed model waits for it, the last frame stays shown.
    bool codePending = false;
};

struct PixelDebug {
    int x = -1, y = -1;
    bool hit = false;
    octree::Trace trace;
    glm::vec3 gpuExitance{0.0f};   // M read back from the frame
    glm::uvec4 gpuStats{0u};       // steps, max stack depth, flags, evaluations
    glm::vec3 bruteExitance{0.0f}; // Σ over every point (GPU-evaluated BSSRDF, float sum)
};

class SceneStage : public Stage {
  public:
    explicit SceneStage(std::filesystem::path root);
    ~SceneStage();

    SceneSettings& settings() { return m_settings; }
    const char* name() const override { return "scene"; }
    // Problems of every sub-stage; stats: the runs and last time of each.
    StageStatus status() const override;
    void cancel() override { cancelPointCloud(); }
    // Runs whatever is stale. interacting: the user is dragging / editing (half resolution).
    // Returns true when a result changed.
    bool update(const SceneModelInput& model, bool interacting);
    // Waits for a running point-cloud generation and runs every stage to completion at full
    // resolution (CLI, captures, tests, bench). Occluded IBL runs all its samples.
    // `progress(step, fraction)` hears each step as it starts (fraction −1) and, while the
    // point cloud is generated, its fraction done about every 200 ms.
    using FinishProgress = std::function<void(const char* step, double fraction)>;
    void finish(const SceneModelInput& model, const FinishProgress& progress = {});
    // Captures (when enabled): the mesh as an input, then every sub-stage run to completion and
    // its outputs, with the traversal of pixel (out.traceX, out.traceY) when both are >= 0
    // (scene_capture.cpp lists them). core::Error with the first problem.
    void capture(const SceneModelInput& model, CaptureEntries& out);
    // Hot reload: rebuilds exactly the render and irradiance programs whose shader files
    // include one of `changed` (a failure keeps the old program and is a "shaders" problem);
    // what they computed is computed again. Returns true when a program was rebuilt.
    bool reloadShaders(const std::vector<std::filesystem::path>& changed) override;
    // The scene's programs ("render:NAME", "irradiance:NAME", "brute force:NAME").
    shader::Records shaderRecords() const override;
    void cancelPointCloud(); // the running generation's result will be dropped
    // Reads the mesh, point-cloud, environment and texture files again (after the user fixed
    // one on disk); stages re-run only where the content changed.
    void reloadFiles();
    // The G-buffer the renderer traverses instead of its own rasterisation (a replayed
    // capture's recorded one; a test's emulating another rasteriser), std::nullopt: its own
    // again. The frame is rendered again at the next update or finish.
    void setGivenGbuffer(std::optional<render::Gbuffer> g);
    // The transmitted irradiance E_t per point (input order) the octree and so the traversal
    // read instead of the irradiance stage's own (a replayed capture's recorded one: another
    // sampler's visibility must not move the render), std::nullopt: its own again. The stage
    // still computes its own (irradiance() and what captures compare). One of another length
    // than the point cloud is a "given irradiance" problem, and the own is used.
    void setGivenIrradiance(std::optional<std::vector<glm::vec3>> e);
    bool hasGivenIrradiance() const { return m_givenIrradiance.has_value(); }
    // The G-buffer a replayed capture recorded (scene.gbuffer_position / _normal, both needed),
    // std::nullopt when it has none or this is no replay: what the scene's traversal and the
    // texture-space render read then. core::Error when the two images differ in size.
    static std::optional<render::Gbuffer> recordedGbuffer(const CaptureEntries& out);
    // Keep settings().render.camera as it is when the mesh loads (captures set it).
    void keepCamera() { m_cameraFitted = true; }

    // Results (last good).
    bool hasMesh() const { return m_mesh.has_value(); }
    const mesh::Mesh& mesh() const { return *m_mesh; }
    std::string meshHash() const;
    const pointcloud::PointCloud& cloud() const { return m_cloud; }
    const pointcloud::Uniformity& uniformity() const { return m_uniformity; }
    bool cloudFromCache() const { return m_cloudFromCache; }
    bool generating() const { return m_pending.valid(); }
    // Of the pending point-cloud generation, 0..1 (its relaxation iterations).
    double generatingProgress() const { return m_cloudProgress->load(); }
    double generatingSeconds() const;
    const octree::Octree* tree() const { return m_tree ? &*m_tree : nullptr; }
    const std::vector<glm::vec3>& irradiance() const { return m_irradiance; }
    float occludedProgress() const;
    bool occludedRunning() const;
    // The occluded IBL estimate in use: the samples it averages, of the run's K (0, 0 before
    // its first step; kept when the run is stopped), and per channel the points' summed
    // standard error of E_t over their summed E_t (Σ se / Σ E, from
    // irradiance::Stage::occludedStdError; 0 before two samples).
    int occludedSamplesDone() const { return m_occludedDone; }
    int occludedSamplesTotal() const { return m_occludedTotal; }
    glm::vec3 occludedRelativeError() const { return m_occludedRelError; }
    void cancelOccluded();
    const render::Frame& frame() const { return m_frame; }
    bool hasFrame() const { return m_frame.width > 0; }
    bool rendering() const { return m_renderer && m_renderer->inProgress(); }
    render::Readback readback() const; // of the renderer's current frame (done: the shown one)
    irradiance::Stage* irradianceStage() { return m_irradiance_stage.get(); }
    render::Renderer* renderer() { return m_renderer.get(); }
    const std::map<std::string, StageStat>& stats() const { return m_stats; }
    // Current problems, "stage: file:line: message".
    std::vector<std::string> problems() const;

    // Traversal debugger (thesis Algorithm 2 replayed on the CPU for one pixel of the last
    // frame). Throws core::Error when there is no frame or the pixel is outside it.
    PixelDebug debugPixel(int x, int y);
    // Radiant exitance M at a surface point (mesh units, unit normal) by the CPU replica of the
    // traversal with the current render settings and GPU-evaluated BSSRDF values (the point
    // cloud panel's readout for a clicked point). Throws core::Error before the first frame.
    glm::vec3 exitanceAt(const glm::vec3& xo, const glm::vec3& no);

    // The second renderer: brute force of the last frame's view (the relative-error heatmap) and
    // the B side of the Render panel's A/B view; update() advances its pass.
    SceneComparison& comparison() { return m_comparison; }
    const SceneComparison& comparison() const { return m_comparison; }
    // Finishes the current frame, then runs the brute-force pass to the end (tests, CLI).
    std::vector<glm::vec4> bruteForceExitance();

  private:
    void setProblem(const std::string& stage, const std::string& text);
    void clearProblem(const std::string& stage);
    bool updateMesh();
    bool updatePointCloud(bool wait);
    bool updateIrradiance(float ior, bool finishOccluded);
    // η of the light's Fresnel transmittance: the model's, else the light settings' own.
    float lightIor(const SceneModelInput& model) const {
        return model.entry ? model.builtins.ior : m_settings.light.ior;
    }
    bool updateRender(const SceneModelInput& model, bool interacting, bool finishNow);

  public:
    // Interactive renders: traversal dispatches of this many loop iterations per pixel, and
    // about this much traversal time per update (the rest of the frame continues next update).
    // The texture-space stage's sets render in such dispatches too.
    static constexpr uint32_t kInteractiveIterations = 32;
    static constexpr double kFrameBudgetMs = 30.0;

  private:
    core::Stopwatch m_renderClock;
    void applyCloud(pointcloud::PointCloud cloud, bool fromCache, double ms);
    std::filesystem::path resolve(const std::string& file) const;
    void ensureGl();

    std::filesystem::path m_root;
    SceneSettings m_settings;
    std::map<std::string, StageStat> m_stats;
    std::map<std::string, std::string> m_problems;

    std::string m_meshKey, m_cloudKey, m_irrKey, m_renderKey, m_modelKey;
    std::string m_deferredModelKey; // a changed model seen once, adopted at the next update
    std::string m_envTried, m_texTried;
    long long m_envLoads = 0, m_texLoads = 0;
    long long m_meshVersion = 0, m_cloudVersion = 0, m_irrVersion = 0;
    long long m_irradianceBuilds = 0, m_renderBuilds = 0; // hot-reloaded program rebuilds
    std::optional<mesh::Mesh> m_mesh;
    pointcloud::PointCloud m_cloud;
    pointcloud::Uniformity m_uniformity;
    bool m_cloudFromCache = false;
    std::future<pointcloud::Generated> m_pending;
    // Fraction of the pending generation's relaxation done, written by its thread.
    std::shared_ptr<std::atomic<double>> m_cloudProgress = std::make_shared<std::atomic<double>>(0);
    double m_pendingStart = 0;
    std::optional<octree::Octree> m_tree;
    std::vector<glm::vec3> m_irradiance;
    std::optional<std::vector<glm::vec3>> m_givenIrradiance;
    long long m_givenIrradianceVersion = 0;
    bool m_occludedActive = false;
    int m_occludedDone = 0, m_occludedTotal = 0;
    glm::vec3 m_occludedRelError{0.0f};
    std::unique_ptr<irradiance::Stage> m_irradiance_stage;
    std::unique_ptr<render::Renderer> m_renderer;
    render::Frame m_frame;
    // The displayed frame's image, owned here: the renderer reallocates its textures when a
    // new frame changes size (half resolution while moving), and the shown frame must not
    // point at a deleted texture meanwhile.
    FinishProgress m_finishProgress; // set during finish()
    gl::Texture m_displayLdr;
    int m_displayW = 0, m_displayH = 0;
    void adoptFrame(); // the renderer's finished frame becomes the displayed one (one run)
    bool m_cameraFitted = false;
    SceneComparison m_comparison{m_root, m_mesh, m_tree, kInteractiveIterations};
};

} // namespace app
