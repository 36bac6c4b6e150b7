// The workbench: its state and its stage graph (no ImGui here; panels only show and edit it).
// The models (.bssrdf files, hot-reloaded, last good kept: bssrdf::ModelLibrary) feed an
// ordered list of stages (stage.h), each with explicit inputs gathered from the ones before:
//   material      — σ per model: as given, or inverted from R_dr / l_d      (model_stages.h)
//   pencil        — pencil-beam profile per model on the GPU                (model_stages.h)
//   reference     — path-traced R_d(r) for the source model's σ             (reference_stage.h)
//   slice         — the whole BSSRDF at oblique incidence: path traced
//                   (seed 001) and every model on the same bins             (slice_stage.h)
//   scoreboard    — every model scored against the reference                (scoreboard_stage.h)
//   geometry      — every model's image of the suite's shapes against the
//                   mesh path tracer (the Scoreboard's geometry tab)         (geometry_stage.h)
//   lit sphere    — path-traced and BSSRDF-integrated lit spheres           (lit_sphere_stage.h)
//   scene         — mesh → point cloud → octree → irradiance → render       (scene_stage.h)
//   monte carlo   — the scene's view integrated by probe rays               (monte_carlo_stage.h)
//   texture space — the scene's view by texture-space sampling or hybrid    (texspace_stage.h)
// The source model of the reference, slice, lit spheres and scene is one choice: the soloed
// model, else the first visible one whose material is usable (sourceModel). Each stage re-runs
// only when its inputs' key changes. Hot reload, the programs' records and captures loop over
// the stages (their reloadShaders, shaderRecords and capture hooks).
#pragma once

#include "bssrdf/program_library.h"
#include "core/file_watcher.h"
#include "core/limits.h"
#include "material/material.h"
#include "pipeline/fit_stage.h"
#include "pipeline/geometry_stage.h"
#include "pipeline/lit_sphere_stage.h"
#include "pipeline/model_stages.h"
#include "pipeline/monte_carlo_stage.h"
#include "pipeline/reference_stage.h"
#include "pipeline/scene_stage.h"
#include "pipeline/scoreboard_stage.h"
#include "pipeline/slice_stage.h"
#include "pipeline/texspace_stage.h"
#include "plot/plot.h"
#include "probe/model_probe_process.h"

#include <array>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace app {

// Pencil plot settings (thesis 3.6.3).
struct PlotSettings {
    plot::Scale yScale = plot::Scale::Log;
    bool rTimesR = false;
    int channel = 3;  // 0 R, 1 G, 2 B, 3 luminance
    std::string solo; // display path of the soloed model, empty = all models
    int samples = 512;
    bool fixedRange = false;
    double rMaxMm = 20.0; // used when fixedRange
    double rangeLd = 5.0; // otherwise: this many diffuse mean free paths (largest l_d)
    plot::Relation relation = plot::Relation::Values; // or ratio / difference to the reference
    // what a ratio / difference is to: the display path of a shown model (every other curve,
    // the path-traced and the MCML reference relative to it), empty: the path-traced reference
    std::string compareWith;
};
// The description of PlotSettings' members (core/fields.h).
template <class V> void fields(V& v, PlotSettings& s) {
    v("y_scale", s.yScale, "y axis scale");
    v("r_times_r", s.rTimesR, "plot r·R(r)");
    v("channel", s.channel, "0 R, 1 G, 2 B, 3 luminance", core::Limits{0, 3});
    v("solo", s.solo, "display path of the soloed model (empty: all)");
    v("samples", s.samples, "radii evaluated", core::Limits{2, 16384});
    v("fixed_range", s.fixedRange, "use r_max_mm instead of range_ld");
    v("r_max_mm", s.rMaxMm, "plot radius with fixed_range, mm", core::Limits{0.01, 1000});
    v("range_ld", s.rangeLd, "plot radius in largest l_d otherwise", core::Limits{0.1, 50});
    v("relation", s.relation, "values, or each model's ratio / difference to the reference");
    v("compare_with", s.compareWith,
      "display path of the model a ratio / difference is to (empty: the path-traced reference)");
}

