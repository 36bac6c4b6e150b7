// irradiance: the first pass of the Jensen–Buhler two-pass method (thesis 2.6.4, 3.3.2): the
// irradiance of every point of a surface point cloud, cached for the hierarchical evaluation.
//
// Quantity. Per point p with unit normal n the stage stores the TRANSMITTED irradiance
//     E_t(p) = ∫ Ft(η, n·ω) · L(ω) · max(0, n·ω) · V(p, ω) dω        (RGB, W/m² per unit L)
// with Ft = 1 − R the exact unpolarised Fresnel transmittance of light entering from index 1
// into relative index η = Settings::ior (common/irradiance_lighting.glsl, as
// pathtrace/fresnel.h) and V the visibility. The renderer multiplies E_t by the point's area
// and the BSSRDF's diffusion term (Jensen–Buhler: M_o = Σ_p R_d · E_t(p) · A_p; the entry
// Fresnel factor is already in E_t).
//
// Light modes (Settings::mode):
//   Directional  E_t = E0 · Ft(η, n·L) · max(0, n·L) · V, E0 = Settings::irradiance the RGB
//                irradiance on a surface facing the light, L = Settings::direction (towards
//                the light; normalised here), V from a shadow map (light_frame.h) filtered by
//                Settings::filter, the four methods of thesis Fig. 3.3 (naive, offset, offset +
//                hardware PCF, offset + PCF + jittered lookups; common/irradiance_shadow.glsl
//                states the slope-scaled offset), or none (V = 1).
//   Filtered     Directional times a projected texture T(uv) looked up in light space (uv of
//                light_frame.h; texture row 0 = the image's top = v near 1, linear filtering,
//                clamped at the edges). Default: a checkerboard of 8 × 8 squares of 8 texels,
//                values 1 and 0.25 (grey).
//   Ibl          E_t(n) = envIntensity · ∫ Ft(η, n·ω) L(R ω) max(0, n·ω) dω without occlusion,
//                read from an irradiance cubemap (kCubeFaceSize² per face, bilinear, seamless,
//                filtered by the shader in float so that every driver agrees: no sampler's
//                fixed-point weights, irradiance_ibl.comp) that is precomputed on the GPU by
//                the quadrature of environment.h
//                (irradiance_cubemap.comp) whenever the environment or η changes. The world
//                frame is the environment's rotated by envRotation about +y:
//                ω_world = R_y(envRotation)·ω_env, R_y(a)·(1,0,0) = (cos a, 0, −sin a).
//   OccludedIbl  the same integral with V, estimated by Monte Carlo with the same K =
//                occludedTotalSamples environment samples for every point (env_sampling.h),
//                each a directional light with its own shadow map; incremental
//                (beginOccluded / stepOccluded, occludedSamplesPerStep per step, ping-pong
//                buffers of Σ Y and Σ Y²), deterministic for a seed; the standard error per
//                point is from the per-sample values (conservative: the samples are
//                stratified).
// Positions are in mesh units (the mesh normalised to ~1 unit); only directions matter for
// lighting, lengths only for the shadow offset (Settings::depthOffset, in mesh units).
//
// Errors are core::Error: file errors name the file (environment.h, projected textures);
// settings errors (zero-length direction, shadow-map size outside [16, min(8192, GL max)],
// η outside [1, 4], jitter samples outside [1, 16], negative or non-finite colours) name the
// setting. A Stage needs a current OpenGL 4.5 context and is single threaded. Its calls change
// the current program, SSBO bindings 0–3 and texture units 0–3 (the comparison samplers on
// units 0 and 1 are unbound again), and Ibl enables GL_TEXTURE_CUBE_MAP_SEAMLESS; the shadow
// pass restores the framebuffer binding, viewport and depth / cull / scissor state.
// Cost (llvmpipe, 2 cores): the cubemap of the 128 × 64 default sky takes ~2 s (32768 nodes ×
// 6144 texels); a directional pass over 100k points ~15–60 ms; an occluded step of 4 samples
// at 1024² ~0.3 s.
#pragma once

#include "core/limits.h"
#include "gl/gl.h"
#include "gl/vertex_snap.h"
#include "irradiance/environment.h"
#include "irradiance/light_frame.h"
#include "mesh/mesh.h"
#include "pointcloud/pointcloud.h"
#include "shader/program.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace irradiance {

