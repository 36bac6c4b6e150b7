// integrate: the BSSRDF-integrated picture of the lit-sphere setup (thesis 3.5, litsphere.h) on
// the sphere or on any closed mesh, by uniform area sampling or by the disk probe-ray importance
// sampling of King et al. 2013 (sampling/disk_sampling.h), for every model.
//   Pixel value: the radiant exitance at the pixel-centre camera ray's first surface point P
//       M(P) = ∫_A Bssrdf(x, L, P, n(P)) · Ft(η, n(x)·L) · max(0, n(x)·L) · V(x) dA(x)
//   (L the unit light direction, irradiance 1; Ft = 1 − F the exact unpolarised Fresnel
//   transmittance; V(x) = 1 when x sees the light: always where n·L > 0 on the convex sphere, a
//   shadow ray on meshes), the quantity of bssrdf/sphere_integrator.h, which it reproduces on
//   the sphere with uniform sampling.
//   Estimators, per pixel sample:
//     uniform  F = A · f(x), x uniform on the surface (sampling::AreaSampler);
//     disk     F = Σ_hits f(x)/p(x), p the balance-heuristic density over the three axes and
//              the three channels (sampling::DiskSampler; channel c chosen with probability
//              ∝ its kept energy E_m,c, sampling::energyChannelProbabilities); each channel's
//              radial distribution comes from radial_source.h: the model's analytic sampler
//              section, its Gaussian lobes, or else its profile R(r) = Bssrdf(0, n, (r, 0, 0), n)
//              tabulated on the GPU (render::buildProfileTable, no cap), cut at R_m,c keeping all
//              but `energyLoss` of its energy. The disk estimator integrates over |x − P| <= max_c
//              R_m,c: on a plane it gives up exactly that fraction, a bias the tests keep below
//              their noise.
//   The model is evaluated on the GPU (bssrdf::evaluateQueries, translation invariance: Xi = 0,
//   Xo = P − x) with the actual directions, so directional models are integrated as they are.
//   Geometry: the sphere of radius R mm at the origin, or the mesh normalised to one unit on its
//   longest axis, centred, times 2R mm (the lit-mesh convention of pathtrace/mesh_tracer.h);
//   orthographic camera along −z over ±1.1 R, pixel (0, 0) top left.
//   Random numbers: sample s of pixel p draws from Pcg32::forPath(seed', s·P + p), P the pixel
//   count, so an image depends only on (setup, model, seed, samples done), not on threads or on
//   how steps were sized. The disk estimator's samples come in Latin-hypercube blocks of 16
//   (sampling/stratified.h: the strategy-with-radius uniform of DiskSampler::probe and the
//   angle are stratified, block b of pixel p permuted by Pcg32::forPath(seed'', b·P + p)), so
//   each block takes the axes and channels in proportion to their probabilities; uniform area
//   sampling draws independent samples.
//   Accumulation: Σ F and Σ F² per pixel in double, and for the disk estimator Σ B² of its
//   whole blocks' sums B and the current block's partial sum; the image is the mean and the
//   variance of the mean (from the blocks once there are two, sampling::blockVarianceOfMean), as
//   litsphere::Image.
#pragma once

#include "bssrdf/program.h"
#include "core/limits.h"

#include "integrate/radial_source.h"
#include "litsphere/litsphere.h"
#include "mesh/mesh.h"
#include "sampling/disk_sampling.h"
#include "sampling/stratified.h"
#include "sampling/tabulated_radial.h"
#include <glm/vec4.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace integrate {

enum class Sampling { Uniform, Disk };
constexpr auto enumNames(Sampling) {
    return std::array{std::pair{Sampling::Uniform, "uniform"}, std::pair{Sampling::Disk, "disk"}};
}

// The help text of every `axes` setting (this one, the Lit spheres panel's, the Monte Carlo
// render's).
inline constexpr const char* kAxesHelp =
    "disk sampling: probe axes all (N twice, T and B in each sample), uniform (one of three, 1/3 "
    "each), pbrt (N 1/2) or normal";

// The estimator's settings; the Lit spheres panel, `integrate` and captures share these
// defaults (uniform area sampling: what the panel did before importance sampling existed; for
// disk sampling every axis in each sample, the scheme with the least error at equal time on
// the sphere and the bunny and the least variance near edges: README, Importance sampling).
struct Settings {
    Sampling sampling = Sampling::Uniform;
    sampling::AxisScheme axes = sampling::AxisScheme::All;
    double energyLoss = sampling::kDefaultEnergyLoss; // eps of R_m
    uint64_t seed = 1;
};
template <class V> void fields(V& v, Settings& s) {
    v("sampling", s.sampling, "BSSRDF integration: uniform area sampling or disk probe rays");
    v("axes", s.axes, kAxesHelp);
    v("energy_loss", s.energyLoss, "disk sampling: energy given up beyond R_m",
      core::Limits{1e-9, 0.5});
    v("seed", s.seed, "random seed");
}