struct ErrorItem {
    std::string source; // "model", "shader", "material", "action"
    std::string text;   // "file:line: message"
};

class Workbench {
  public:
    // root: project root holding materials/ and shaders/. watch: enable hot reload.
    // models: load exactly these files instead of every materials/*.bssrdf (CLI, replay).
    Workbench(std::filesystem::path root, bool watch,
              const std::vector<std::filesystem::path>& models = {});

    // Polls the file watcher and re-runs stale stages. Returns true when anything changed.
    bool update();
    // Called after a frame with the new results is on screen: closes the save→pixels clock.
    void framePresented();
    // Work under way that the next updates will show: a stage running (its StageStatus, the
    // scene's occluded irradiance) or a model under its check. The windowed loop draws at its
    // full rate while this holds (gui/frame_pacing.h).
    bool working() const;

    void reloadAll();
    void openModel(const std::filesystem::path& file);
    void applyPreset(MaterialSettings& s, const std::string& name);
    MaterialSettings& settingsFor(const std::string& displayPath); // own or shared

    bssrdf::ModelLibrary& library() { return *m_library; }
    const bssrdf::ModelLibrary& library() const { return *m_library; }
    ModelView& view(const std::string& displayPath) { return m_views[displayPath]; }
    const std::map<std::string, ModelView>& views() const { return m_views; }
    const std::vector<material::Preset>& presets() const { return m_presets; }
    MaterialSettings& shared() { return m_shared; }
    PlotSettings& plotSettings() { return m_plot; }
    const PlotSettings& plotSettings() const { return m_plot; }
    const std::filesystem::path& root() const { return m_root; }
    double rMaxMm() const { return m_rMax; }
    bool watching() const { return m_watcher != nullptr; }
    // A loop that sleeps between frames is woken by `wake` (any thread) when a watched file
    // changes (core::FileWatcher::setWake); an empty function stops that.
    void wakeOnFileChanges(std::function<void()> wake) {
        if (m_watcher) m_watcher->setWake(std::move(wake));
    }

    // Captures: updates, then runs every stage with outputs to record to completion in pipeline
    // order and collects its entries (pipeline/capture_entries.h; captures/ writes and
    // compares them). core::Error from the first stage that cannot produce its outputs.
    // onStage, when given, is told each stage's name before it is captured (progress lines).
    void capture(CaptureEntries& out, const std::function<void(const std::string&)>& onStage = {});

    // A model's plot slot (its colour and line style in the pencil plot): given when the model
    // first loads, the lowest no other present model holds, and kept while it stays loaded, so
    // adding or removing a model never changes another's colour.
    size_t plotSlot(const std::string& displayPath) const;

    // Every current problem (Errors panel): broken models/shaders, bad parameters, failed
    // user actions (which stay until dismissed), GL debug messages that came in the last
    // kGlProblemSeconds (a message stops when its cause is gone, and so does its entry).
    static constexpr double kGlProblemSeconds = 2.0;
    std::vector<ErrorItem> errors() const;
    void reportActionError(const std::string& text);
    // Forgets the action errors and the GL debug problems (Errors panel: Dismiss).
    void clearActionErrors();

    // Path-traced reference (pencil plot): settings, the model whose σ it uses, its state.
    ReferenceSettings& referenceSettings() { return m_refSettings; }
    const ReferenceSettings& referenceSettings() const { return m_refSettings; }
    ReferenceStage& reference() { return *m_reference; }
    const ReferenceStage& reference() const { return *m_reference; }
    // Starts the reference if needed and waits for it to finish (captures, CLI, tests).
    ReferenceSnapshot finishReference();