enum class LightMode { Directional, Filtered, Ibl, OccludedIbl };
// The name the Irradiance panel's light list and messages give a mode.
constexpr const char* lightModeName(LightMode m) {
    switch (m) {
    case LightMode::Directional:
        return "directional";
    case LightMode::Filtered:
        return "filtered directional";
    case LightMode::Ibl:
        return "image based (IBL)";
    case LightMode::OccludedIbl:
        return "occluded IBL";
    }
    return "unknown";
}
// The lights whose E_t is one shadow-map visibility V times the unshadowed E_u (Stage::factors).
constexpr bool hasVisibilityFactor(LightMode m) {
    return m == LightMode::Directional || m == LightMode::Filtered;
}
// thesis Fig. 3.3 a–d, and None (V = 1: the lighting without shadows)
enum class ShadowFilter { Naive, Offset, OffsetPcf, OffsetPcfJitter, None };
// How far two conforming GL implementations' V of one filter may differ at a point: a PCF
// lookup is a bilinear blend of 0/1 comparisons, so |ΔV| <= |Δα| + |Δβ| for weight errors Δα,
// Δβ; samplers compute the weights in fixed point with 8 fractional bits (Direct3D 11's
// D3D11_SUBTEXEL_FRACTIONAL_BIT_COUNT; NVIDIA's texture units, CUDA Programming Guide,
// "Linear Filtering"), a weight error of up to 2^-8 per axis, and the mean of jittered lookups
// keeps that bound (Vulkan allows samplers with as few as 4 bits, which would need 2^-3).
// Float samplers (llvmpipe, lavapipe) differ by N·ulp(uv) per ulp of uv instead, far less.
inline constexpr double kVisibilityTolerance = 2.0 / 256.0;
// How far two conforming rasterisers may place a shadow map's edges apart, in texels (twice the
// 1/32 texel a vertex may move at GL_SUBPIXEL_BITS = 4; Stage::visibilitySpread), along each
// axis.
inline constexpr float kRasterShiftTexels = 1.0f / 16.0f;
// The moves of a map's image that stand for another rasteriser: the corners and the edges'
// midpoints of the square |x|, |y| <= kRasterShiftTexels. A straight edge moves across a texel
// by s·n for a move s, largest at a corner; near a vertex where several triangles meet, which
// one covers a texel is no monotone function of s (a jittered comparison at the bunny flipped
// under (1/16, 0) and (0.05, 0.03) but under no corner), so the midpoints are tried too. The
// moves are rigid and a driver snaps each vertex on its own: the tests move the bunny's vertices
// independently (Stage::setVertexSnap) and find V and occluded E_t within the rigid moves'
// spread (IrradianceDirectional.TheVisibilitySpreadBoundsAMapWhoseVerticesSnapApart,
// IrradianceOccluded.TheRasterSpreadBoundsMapsWhoseVerticesSnapApart).
inline std::array<glm::vec2, 8> rasterShifts() {
    const float d = kRasterShiftTexels;
    return {glm::vec2(d, d), glm::vec2(d, -d), glm::vec2(-d, d), glm::vec2(-d, -d),
            glm::vec2(d, 0), glm::vec2(-d, 0), glm::vec2(0, d),  glm::vec2(0, -d)};
}
constexpr auto enumNames(LightMode) {
    return std::array{std::pair{LightMode::Directional, "directional"},
                      std::pair{LightMode::Filtered, "filtered"}, std::pair{LightMode::Ibl, "ibl"},
                      std::pair{LightMode::OccludedIbl, "occluded-ibl"}};
}
constexpr auto enumNames(ShadowFilter) {
    return std::array{std::pair{ShadowFilter::Naive, "naive"},
                      std::pair{ShadowFilter::Offset, "offset"},
                      std::pair{ShadowFilter::OffsetPcf, "offset-pcf"},
                      std::pair{ShadowFilter::OffsetPcfJitter, "offset-pcf-jitter"},
                      std::pair{ShadowFilter::None, "none"}};
}

inline constexpr int kCubeFaceSize = 32;

