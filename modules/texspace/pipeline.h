// texspace/pipeline: the three stages of texture-space importance sampling (Chang 2007, seed
// 004, §3.2) as one GPU pipeline beside the point-cloud renderer, seeing the same light and
// rendering with the same BSSRDF evaluation and exit Fresnel term.
//   Stage 0 (setMesh): the parameterisation (texspace.h) rasterised into K × K texels
//     (texture_space.h), K a power of two in [16, 2048].
//   Stage 1 (beginLight / advanceLight): the transmitted irradiance E_t of every covered texel
//     by the point-cloud pipeline's own irradiance::Stage (the texels are its points: same
//     modes, shadow maps, Fresnel transmittance and IBL quadrature), then eq. 3.2's
//     E′ = E_t · A_S/A_T per texel and the texel weights w_t = Y(E′_t) · A_texel (Y the
//     luminance, A_texel = 1/K²), so that Σ_t w_t = W approximates ∫_S Y(E_t) dA.
//   Stage 2 (drawSet): N texels drawn with probability p_t = w_t / W by Algorithm 3.1 on the GPU
//     (gpu_sampler.h), one set shared by every outgoing point.
//   Stage 3 (advance): eq. 3.5, per pixel
//         M(x_o) = ∫_T E′(x) R_d(x, x_o) dx ≈ (1/N) Σ_i E′_i A_texel R_d(x_i, x_o) / p_i
//                = (W/N) Σ_i R_d(x_i, x_o) · E_t,i / Y(E_t,i)
//     (for grey light E_t / Y = 1: the thesis's (E′_avg/N) Σ R_d). It is evaluated by the point-
//     cloud renderer's brute-force pass (render.h) over the drawn texels as points with
//     irradiance E_t,i and area (count_i · W) / (N · Y(E_t,i)) (a texel drawn count_i times is
//     one point), so R_d comes from the model's radial profile table, or Bssrdf() for non-radial
//     models, and L_o = Ft(η, cos θo)/π · M as there. Progressive: every frame draws a new,
//     independent set (counter-based random numbers, set k uses draws [kN, (k+1)N)) and the
//     images are averaged; the spread between sets gives each pixel's variance of the mean.
// The estimator is unbiased for the texel sum (the same sum over every covered texel, allTexels());
// that sum differs from the surface integral by the rasterisation (texel centres, eq. 3.2 per
// texel), which is what a larger K reduces.
// Every call needs the same current OpenGL 4.5 context.
#pragma once

#include "bssrdf/program.h"
#include "core/limits.h"
#include "irradiance/irradiance.h"
#include "litsphere/litsphere.h"
#include "mesh/mesh.h"
#include "render/render.h"
#include "shader/program.h"
#include "texspace/gpu_sampler.h"
#include "texspace/hybrid.h"
#include "texspace/texspace.h"
#include "texspace/texture_space.h"

#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