    // An MCML run shown in the pencil plot beside the models (File → Open MCML reference):
    // its R_d(r) per unit power entering, for the medium the file declares (pathtrace/mco.h).
    struct McmlReference {
        std::string path, name;
        pathtrace::Medium medium;
        pathtrace::SlabResult profile;
    };
    // Reads `file` (and `second`, an independent run of the same input, for standard errors);
    // throws core::Error naming the file and line when it cannot be a reference.
    void openMcmlReference(const std::filesystem::path& file,
                           const std::filesystem::path& second = {});
    void clearMcmlReference() { m_mcml.reset(); }
    const std::optional<McmlReference>& mcmlReference() const { return m_mcml; }

    // BSSRDF slice (seed 001): settings, the stage (reference snapshot, model slices).
    SliceSettings& sliceSettings() { return m_sliceSettings; }
    SliceStage& slice() { return *m_slice; }
    // The display path of the model whose σ the reference, the slice, the lit spheres and the
    // scene use now (sourceModel), "" when no loaded model is visible and usable. The stages
    // learn it on their next update; a panel drawn before that asks here.
    std::string sourceModelPath() const {
        const bssrdf::ModelEntry* e = sourceModel(nullptr);
        return e ? e->displayPath : std::string();
    }

    // The scoreboard of the current parameters (scoreboard_stage.h): every model against the
    // pencil plot's reference. Runs while enabled (the GUI: while its panel shows).
    void setScoreboardEnabled(bool on) { m_scoreboardEnabled = on; }
    const ScoreboardStage& scoreboard() const { return *m_scoreboard; }
    // The Scoreboard's geometry tab (geometry_stage.h): its request and its scores.
    GeometryTabSettings& geometryTab() { return m_geometryTab; }
    GeometryStage& geometry() { return *m_geometry; }
    // The Fit panel's fit (fit_stage.h) against the pencil plot's reference.
    FitStage& fit() { return *m_fit; }
    const FitStage& fit() const { return *m_fit; }
    // Starts fitting `params` of `model` to the reference as it is now (FitStage::start).
    void startFit(const std::string& model, const std::vector<std::string>& params,
                  const FitSettings& s = {});
    void finishFit(); // runs the fit to its end on this thread (tests)
    // The last fit asked for, which captures record and replay (settings section "fit").
    FitRequestSettings& fitRequest() { return m_fitRequest; }
    // Runs the slice's estimate to its target and evaluates every model (captures, tests).
    SliceSnapshot finishSlice() {
        update(); // the stages before it (the models' σ) first
        return m_slice->finish(sliceInputs());
    }

    // Lit spheres (thesis 3.5, 3.6.2): path traced and BSSRDF integrated, same setup.
    LitSphereSettings& litSphereSettings() { return m_sphere; }
    const LitSphereSettings& litSphereSettings() const { return m_sphere; }
    LitSphereStage& litSpheres() { return *m_litSpheres; }
    const LitSphereStage& litSpheres() const { return *m_litSpheres; }
    // Runs both renderings to their targets (tests, captures).
    void finishLitSpheres();

    // Mesh rendering pipeline (thesis 3.3): mesh → point cloud → octree → irradiance → render.
    // Off until enabled (the GUI enables it while a scene panel is open; captures and the CLI
    // enable it when they need it).
    SceneStage& scene() { return *m_scene; }
    // The model and material the scene renders with (the same source model as the lit spheres).
    SceneModelInput sceneModelInput() const;
    // Runs every scene stage to completion (CLI, captures, tests).
    // Starts the B side of the Render panel's A/B view: "" brute force of the shown frame,
    // else the model with this display path, with its own parameters and material.
    void requestSceneComparison(const std::string& model);
    void finishScene(const SceneStage::FinishProgress& progress = {}) {
        m_scene->finish(sceneModelInput(), progress);
    }
    // The Render panel's Monte Carlo renderer (monte_carlo_stage.h) of the shown frame's view.
    MonteCarloSettings& monteCarloSettings() { return m_mc; }
    const MonteCarloStage& monteCarlo() const { return *m_monteCarlo; }
    // Runs it to its target on the current frame (CLI, tests, bench).
    void finishMonteCarlo() { m_monteCarlo->finish({m_mc, m_scene.get(), sceneModelInput(), -1}); }
    // The Render panel's texture-space renderer (texspace_stage.h) of the scene's view.
    TextureSpaceSettings& textureSpaceSettings() { return m_ts; }
    const TextureSpaceSettings& textureSpaceSettings() const { return m_ts; }
    TextureSpaceStage& textureSpace() { return *m_textureSpace; }
    // Runs it to its target (CLI, tests, bench); throws core::Error with its problem.
    void finishTextureSpace() {
        m_textureSpace->finish({m_ts, m_scene.get(), sceneModelInput(), -1});
    }
    // The user is dragging the view or a control (set by the Render panel each frame): the
    // scene renders at half resolution meanwhile when its setting asks for it.
    void setInteracting(bool v) { m_interacting = v; }
    bool interacting() const { return m_interacting; }
    // Every GL program with the shader files it was built from and its build count, by
    // "owner:program" (model:<model file>:<template>, scene's render:/irradiance:,
    // reference:<channel>, lit sphere:). A changed file rebuilds exactly the programs listing it.
    shader::Records shaderPrograms() const;

