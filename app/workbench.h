// The workbench state and its stage graph (no ImGui here; panels only show and edit it).
// Stages of the foundation:
//   models    — .bssrdf files (hot-reloaded, last good kept)          bssrdf::ModelLibrary
//   material  — σ per model: as given, or inverted from R_dr / l_d    material + invert_rdr.comp
//   pencil    — pencil-beam profile per model on the GPU               pencil_profile.comp
// Each stage remembers a key of its inputs and re-runs only when that key changes.
#pragma once

#include "bssrdf/program_library.h"
#include "core/file_watcher.h"
#include "lit_sphere_stage.h"
#include "material/material.h"
#include "plot/plot.h"
#include "reference_stage.h"
#include "scene_stage.h"

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace app {

enum class ParamMode { Sigma, RdrLd };
constexpr auto enumNames(ParamMode) {
    return std::array{std::pair{ParamMode::Sigma, "sigma"}, std::pair{ParamMode::RdrLd, "rdr_ld"}};
}

// Material inputs as the user edits them (thesis 3.6.1).
struct MaterialSettings {
    ParamMode mode = ParamMode::Sigma;
    material::MaterialParams params; // σ mode (g, η, scale apply in both modes)
    glm::dvec3 rdr{0.6, 0.45, 0.3};  // R_dr / l_d mode
    glm::dvec3 ld{8.0, 4.0, 2.0};    // mm
    std::string preset = "Marble";
};
// The description of MaterialSettings' members (core/fields.h).
template <class V> void fields(V& v, MaterialSettings& s) {
    v("mode", s.mode, "parametrisation: sigma or rdr_ld");
    v.inlined(s.params);
    v("rdr", s.rdr, "diffuse reflectance R_dr (rdr_ld mode)");
    v("ld_mm", s.ld, "diffuse mean free path l_d, mm (rdr_ld mode)");
    v("preset", s.preset, "last applied preset");
}

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
};
// The description of PlotSettings' members (core/fields.h).
template <class V> void fields(V& v, PlotSettings& s) {
    v("y_scale", s.yScale, "y axis scale");
    v("r_times_r", s.rTimesR, "plot r·R(r)");
    v("channel", s.channel, "0 R, 1 G, 2 B, 3 luminance");
    v("solo", s.solo, "display path of the soloed model (empty: all)");
    v("samples", s.samples, "radii evaluated");
    v("fixed_range", s.fixedRange, "use r_max_mm instead of range_ld");
    v("r_max_mm", s.rMaxMm, "plot radius with fixed_range, mm");
    v("range_ld", s.rangeLd, "plot radius in largest l_d otherwise");
}

