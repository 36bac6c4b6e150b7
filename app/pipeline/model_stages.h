// The per-model stages of the workbench (stage.h): material — each model's σ, as given or
// inverted from R_dr / l_d with the model's own DiffuseReflectance on the GPU (thesis 3.1.1,
// 3.4; shaders/invert_rdr.comp) — and pencil — each model's pencil-beam profile R(r) on the
// GPU (thesis 3.6.3; shaders/pencil_profile.comp). Both re-run a model only when its key (its
// inputs) changed; results live in the model's ModelView.
#pragma once

#include "core/limits.h"
#include "pipeline/capture_entries.h"
#include "pipeline/stage.h"

#include "bssrdf/program_library.h"
#include "material/material.h"

#include <array>
#include <map>
#include <optional>
#include <string>

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
    v("rdr", s.rdr, "diffuse reflectance R_dr (rdr_ld mode)", core::Limits{0, 1});
    v("ld_mm", s.ld, "diffuse mean free path l_d, mm (rdr_ld mode)", core::Limits{0, 1e6});
    v("preset", s.preset, "last applied preset");
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
    std::string profileProblem; // NaN, Inf or negative values of the profile (Errors)
};

// Effective σ for one model: validates, and inverts R_dr / l_d with the model's own
// DiffuseReflectance on the GPU. Throws core::Error with a clear message.
material::MaterialParams effectiveParams(const bssrdf::ModelEntry& e, const MaterialSettings& s);
bssrdf::Builtins builtinsOf(const material::MaterialParams& p);

struct ModelStageInputs {
    bssrdf::ModelLibrary* library = nullptr;
    std::map<std::string, ModelView>* views = nullptr; // one per model, by display path
    const MaterialSettings* shared = nullptr;          // for models without their own
};

class MaterialStage : public StageOf<ModelStageInputs> {
  public:
    const char* name() const override { return "material"; }
    bool update(const ModelStageInputs& in) override;
    StageStatus status() const override; // "<model>: <why it has no σ>" per model
    // Captures: material.<model>, the effective σ per channel (exact when copied, within the
    // inversion's tolerance when inverted); a model without σ is listed as missing.
    void capture(const ModelStageInputs& in, CaptureEntries& out) const;

  private:
    const std::map<std::string, ModelView>* m_views = nullptr;
};

struct PencilInputs {
    bssrdf::ModelLibrary* library = nullptr;
    std::map<std::string, ModelView>* views = nullptr;
    double rMaxMm = 20.0; // profile radius
    int samples = 512;
};

class PencilStage : public StageOf<PencilInputs> {
  public:
    const char* name() const override { return "pencil"; }
    bool update(const PencilInputs& in) override;
    StageStatus status() const override; // "<model>: R(r) is NaN at …" per model
    // Captures: pencil_plot.<model>, the profile R(r) of every model with σ (GPU float32).
    void capture(const PencilInputs& in, CaptureEntries& out) const;

  private:
    const std::map<std::string, ModelView>* m_views = nullptr;
};

} // namespace app