// The shading points of a rendered view of a mesh (the hierarchical renderer's G-buffer,
// render::Readback): per pixel the surface point and normal in mesh units (w = 1: hit) and the
// camera position, for the Monte Carlo render of the Render panel. The pixel value is then the
// renderer's radiance, with its conventions (render.h, irradiance.h):
//     L_o(P) = Ft(η, cos θo)/π · ∫_A Bssrdf(x, n(x), P, n(P)) · E_t(x) dA(x),
//     E_t(x) = E0 · Ft(η, n(x)·L) · max(0, n(x)·L) · V(x),   cos θo = min(1, |n(P)·ω_o|),
// ω_o towards the camera, V by a shadow ray through the mesh (Embree; the point-cloud pipeline
// uses a shadow map).
struct ViewPoints {
    int width = 0, height = 0;
    std::vector<glm::vec4> position, normal; // mesh units; position.w > 0.5: the pixel hits
    glm::dvec3 camera{0.0};                  // mesh units
    glm::dvec3 lightDir{0, 0, 1};            // towards the light
    glm::dvec3 irradiance{1.0};              // E0, RGB
};

class ImageIntegrator {
  public:
    // The sphere of setup.radiusMm (validated: core::Error("integrate", 0, …) naming the field).
    explicit ImageIntegrator(const litsphere::Setup& setup);
    // A closed, consistently wound mesh (mesh::checkClosedOutward: an open mesh is a
    // core::Error naming it), normalised and scaled as above.
    ImageIntegrator(const litsphere::Setup& setup, mesh::Mesh m, const std::string& name);
    // A view of a mesh (normalised as the scene has it, in mesh units) scaled by `scaleMm`: the
    // Monte Carlo render of the Render panel (ViewPoints above). Not checked for closedness
    // (the scene's meshes are what they are; probe rays find every surface).
    ImageIntegrator(const mesh::Mesh& m, double scaleMm, const std::string& name,
                    const ViewPoints& view);
    ~ImageIntegrator();
    ImageIntegrator(const ImageIntegrator&) = delete;
    ImageIntegrator& operator=(const ImageIntegrator&) = delete;

    // The model and estimator; starts over. `pencilProgram` from
    // bssrdf::buildModelProgram(m, "pencil_profile.comp"). With Sampling::Disk the model's
    // radial distributions are built here (GPU, radialSource) and a profile that cannot be
    // sampled (NaN, negative, no energy, energy that does not converge) is a core::Error naming
    // the model and the radius; a model's sampler section or lobes that fail their checks name
    // the model file and line. On an error the integrator keeps its previous model.
    void setModel(GLuint pencilProgram, const bssrdf::Model& m, const bssrdf::ParamValues& values,
                  const bssrdf::Builtins& b, const Settings& s, const std::string& name);
    // Takes `samplesPerPixel` (>= 1) more samples per pixel; stops early between batches when
    // `cancel` is set (the image then holds whole samples only). Needs the GL context current.
    void step(int samplesPerPixel, const std::atomic<bool>* cancel = nullptr);
    litsphere::Image image() const;
    uint64_t samplesPerPixelDone() const { return m_samples; }
    double seconds() const { return m_seconds; }
    // R_m per channel of the disk sampler (0 before setModel or with uniform sampling).
    std::array<double, 3> radiusMax() const;
    // Model evaluations (hits) so far: the cost of the estimator besides the probe rays.
    uint64_t evaluations() const { return m_evaluations; }
    const litsphere::Setup& setup() const { return m_setup; }
    // Per pixel: 1 where the pixel-centre camera ray hits the surface (the pixels it estimates).
    const std::vector<char>& coveredPixels() const { return m_hit; }

  private:
    struct Geometry;
    void findShadingPoints();

    litsphere::Setup m_setup;
    std::unique_ptr<Geometry> m_geo;
    glm::dvec3 m_light{0, 0, 1};
    // the model
    GLuint m_program = 0;
    std::optional<bssrdf::Model> m_model;
    bssrdf::ParamValues m_values;
    bssrdf::Builtins m_builtins;
    Settings m_settings;
    std::unique_ptr<RadialSource> m_radial;
    std::unique_ptr<sampling::DiskSampler> m_disk;
    // per pixel: shading point (valid when the centre ray hits), Σ F, Σ F²
    std::vector<char> m_hit;
    std::vector<sampling::SurfacePoint> m_shading;
    std::vector<double> m_sum, m_sumSq;
    // per pixel and channel, over the Latin-hypercube blocks (sampling/stratified.h): the
    // current block's partial sum and the whole blocks' Σ B² (their Σ B is m_sum − partial)
    std::vector<double> m_blockPartial, m_blockSumSq;
    std::vector<sampling::BlockStrata<2>> m_strata; // per pixel: its current block's strata
    // step()'s round: per pixel its samples' pending model evaluations, and per (pixel, sample)
    // how many (kept between rounds)
    struct Pending;
    std::vector<std::vector<Pending>> m_pending;
    std::vector<uint32_t> m_pendingCount;
    // the view's conventions (ViewPoints): Wi = n(x), E0, Ft(η, cos θo)/π per pixel
    bool m_view = false;
    glm::dvec3 m_irradiance{1.0};
    std::vector<glm::dvec3> m_toCamera; // per pixel, unit
    uint64_t m_samples = 0, m_evaluations = 0;
    double m_seconds = 0;
};

} // namespace integrate
