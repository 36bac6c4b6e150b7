// The geometry scores (issue "Where models break"): each model's BSSRDF-integrated image of a
// shape of the suite (mesh/suite.h) against the volumetric path-traced image of the same shape,
// light and camera, shared by `compare --geometry` (cli/compare_geometry.cpp) and the
// Scoreboard's geometry tab. One case is (shape, preset, channel):
//   Scale: the shape's lengths are in l_d of the case's channel, l_d = 1/√(3σa(σa + σs(1 − g))),
//   so the mesh is the suite's times l_d mm (half its longest axis is the setup's radiusMm: the
//   tracers' normalisation then gives back exactly these millimetres).
//   Reference: the lit mesh path tracer (pathtrace/mesh_tracer.h) with the channel's medium in
//   all three of its channels: three independent estimates of one image (distinct random
//   streams), averaged, variance of the mean (v0 + v1 + v2)/9. Cached on disk
//   (compareCacheDir()/geometry) by a key of kGeometryCacheVersion, the spec, the medium, the
//   image size, paths per pixel, seed and light; an entry of another version, unreadable or of
//   the wrong size, is traced again.
//   Model: integrate::ImageIntegrator on the same mesh, the material the channel's medium in
//   all three channels, the output's channel `channel` (a model's per-channel parameters stay
//   those of the channel scored).
//   Pixels scored: those whose centre ray hits the object in both images (the object, lit or
//   not: a back-lit slab is scored on its transmission).
//   rel_l2 (imageRelativeL2 below): the relative L2 error of the model image over those pixels
//   with both images' noise removed, and its standard error from both images' variances;
//   mean_ratio = Σ M / Σ R with its standard error. Ties and ranks within (shape, preset,
//   channel) as the scoreboard: |Δ| < 2√(se_a² + se_b²) of the best shares its rank.
#pragma once

#include "integrate/integrate.h"
#include "mesh/suite.h"
#include "pathtrace/pathtrace.h"
#include "pipeline/model_stages.h"

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace app {

inline constexpr int kGeometryCacheVersion = 1;

// The settings of a geometry comparison; `compare --geometry`, the Scoreboard's geometry tab
// and captures share these defaults.
struct GeometrySettings {
    // The defaults run the whole suite on Marble and Skin1 (150 cases, every model) on 2 CPU
    // cores with llvmpipe in a quarter of an hour (README, docs/geometry/).
    int size = 48;              // image side, pixels
    uint64_t referenceSpp = 64; // reference paths per covered pixel, each of 3 estimates
    uint64_t modelSpp = 32;     // BSSRDF samples per pixel
    integrate::Sampling sampling = integrate::Sampling::Disk;
    uint64_t seed = 1;
};
template <class V> void fields(V& v, GeometrySettings& s) {
    v("size", s.size, "image side in pixels", core::Limits{8, 1024});
    v("reference_spp", s.referenceSpp, "reference paths per covered pixel (x3 estimates)",
      core::Limits{1, 1e6});
    v("model_spp", s.modelSpp, "BSSRDF samples per pixel", core::Limits{1, 1e6});
    v("sampling", s.sampling, "BSSRDF integration: uniform area sampling or disk probe rays");
    v("seed", s.seed, "random seed");
}

// One channel's image: mean and variance of the mean per pixel, row-major, top row first, and
// whether the pixel's centre ray hits the object.
struct ChannelImage {
    int width = 0, height = 0;
    std::vector<double> mean, variance;
    std::vector<char> covered;
};

struct GeometryCase {
    std::string shape; // canonical spec
    std::string preset;
    int channel = 0;
    double ldMm = 0;
    pathtrace::Medium medium;
};
struct GeometrySkip {
    std::string preset;
    int channel = 0;
    std::string reason;
};
// l_d = 1 / sqrt(3 σa σt') of `preset`'s `channel` (0 R, 1 G, 2 B) in mm, the unit of the
// suite's lengths; 0 when there is none (σa = 0). core::Error for an unknown preset.
double geometryLdMm(const std::vector<material::Preset>& presetTable, const std::string& preset,
                    int channel);
// The cases of shapes × presets × channels in this order (shape outermost); channels without an
// l_d (σa = 0) are skipped and said. Specs are checked (core::Error naming `label`).
std::vector<GeometryCase> geometryCases(const std::vector<material::Preset>& presetTable,
                                        const std::vector<std::string>& shapes,
                                        const std::vector<std::string>& presets,
                                        std::vector<GeometrySkip>* skipped = nullptr);

// The scored quantities of one model image against its reference.
struct ImageScore {
    double relL2 = 0, relL2Se = 0, meanRatio = 0, meanRatioSe = 0;
    size_t pixels = 0;
    std::string problem; // why there is no score ("" when there is)
};
// rel_l2² = (Σ(M − R)² − Σ(v_M + v_R)) / (Σ R² − Σ v_R) over the pixels covered in both; its
// variance by the delta method (Var d² = 4δ²v + 2v², Var R² = 4R²v_R + 2v_R²,
// Cov(d², R²) = −4δR v_R + 2v_R², δ² estimated without its noise); se(e) = √(e² + se(e²)) − e
// and e = 0 when the noise explains the whole difference, as core::relativeError.
ImageScore imageRelativeL2(const ChannelImage& model, const ChannelImage& ref);

struct GeometryRow {
    std::string model, shape, preset, channel; // channel "R" | "G" | "B"
    double ldMm = 0, radiusMm = 0;
    ImageScore score;
    int rank = 0;
    bool tie = false;
};
// Ranks and ties within each (shape, preset, channel); rows with a problem get rank 0.
void rankGeometryRows(std::vector<GeometryRow>& rows);

// The camera, light and scale of a case.
struct GeometryScene {
    mesh::SuiteShape shape;
    litsphere::Setup setup; // radiusMm, light, size, seed
};
GeometryScene geometryScene(const GeometryCase& c, const GeometrySettings& s);

// The reference image of a case from the cache, or traced (progress(done, total) in paths;
// nullopt when cancelled). Throws core::Error when the trace fails its energy check.
std::optional<ChannelImage>
geometryReference(const GeometryCase& c, const GeometrySettings& s,
                  const std::function<void(uint64_t, uint64_t)>& progress,
                  const std::atomic<bool>* cancel, bool& fromCache);
std::filesystem::path geometryCacheFile(const GeometryCase& c, const GeometrySettings& s);

// The integrator of one model's image of a case with the model set (GL context current;
// core::Error as geometryModelImage), to be stepped by the caller, and the case's channel of its
// image (core::Error naming the model when a covered pixel is not finite).
std::unique_ptr<integrate::ImageIntegrator> geometryIntegrator(const bssrdf::ModelEntry& e,
                                                               const MaterialSettings& material,
                                                               const GeometryCase& c,
                                                               const GeometrySettings& s);
ChannelImage geometryChannelImage(const integrate::ImageIntegrator& ig, const GeometryCase& c,
                                  const std::string& modelName);
// One model's image of a case (GL context current); a model that cannot be integrated there
// (its profile cannot be sampled, NaN, negative) throws core::Error naming it; nullopt when
// cancelled.
std::optional<ChannelImage> geometryModelImage(const bssrdf::ModelEntry& e,
                                               const MaterialSettings& material,
                                               const GeometryCase& c, const GeometrySettings& s,
                                               const std::atomic<bool>* cancel);
// The case's medium in all three channels (the preset's η and g).
MaterialSettings geometryMaterial(const std::vector<material::Preset>& presetTable,
                                  const GeometryCase& c);

} // namespace app
