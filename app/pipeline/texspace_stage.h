// The texture-space renderer of the Render panel (seed 004, Chang 2007; texspace/pipeline.h): the
// scene's mesh, light and view, rendered by texture-space importance sampling beside the
// point-cloud renderers. Stages and what re-runs them:
//   mesh file / texture size K → parameterisation and texels (the atlas note when the mesh's UVs
//   do not qualify); light (mode, direction, colour, η of the rendered model, environment,
//   projected texture) → E_t, E′ and the mip CDF (occluded IBL a few environment samples per
//   update); model, material, view, N, sets, seed → the accumulation starts again.
// Progressive: within the frame budget it draws and renders the next sample sets until
// sample_sets are averaged. A failure (a mesh that cannot be parameterised, a K above the GL
// limit, a missing environment) is a problem in Errors and the last good image stays.
#pragma once

#include "core/limits.h"
#include "pipeline/scene_stage.h"
#include "pipeline/stage.h"
#include "texspace/pipeline.h"

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace app {

struct TextureSpaceSettings {
    bool enabled = false; // the GUI sets it while the Render panel shows this renderer
    texspace::Settings sampling;
};
template <class V> void fields(V& v, TextureSpaceSettings& s) {
    v("enabled", s.enabled, "texture-space render of the Render panel's view");
    texspace::fields(v, s.sampling);
}

struct TextureSpaceInputs {
    TextureSpaceSettings settings;
    SceneStage* scene = nullptr;
    SceneModelInput model;
    double budgetMs = 20.0; // < 0: run to the target (finish)
};

class TextureSpaceStage : public StageOf<TextureSpaceInputs> {
  public:
    explicit TextureSpaceStage(std::filesystem::path root) : m_root(std::move(root)) {}
    const char* name() const override { return "texture space"; }
    bool update(const TextureSpaceInputs& in) override;
    StageStatus status() const override;
    // Runs every stage to the end (CLI, tests, bench); throws core::Error with the problem.
    void finish(TextureSpaceInputs in);
    // Captures (when the scene and this stage are on): runs to the target, then its texels, E′,
    // the first draws and the render (texspace_stage.cpp lists them).
    void capture(const TextureSpaceInputs& in, CaptureEntries& out);
    bool reloadShaders(const std::vector<std::filesystem::path>& changed) override;
    shader::Records shaderRecords() const override;
    // The E_t per texel the draws and the render read instead of the light's own
    // (texspace::Pipeline::setGivenIrradiance: a replayed capture's recorded one),
    // std::nullopt: the own again. The light is computed again at the next update or finish.
    void setGivenIrradiance(std::optional<std::vector<glm::vec3>> et);
    // The G-buffer of the scene's view the render (and the hybrid's local term) read instead of
    // its own rasterisation (render::Renderer::setGivenGbuffer: a replayed capture's recorded
    // scene.gbuffer_*, a test's emulating another rasteriser), std::nullopt: its own again. The
    // accumulation starts again at the next update or finish.
    void setGivenGbuffer(std::optional<render::Gbuffer> g);
    // The hybrid's local L_o per pixel the render adds instead of its own
    // (texspace::Pipeline::setGivenLocalRadiance: a replayed capture's recorded one),
    // std::nullopt: the own again. The accumulation starts again at the next update or finish.
    void setGivenLocalRadiance(std::optional<std::vector<glm::vec3>> l);

    bool active() const { return m_pipe && m_pipe->setsDone() > 0; }
    texspace::Pipeline* pipeline() { return m_pipe.get(); }
    const texspace::Pipeline* pipeline() const { return m_pipe.get(); }
    litsphere::Image radiance() const;         // L_o per pixel with the variance of the mean
    std::vector<std::string> problems() const; // "stage: message", sorted by stage
    const std::string& note() const { return m_note; } // why the atlas was used
    double seconds() const { return m_seconds; }       // of the current accumulation

  private:
    std::filesystem::path m_root;
    std::unique_ptr<texspace::Pipeline> m_pipe;
    std::string m_meshKey, m_lightKey, m_modelKey, m_runKey;
    std::string m_envTried, m_texTried;
    long long m_envLoads = 0, m_texLoads = 0;
    bool m_lightRunning = false, m_runOk = false;
    std::map<std::string, std::string> m_problems; // by sub-stage
    void setProblem(const std::string& stage, const std::string& text);
    void clearProblem(const std::string& stage);
    std::string m_note;
    double m_seconds = 0;
    std::optional<std::vector<glm::vec3>> m_givenEt;
    std::optional<render::Gbuffer> m_givenGbuffer;
    std::optional<std::vector<glm::vec3>> m_givenLocalL;
    long long m_givenVersion = 0; // of the given G-buffer and local term
};

} // namespace app