namespace texspace {

struct Settings {
    int textureSize = 512; // K, a power of two in [16, 2048]
    int samples = 1024;    // N per sample set (seed 004 Table 4.2: 49 … 2500), [1, 2^20]
    int sampleSets = 64;   // progressive target: sets averaged
    uint64_t seed = 1;
    // The hybrid method (hybrid.h): the local part of R_d by the light-view ring filter, the
    // global part by these sets. Directional light and radial models only.
    bool hybrid = false;
    HybridSettings local;
};
template <class V> void fields(V& v, Settings& s) {
    v("texture_size", s.textureSize, "texels per side K (a power of two)", core::Limits{16, 2048});
    v("samples", s.samples, "texels drawn per sample set N", core::Limits{1, 1048576});
    v("sample_sets", s.sampleSets, "sample sets averaged (progressive target)",
      core::Limits{1, 1e6});
    v("seed", s.seed, "random seed of the draws");
    v("hybrid", s.hybrid, "hybrid method: local part by the light-view ring filter");
    v("local", s.local, "the hybrid's weighting and local filter");
}
// Throws core::Error("texture space", 0, …) naming the setting: K not a power of two in
// [16, 2048] or above maxTextureSize (the GL limit; 0 = unchecked), N or the set count < 1.
void validateSettings(const Settings& s, int maxTextureSize = 0);

// One drawn set as points of the brute-force pass (distinct texels, draw order of first draw).
struct SampleSet {
    std::vector<uint32_t> draws;       // the N drawn texels (row-major index), in draw order
    std::vector<uint32_t> texel;       // per point
    std::vector<uint32_t> count;       // times drawn
    std::vector<glm::vec3> position;   // mesh units
    std::vector<glm::vec3> normal;     // unit
    std::vector<float> area;           // (count · W) / (N · Y(E_t)), mesh units²
    std::vector<glm::vec3> irradiance; // E_t
};

class Pipeline {
  public:
    // root: the project folder (shaders/ below it). Builds every program (core::Error naming
    // the file and line of a compile error).
    explicit Pipeline(const std::filesystem::path& root);
    ~Pipeline();
    Pipeline(const Pipeline&) = delete;
    Pipeline& operator=(const Pipeline&) = delete;

    // Stage 0. Throws core::Error for a bad size or a mesh that cannot be parameterised; the
    // previous mesh stays then. The light must be computed again afterwards.
    void setMesh(const mesh::Mesh& m, int textureSize);
    bool hasMesh() const { return m_texels.size > 0; }
    const Parameterization& parameterization() const { return m_param; }
    // The texture side the atlas was laid out for (K, or larger when K's texels cannot hold a
    // gutter between the mesh's triangles; the mesh's own UVs: K).
    int layoutSize() const { return m_layoutSize; }
    const Texels& texels() const { return m_texels; }
    // Σ over covered texels of A_S/A_T · A_texel (mesh units²): the area the texels stand for,
    // against the mesh's own (the rasterisation's coverage).
    double representedArea() const;

    // Environment and projected texture of the IBL / filtered modes are set here, as on the
    // point-cloud pipeline's stage.
    irradiance::Stage& irradianceStage() { return *m_irradiance; }

    // Stage 1. beginLight validates and starts; advanceLight runs (occluded IBL: the next
    // environment samples) and returns true when E_t, E′ and the CDF are ready. Throws
    // core::Error (bad settings, no environment); the previous light stays then.
    void beginLight(const irradiance::Settings& light);
    bool advanceLight();
    bool lightReady() const { return m_lightReady; }
    float lightProgress() const;
    // E_t and E′ per texel as this light computed them (0 off the chart).
    const std::vector<glm::vec3>& transmitted() const { return m_ownEt; }
    std::vector<glm::vec3> eprime() const;
    // The E_t per texel (K² row-major) that stages 2 and 3 read instead of the light's own (a
    // replayed capture's recorded one: another sampler's visibility must not move the CDF, the
    // draws or the render), std::nullopt: the own. Taken at the next light computed
    // (beginLight); one of another length than K² is a core::Error there, and a covered
    // texel's value must be finite and >= 0 as the light's own.
    void setGivenIrradiance(std::optional<std::vector<glm::vec3>> et) { m_givenEt = std::move(et); }
    // What stages 2 and 3 read: the given E_t when one was set, else transmitted().
    const std::vector<glm::vec3>& drawnIrradiance() const { return m_et; }
    double totalWeight() const { return m_total; } // W
    const MipCdf& cdf() const { return m_cdf; }
    // E′ as its two factors, E′ = E′_u · V (irradiance::Stage::factors, which says why): per
    // texel the unshadowed E′_u and the shadow-map visibility V (0 off the chart). Directional
    // and filtered light only (core::Error otherwise, or before the light is computed).
    struct EprimeFactors {
        std::vector<glm::vec3> unshadowed;
        std::vector<float> visibility;
    };
    EprimeFactors eprimeFactors();
    // Occluded IBL: for each of `texels` (covered ones) the unshadowed sum U times A_S/A_T, U of
    // the light last computed (irradiance::Stage::occludedUnshadowed, CPU): E′ of two drivers
    // lies within kVisibilityTolerance times it. core::Error for other lights or before the
    // light is computed.
    std::vector<glm::vec3> eprimeUnshadowedOccluded(const std::vector<size_t>& texels) const;
    // Occluded IBL: for each of `texels` (covered ones) how far another rasteriser's shadow maps
    // may move E′ (irradiance::Stage::occludedRasterSpread of the light last computed, times
    // A_S/A_T). core::Error for other lights or before the light is computed.
    std::vector<glm::vec3> eprimeOccludedRasterSpread(const std::vector<size_t>& texels);
    // Directional and filtered light: for each of `texels` (covered ones) how far another
    // rasteriser's shadow map may move V (irradiance::Stage::visibilitySpread of the light last
    // computed). core::Error for other lights or before the light is computed.
    std::vector<float> visibilitySpread(const std::vector<size_t>& texels);