// Per-model view state and stage results.
struct ModelView {
    bool visible = true;
    bool override = false; // own material settings instead of the shared ones
    MaterialSettings own;
    std::optional<material::MaterialParams> effective; // σ actually used
    std::string materialProblem;                       // why `effective` is missing
    std::string materialKey;
    bssrdf::Profile profile;
    std::string profileKey;
};

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

    void reloadAll();
    void openModel(const std::filesystem::path& file);
    void applyPreset(MaterialSettings& s, const std::string& name);
    MaterialSettings& settingsFor(const std::string& displayPath); // own or shared

    bssrdf::ModelLibrary& library() { return *m_library; }
    ModelView& view(const std::string& displayPath) { return m_views[displayPath]; }
    const std::vector<material::Preset>& presets() const { return m_presets; }
    MaterialSettings& shared() { return m_shared; }
    PlotSettings& plotSettings() { return m_plot; }
    const std::filesystem::path& root() const { return m_root; }
    double rMaxMm() const { return m_rMax; }
    bool watching() const { return m_watcher != nullptr; }

    // Every current problem (Errors panel): broken models/shaders, bad parameters, failed
    // user actions (which stay until dismissed).
    std::vector<ErrorItem> errors() const;
    void reportActionError(const std::string& text);
    void clearActionErrors() { m_actionErrors.clear(); }

    // Plot series for the current settings (one per visible model, or R/G/B when soloed),
    // then the path-traced reference when enabled; model labels carry their error against it.
    std::vector<plot::Series> plotSeries() const;

    // Path-traced reference (pencil plot): settings, the model whose σ it uses, its state.
    ReferenceSettings& referenceSettings() { return m_refSettings; }
    const std::string& referenceModel() const { return m_refModel; }
    ReferenceSnapshot referenceSnapshot() const {
        return m_refSettings.gpu ? m_gpuRef->snapshot() : m_ref->snapshot();
    }
    void restartReference() { m_refKey.clear(); }
    void cancelReference() {
        m_ref->cancel();
        m_gpuRef->cancel();
    }
    // Starts the reference if needed and waits for it to finish (captures, CLI, tests).
    ReferenceSnapshot finishReference();

    // Lit spheres (thesis 3.5, 3.6.2): path traced and BSSRDF integrated, same setup.
    LitSphereSettings& litSphereSettings() { return m_sphere; }
    const std::string& litSphereModel() const { return m_sphereModel; }
    pathtrace::Image pathTracedSphere() const { return m_ptSphere->image(); }
    pathtrace::Image integratedSphere() const { return m_integrator.image(); }
    const PathTracedSphere& pathTracer() const { return *m_ptSphere; }
    uint64_t integratedSppDone() const { return m_integrator.samplesPerPixelDone(); }
    const std::string& litSphereProblem() const { return m_sphereProblem; }
    void restartLitSpheres() { m_sphereKey.clear(); }
    // Stops the path tracer where it is (the image keeps the passes completed so far).
    void cancelLitSpheres() { m_ptSphere->cancel(); }
    // Runs both renderings to their targets (tests, captures).
    void finishLitSpheres();
    static std::string normalisationNote();

    // Mesh rendering pipeline (thesis 3.3): mesh → point cloud → octree → irradiance → render.
    // Off until enabled (the GUI enables it while a scene panel is open; captures and the CLI
    // enable it when they need it).
    SceneStage& scene() { return *m_scene; }
    // The model and material the scene renders with (the same source model as the lit spheres).
    SceneModelInput sceneModelInput() const;
    // Runs every scene stage to completion (CLI, captures, tests).
    void finishScene() { m_scene->finish(sceneModelInput(), m_shaderGeneration); }
    void setInteracting(bool v) { m_interacting = v; }
    long long shaderGeneration() const { return m_shaderGeneration; }

  private:
    void computeMaterial(bssrdf::ModelEntry& e, ModelView& v);
    void computeProfile(bssrdf::ModelEntry& e, ModelView& v);
    double autoRMax() const;
    void updateReference();
    // Returns the model whose σ the reference / lit spheres use (solo, else first visible).
    const bssrdf::ModelEntry* sourceModel(const ModelView** view) const;
    // budgetMs < 0: fixed slices of kFixedSlice samples (deterministic), else adaptive.
    bool updateLitSpheres(double budgetMs);

    std::filesystem::path m_root;
    std::unique_ptr<bssrdf::ModelLibrary> m_library;
    std::unique_ptr<core::FileWatcher> m_watcher;
    std::vector<material::Preset> m_presets;
    MaterialSettings m_shared;
    PlotSettings m_plot;
    std::map<std::string, ModelView> m_views;
    std::vector<std::string> m_actionErrors;
    double m_rMax = 20.0;
    std::optional<double> m_pendingSaveTime; // seconds since epoch of the save being timed
    ReferenceSettings m_refSettings;
    std::unique_ptr<ReferenceRunner> m_ref = std::make_unique<ReferenceRunner>();
    std::unique_ptr<GpuReference> m_gpuRef;
    std::string m_refKey, m_refModel;
    uint64_t m_refVersion = 0, m_gpuSteps = 0;
    LitSphereSettings m_sphere;
    std::unique_ptr<PathTracedSphere> m_ptSphere;
    bssrdf::SphereIntegrator m_integrator;
    std::string m_sphereKey, m_sphereModel, m_sphereProblem;
    int m_ptSppSeen = 0;
    int m_integratedSlice = 16;
    static constexpr int kFixedSlice = 256;
    std::unique_ptr<SceneStage> m_scene;
    long long m_shaderGeneration = 0;
    bool m_interacting = false;
};

// Effective σ for one model: validates, and inverts R_dr / l_d with the model's own
// DiffuseReflectance on the GPU. Throws core::Error with a clear message.
material::MaterialParams effectiveParams(const bssrdf::ModelEntry& e, const MaterialSettings& s);
bssrdf::Builtins builtinsOf(const material::MaterialParams& p);

} // namespace app