struct Settings {
    LightMode mode = LightMode::Directional;
    glm::vec3 direction{0.0f, 1.0f, 0.0f}; // towards the light (any non-zero length)
    glm::vec3 irradiance{1.0f};            // E0, RGB, on a surface facing the light
    ShadowFilter filter = ShadowFilter::OffsetPcfJitter;
    int shadowMapSize = 2048;       // texels per side, [16, min(8192, GL_MAX_TEXTURE_SIZE)]
    float depthOffset = 1e-3f;      // constant part of the shadow offset, mesh units
    float slopeOffset = 1.0f;       // multiplier of the slope-scaled part (irradiance_shadow.glsl)
    int jitterSamples = 8;          // PCF lookups of OffsetPcfJitter, [1, 16]
    float jitterRadius = 1.5f;      // their disk radius in texels
    float ior = 1.3f;               // η, relative index of refraction, [1, 4]
    float envIntensity = 1.0f;      // multiplies the environment radiance
    float envRotation = 0.0f;       // radians about +y
    int occludedSamplesPerStep = 4; // shadow maps per step, [1, 64]
    int occludedTotalSamples = 256; // K, [1, 2^20]
    uint64_t seed = 1;              // environment samples of OccludedIbl
};
// The description of Settings' members (core/fields.h).
template <class V> void fields(V& v, Settings& s) {
    v("mode", s.mode, "lighting mode");
    v("direction", s.direction, "towards the light");
    v("irradiance", s.irradiance, "E0, RGB, on a surface facing the light", core::Limits{0, 1e6});
    v("filter", s.filter, "shadow-map filter (thesis Fig. 3.3)");
    v("shadow_map_size", s.shadowMapSize, "shadow-map texels per side", core::Limits{16, 8192});
    v("depth_offset", s.depthOffset, "constant shadow offset, mesh units", core::Limits{0, 1});
    v("slope_offset", s.slopeOffset, "slope-scaled shadow offset multiplier", core::Limits{0, 1e3});
    v("jitter_samples", s.jitterSamples, "PCF lookups of offset-pcf-jitter", core::Limits{1, 16});
    v("jitter_radius", s.jitterRadius, "their disk radius in texels", core::Limits{0, 64});
    v("ior", s.ior, "relative index of refraction η (set from the material)", core::Limits{1, 4});
    v("env_intensity", s.envIntensity, "environment radiance multiplier", core::Limits{0, 1e6});
    v("env_rotation", s.envRotation, "environment rotation about +y, radians");
    v("occluded_per_step", s.occludedSamplesPerStep, "occluded IBL shadow maps per step",
      core::Limits{1, 64});
    v("occluded_samples", s.occludedTotalSamples, "occluded IBL environment samples K",
      core::Limits{1, 1048576});
    v("seed", s.seed, "seed of the environment samples");
}

// Throws core::Error naming the first bad setting (see the header comment). maxTextureSize: the
// GL limit (0 = do not check against it).
void validateSettings(const Settings& s, int maxTextureSize = 0);

// Ft(η, cos θ) = 1 − R of the exact unpolarised Fresnel equations (CPU, double); 0 for cos <= 0.
double fresnelTransmittance(double cosTheta, double eta);

class ShadowMaps;

class Stage {
  public:
    // shaderDir: the project's shaders/ folder. Compiles the programs (core::Error with file and
    // line on failure). Needs a current GL context.
    explicit Stage(std::filesystem::path shaderDir);
    ~Stage();
    Stage(const Stage&) = delete;
    Stage& operator=(const Stage&) = delete;

    // Hot reload: rebuilds exactly the programs whose shader files (shaderRecords()) include
    // one of `changed`; a failed one keeps its last good program.
    shader::Reloaded reloadShaders(const std::vector<std::filesystem::path>& changed);
    // "irradiance_shadow", "irradiance_direct.comp", "irradiance_ibl.comp",
    // "irradiance_cubemap.comp", "irradiance_occluded.comp".
    const shader::Records& shaderRecords() const { return m_records; }

    // Uploads the mesh (for shadow maps) and the points (positions in mesh units, normals of
    // any non-zero length, normalised here; results come back in this order). Throws
    // core::Error for an empty mesh, mismatched sizes, non-finite values or zero normals.
    // Cancels a running occluded computation.
    void setScene(const mesh::Mesh& m, const std::vector<glm::vec3>& positions,
                  const std::vector<glm::vec3>& normals);
    void setScene(const mesh::Mesh& m, const pointcloud::PointCloud& cloud);
    size_t pointCount() const { return m_pointCount; }

    // Projected texture of the Filtered mode: RGB floats, row 0 at the top, finite, >= 0.
    void setProjectedTexture(int width, int height, const std::vector<float>& rgb,
                             const std::string& name = "projected texture");
    // PNG / JPG (stb_image; 8-bit sRGB decoded to linear) or EXR (R, G, B). core::Error(path).
    void loadProjectedTexture(const std::filesystem::path& path);
    void useCheckerTexture(); // the default