    // Stage 2: set `index` of N draws under `seed`. Empty when W = 0 (no light on the surface:
    // every pixel is 0). Throws when the light is not ready.
    SampleSet drawSet(int samples, uint64_t seed, uint64_t index) const;
    // Every covered texel with weight once, area A_S/A_T · A_texel: the expectation of a set.
    SampleSet allTexels() const;

    // Stage 3. The model and material of the render (as render::Renderer).
    void setModel(const bssrdf::Model& m);
    void setMaterial(const bssrdf::ParamValues& values, const bssrdf::Builtins& b);
    // Starts the accumulation of `s.sampleSets` sets for the view `view` (brute force forced).
    void begin(const Settings& s, const render::Settings& view);
    // Renders the next sets until about budgetMs passed (at least one dispatch); true once
    // s.sampleSets are accumulated.
    bool advance(double budgetMs);
    // s.sampleSets accumulated and, with the hybrid, its local term computed.
    bool done() const { return m_setsDone >= m_run.sampleSets && !localPending(); }
    int setsTarget() const { return m_run.sampleSets; }
    // Changes the target of the running accumulation (more sets continue it, fewer end it).
    void setSampleSets(int sets) { m_run.sampleSets = std::max(1, sets); }
    int setsDone() const { return m_setsDone; }
    // Renders one given set to the end (tests, the reference sum): L_o and M per pixel.
    render::Readback renderSet(const SampleSet& set, const render::Settings& view);
    // Mean L_o and M over the sets so far with their variance of the mean (samples = sets);
    // with the hybrid, the local term (deterministic) plus the sets' global term.
    litsphere::Image radiance() const;
    litsphere::Image exitance() const;
    // The hybrid's parts (empty without it): the local L_o (no variance) and the global L_o.
    litsphere::Image localRadiance() const;
    litsphere::Image globalRadiance() const;
    // The local L_o per pixel (row-major, the view's size) that radiance() adds instead of the
    // local term's own (a replayed capture's recorded one: another driver's light-view map must
    // not move the render), std::nullopt: the own. Taken when the local term is computed (from
    // the next begin()); one of another size than the frame is a core::Error then.
    void setGivenLocalRadiance(std::optional<std::vector<glm::vec3>> l) {
        m_givenLocalL = std::move(l);
    }
    // The local term's own L_o per pixel (w = hit) as computed here, whatever was given.
    const std::vector<glm::vec4>& ownLocalRadiance() const { return m_ownLocalL; }
    // The light-view map drawn `map` texels aside and read `lookup` texels aside from the next
    // begin() on (an emulated other driver: tests); 0, 0 by default.
    void setLocalShift(glm::vec2 map, glm::vec2 lookup);
    // The light-view map drawn with every vertex moved on its own from the next begin() on
    // (another rasteriser emulated: gl::VertexSnap; tests); {} by default.
    void setLocalVertexSnap(const gl::VertexSnap& snap);
    // How far another driver may move the own local L_o at `pixels` (row-major indices), per
    // channel, absolute (local_spread.cpp says how it is measured). Needs the hybrid's local term
    // computed (core::Error otherwise); per pass of LocalTerm::tapsPerPass() pixels, nine map
    // draws and 17 passes over their taps, after which the map and lookups are the run's.
    std::vector<glm::vec3> localSpread(const std::vector<size_t>& pixels);
    glm::vec3 hybridRp() const { return m_rp; } // R_p per channel of the running hybrid, mm
    const std::vector<RingTap>& hybridTaps() const { return m_taps; }
    // The last set drawn (for the panels) and the frame timings of the last set.
    const SampleSet& lastSet() const { return m_lastSet; }
    double lastSampleMs() const { return m_sampleMs; }
    double lastRenderMs() const { return m_renderMs; }
    double localMs() const { return m_localMs; } // the hybrid's local term (once per view)
    // L_o (rgb, w = hit) of the last set alone (with the hybrid's local term): one frame's image.
    const std::vector<glm::vec4>& lastSetRadiance() const { return m_lastL; }
    render::Renderer& renderer() { return *m_renderer; }
    const render::Renderer& renderer() const { return *m_renderer; }