  private:
    double autoRMax() const;
    void assignPlotSlots();
    // What the check of a new version of `file` evaluates: its current σ, the plot's radii.
    ProbeInputs probeInputs(const std::filesystem::path& file) const;
    // The model whose σ the reference, the lit spheres and the scene use (solo, else first
    // visible), with a usable material.
    const bssrdf::ModelEntry* sourceModel(const ModelView** view) const;
    ReferenceInputs referenceInputs() const;
    SliceInputs sliceInputs();
    // budgetMs < 0: fixed slices (deterministic), else adaptive.
    LitSphereInputs litSphereInputs(double budgetMs) const;

    std::filesystem::path m_root;
    std::unique_ptr<bssrdf::ModelLibrary> m_library;
    std::unique_ptr<core::FileWatcher> m_watcher;
    std::vector<material::Preset> m_presets;
    MaterialSettings m_shared;
    PlotSettings m_plot;
    std::map<std::string, ModelView> m_views;
    std::map<std::string, size_t> m_plotSlots; // by display path (plotSlot)
    std::vector<std::string> m_actionErrors;
    double m_rMax = 20.0;
    std::optional<double> m_pendingSaveTime; // seconds since epoch of the save being timed
    ReferenceSettings m_refSettings;
    LitSphereSettings m_sphere;
    MaterialStage m_material;
    PencilStage m_pencil;
    std::unique_ptr<ReferenceStage> m_reference;
    SliceSettings m_sliceSettings;
    std::unique_ptr<SliceStage> m_slice;
    std::unique_ptr<ScoreboardStage> m_scoreboard;
    std::unique_ptr<FitStage> m_fit;
    GeometryTabSettings m_geometryTab;
    std::unique_ptr<GeometryStage> m_geometry;
    std::optional<McmlReference> m_mcml;
    FitRequestSettings m_fitRequest;
    bool m_scoreboardEnabled = false;
    std::unique_ptr<LitSphereStage> m_litSpheres;
    std::unique_ptr<SceneStage> m_scene;
    MonteCarloSettings m_mc;
    std::unique_ptr<MonteCarloStage> m_monteCarlo;
    TextureSpaceSettings m_ts;
    std::unique_ptr<TextureSpaceStage> m_textureSpace;
    // The stages in data-flow order: run() gathers the stage's inputs and updates it;
    // capture(), for stages with outputs to record, gathers the inputs of a run to completion
    // (no time budgets) and adds the stage's capture entries.
    struct PipelineStep {
        Stage* stage;
        std::function<bool()> run;
        std::function<void(CaptureEntries&)> capture = {};
        // What the last run threw (core::Error: a model loop past its budget in a consumer
        // that does not report it itself, bssrdf/loop_budget.h); kept until a run changes
        // something without throwing.
        std::string failed = {};
    };
    std::vector<PipelineStep> m_pipeline;
    bool m_interacting = false;
};

} // namespace app