    // The environment of Ibl / OccludedIbl (validated; core::Error naming `name` / the path).
    void setEnvironment(const EnvironmentMap& env, const std::string& name = "environment");
    void loadEnvironment(const std::filesystem::path& exr);
    bool hasEnvironment() const { return m_env.width > 0; }
    const EnvironmentMap& environment() const { return m_env; }

    // Directional / Filtered / Ibl: the full result at once; OccludedIbl: runs
    // beginOccluded + stepOccluded to the end. One value per point, input order. Also left on
    // the GPU in resultBuffer(). Ibl modes throw core::Error when no environment is set.
    std::vector<glm::vec3> compute(const Settings& s);

    // Directional / Filtered E_t as its two factors, E_t = E_u · V: the unshadowed E_u (the
    // same settings with ShadowFilter::None) and the visibility V of s.filter (the result's
    // w). They have different precisions across drivers: E_u is float32 arithmetic (a few
    // ulp), V a mean of bilinear depth comparisons whose weights another sampler rounds
    // differently (kVisibilityTolerance). Runs compute twice, `s` last, so resultBuffer()
    // holds what compute(s) leaves. Other modes: core::Error.
    struct Factors {
        std::vector<glm::vec3> unshadowed;
        std::vector<float> visibility;
    };
    Factors factors(const Settings& s);
    // How far another conforming rasteriser may move each point's V of `s` (Directional /
    // Filtered; core::Error otherwise), absolute, beyond the samplers' weights
    // (kVisibilityTolerance). GL leaves the vertices' sub-pixel precision to the driver
    // (GL_SUBPIXEL_BITS >= 4: a vertex lands within 1/32 texel of its exact place, so two
    // drivers' within 1/16 of each other), so a silhouette of the shadow map may lie
    // kRasterShiftTexels elsewhere and flip the comparisons of the texels it crosses. Measured
    // here: V again from maps drawn to each of rasterShifts(), per point
    // max_shift |V_shifted − V|. Eight more shadow passes; computes `s` last, so resultBuffer()
    // holds what compute(s) leaves.
    std::vector<float> visibilitySpread(const Settings& s);
    // Directional / Filtered only: compute(s) with the shadow map drawn `shift` texels aside (an
    // emulated other rasteriser; visibilitySpread, tests). The result's w is V.
    std::vector<glm::vec4> computeShifted(const Settings& s, glm::vec2 shift);
    // Every shadow map from the next compute on drawn with each vertex moved on its own
    // (another rasteriser emulated: gl/vertex_snap.h; tests); {} to stop.
    void setVertexSnap(const gl::VertexSnap& snap);
    // How far two conforming drivers' E_u of `s` may lie apart, absolute, beyond float32
    // arithmetic: 0 but for filtered light, whose T(uv) the shader filters in float from a uv
    // that drivers round a few ulp apart (irradiance_direct.comp): a bilinear weight then moves
    // by N·δ (N the texture's larger side, δ = 8·2^-24, uv in [0, 1]), |ΔT| <= 2·N·δ·(max T −
    // min T), and |ΔE_u| <= max E0 · |ΔT| (Ft·cos <= 1).
    double unshadowedSpread(const Settings& s) const;

    // Occluded IBL, incremental. beginOccluded draws the samples and clears the sums;
    // stepOccluded processes the next occludedSamplesPerStep samples and returns true when all
    // K are done (false while more remain; also false when nothing is running). `shift`: every
    // sample's shadow map drawn that many texels aside (an emulated other rasteriser:
    // occludedRasterSpread, tests).
    void beginOccluded(const Settings& s, glm::vec2 shift = glm::vec2(0.0f));
    bool stepOccluded();
    bool occludedRunning() const { return m_occ.active; }
    int occludedSamplesDone() const { return m_occ.done; }
    int occludedSamplesTotal() const { return m_occ.total; } // K of the last beginOccluded
    float occludedProgress() const; // samples done / K, 0 when nothing was begun
    // The estimate from the samples done so far (mean of Y_k; empty before the first step or
    // after cancel) and its standard error per channel (sqrt of the sample variance / k; 0 for
    // k < 2).
    std::vector<glm::vec3> occludedResult() const;
    std::vector<glm::vec3> occludedStdError() const;
    void cancelOccluded(); // discards the running computation
    // OccludedIbl's estimate with every V = 1, per normal: U(n) = (1/K) Σ_k weight_k · Ft(η,
    // n·ω_k) · max(0, n·ω_k) over the same K samples (the same float directions) that
    // beginOccluded(s) draws, in double on the CPU (parallel over the normals). It bounds how far
    // two conforming drivers' E_t may lie apart: E_t sums each sample's term times its V_k, each
    // V_k within kVisibilityTolerance, so |ΔE_t| <= kVisibilityTolerance · U. Needs an environment
    // (core::Error); touches no GL.
    std::vector<glm::vec3> occludedUnshadowed(const Settings& s,
                                              const std::vector<glm::vec3>& normals) const;
    // OccludedIbl run to the end with every shadow map drawn `shift` texels aside (an emulated
    // other rasteriser), E_t per point; the sums are this run's afterwards.
    std::vector<glm::vec3> occludedShifted(const Settings& s, glm::vec2 shift);
    // How far another conforming rasteriser may move each point's occluded E_t of `s` (per
    // channel, absolute), beyond the samplers' weights (occludedUnshadowed's bound): as
    // visibilitySpread measures V's, each sample's term Y_k again with its map drawn to each of
    // rasterShifts(), per point (1/K) Σ_k max_shift |Y_k,shifted − Y_k| (per sample, so
    // that moves of different samples do not cancel). 9K shadow passes of one sample each; runs
    // `s` last, so the sums and resultBuffer() hold what compute(s) leaves.
    std::vector<glm::vec3> occludedRasterSpread(const Settings& s);