    // Hot reload of the irradiance, sampling and render programs whose files include one of
    // `changed` (a failure keeps the last good program); when something was rebuilt the light
    // must be computed and the accumulation begun again by the caller.
    shader::Reloaded reloadShaders(const std::vector<std::filesystem::path>& changed);
    // "irradiance:NAME", "sample:texspace_sample.comp", "render:NAME".
    shader::Records shaderRecords() const;

  private:
    void finishLight(std::vector<glm::vec3> et);
    void beginHybrid();
    void beginLocal(); // the local term's evaluation on the current frame's G-buffer
    bool localPending() const { return m_run.hybrid && m_localL.empty(); }
    void startSet();
    void accumulate(const render::Readback& rb);

    shader::Sources m_src;
    std::unique_ptr<irradiance::Stage> m_irradiance;
    std::unique_ptr<GpuSampler> m_sampler;
    std::unique_ptr<render::Renderer> m_renderer;
    Parameterization m_param;
    Texels m_texels;
    int m_layoutSize = 0;
    std::vector<uint32_t> m_covered; // covered texel indices (the irradiance points)
    bool m_lightReady = false, m_lightOccluded = false;
    std::vector<glm::vec3> m_ownEt, m_et; // the light's own; what stages 2 and 3 read
    std::optional<std::vector<glm::vec3>> m_givenEt;
    std::vector<double> m_weights;
    MipCdf m_cdf;
    double m_total = 0;

    Settings m_run;
    render::Settings m_view;
    bool m_running = false, m_setRendering = false;
    int m_setsDone = 0;
    int m_width = 0, m_height = 0;
    std::vector<double> m_sumL, m_sumL2, m_sumM, m_sumM2;
    // the hybrid
    bool m_radial = false;
    irradiance::Settings m_light;
    std::unique_ptr<LocalTerm> m_local;
    bool m_localMesh = false;
    int m_lightMapSize = 0; // of the light-view map rendered last (0: none for this mesh)
    glm::vec3 m_lightMapDirection{0.0f};
    mesh::Mesh m_meshCopy;
    glm::vec3 m_rp{0.0f};
    std::vector<RingTap> m_taps;
    std::vector<glm::vec4> m_localM, m_localL; // per pixel, w = hit; m_localL the given if set
    std::vector<glm::vec4> m_ownLocalL;
    std::optional<std::vector<glm::vec3>> m_givenLocalL;
    glm::vec2 m_mapShift{0.0f}, m_lookupShift{0.0f}, m_lightMapShift{0.0f};
    gl::VertexSnap m_localSnap;
    std::vector<glm::vec4> m_lastL;
    bool m_localStarted = false;
    SampleSet m_lastSet;
    double m_sampleMs = 0, m_renderMs = 0, m_localMs = 0;
};

} // namespace texspace