    // For inspector panels (0 until made): a GL_TEXTURE_2D view of shadow map 0 (depth, the
    // last directional light or the first sample of the last occluded step); the environment
    // as GL_RGB32F lat-long texture; the irradiance cubemap (GL_RGBA32F, without
    // envIntensity); the projected texture; the SSBO of vec4 per point holding the last
    // compute() result (rgb = E_t, w = visibility of Directional / Filtered, else 1).
    GLuint shadowMapTexture() const;
    GLuint environmentTexture() const { return m_envTexture.id(); }
    GLuint irradianceCubemap() const { return m_cube.id(); }
    GLuint projectedTexture() const { return m_projected.id(); }
    GLuint resultBuffer() const { return m_result.id(); }
    // The light frame of the last Directional / Filtered compute().
    const LightFrame& lastLightFrame() const { return m_lastFrame; }

  private:
    // OccludedIbl's K samples for s: world direction (xyz, the float the shader reads) and
    // weight times envIntensity (rgb).
    struct OccludedSamples {
        std::vector<glm::vec4> dirs, weights;
    };
    OccludedSamples occludedSamples(const Settings& s) const;

    struct Occluded {
        bool active = false;
        Settings settings;
        OccludedSamples samples;
        int done = 0, total = 0;
        int current = 0;       // which of m_sums holds the sums
        glm::vec2 shift{0.0f}; // every shadow map drawn this many texels aside
    };

    // Draws the maps of samples [first, first + count) `shift` texels aside and adds their terms
    // to the sums (Σ Y, Σ Y² per point) in `prev`, written to `next` (irradiance_occluded.comp).
    void dispatchOccluded(const Settings& s, const OccludedSamples& samples, int first, int count,
                          GLuint prev, GLuint next, glm::vec2 shift);
    std::vector<glm::vec3> readResult() const;
    void ensureCubemap(float ior);
    void setShadowUniforms(const gl::Program& p, const Settings& s) const;
    void bindShadowSamplers() const;
    void dispatchPoints(const gl::Program& p) const;
    std::vector<glm::vec3> computeDirect(const Settings& s, glm::vec2 shift = glm::vec2(0.0f));
    std::vector<glm::vec3> computeIbl(const Settings& s);

    void install(const std::string& name, gl::Program program);

    shader::Sources m_sources;
    shader::Records m_records;
    std::unique_ptr<ShadowMaps> m_shadow;
    gl::Program m_direct, m_ibl, m_cubeProgram, m_occluded;
    gl::Buffer m_points, m_result;
    gl::Buffer m_sums[2];
    size_t m_pointCount = 0;
    BoundingSphere m_bounds;
    LightFrame m_lastFrame;
    gl::Texture m_projected, m_envTexture, m_cube;
    int m_projectedSide = 0;                            // the larger of width and height
    float m_projectedMin = 0.0f, m_projectedMax = 0.0f; // over every channel
    gl::Buffer m_cubeTexels; // m_cube's texels, which irradiance_ibl.comp filters itself
    EnvironmentMap m_env;
    uint64_t m_envGeneration = 0, m_cubeGeneration = ~0ull;
    float m_cubeIor = -1.0f;
    Occluded m_occ;
};

} // namespace irradiance
