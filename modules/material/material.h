// material: the parameter module of thesis 3.1.1 / 3.4 / 3.6.1.
//   - MaterialParams: σa, σs (RGB, 1/mm), g, η, scale (mm per model unit); validation with
//     messages naming the offending field and channel.
//   - presets: measured media of Jensen et al. 2001 and Narasimhan et al. 2006
//     (materials/presets.json: σ′s, σa in 1/mm, η, each table with its source).
//   - the R_dr / l_d parametrisation (Jensen & Buhler 2002): given α′ solved per channel from
//     the model's own DiffuseReflectance (GPU bisection, see invertRdr in bssrdf/gpu), thesis
//     eqs. (3.3)–(3.5) give σ′t = 1/(l_d √(3(1−α′))), σ′s = α′σ′t, σa = σ′t − σ′s, and the
//     similarity relation (2.24) gives σs = σ′s/(1−g).
//   - the colour swatch of thesis 3.6.1: an RGB triple rescaled to luminance 0.75.
#pragma once

#include "core/limits.h"

#include <glm/vec3.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace material {

struct MaterialParams {
    glm::dvec3 sigmaA{0.0021, 0.0041, 0.0071}; // 1/mm (Marble)
    glm::dvec3 sigmaS{2.19, 2.62, 3.00};       // 1/mm
    double g = 0.0;
    double eta = 1.3;
    double scale = 50.0; // mm per model unit
};
// The description of MaterialParams' members (core/fields.h).
template <class V> void fields(V& v, MaterialParams& p) {
    v("sigma_a", p.sigmaA, "absorption coefficient σa, 1/mm", core::Limits{0, 1e6});
    v("sigma_s", p.sigmaS, "scattering coefficient σs, 1/mm", core::Limits{0, 1e6});
    v("g", p.g, "Henyey-Greenstein mean cosine", core::Limits{-1, 1});
    v("eta", p.eta, "relative index of refraction η", core::Limits{0.01, 100});
    v("scale", p.scale, "mm per mesh unit", core::Limits{1e-6, 1e9});
}

// Throws core::Error("<what>", 0, msg) naming the field and channel: σa < 0, σs ≤ 0,
// non-finite σ, η ≤ 0 or non-finite, |g| ≥ 1, scale ≤ 0. σa = 0 is valid (Spectralon).
void validate(const MaterialParams& p, const std::string& what = "material");

struct Preset {
    std::string name;
    glm::dvec3 sigmaSPrime; // reduced scattering, 1/mm (σs (1 − g) for a table that gives g)
    glm::dvec3 sigmaA;      // 1/mm
    double eta = 1.3;
    std::string table;     // the table's id ("jensen2001")
    std::string tableName; // "Jensen et al. 2001"
    std::string source;    // the table's citation
    std::string note;      // the entry's notes and disputes in words ("" for none)
    bool disputed = false; // the published copies disagree on a value
    bool hasG = false;     // the table gives g per channel (publishedG)
    glm::dvec3 publishedG{0.0};
    std::string unusable; // why the BSSRDF models cannot use it ("" when they can)
};
// Parses presets.json (version 2: "tables", each with id, name, source, form "sigma_s_prime" or
// "sigma_s_and_g", eta and its presets; version 1: one "presets" array of σ′s and σa). Throws
// core::Error(path, line, msg) on bad JSON or fields, naming the preset or table and its line:
// missing or non-numeric values, negative σ, |g| >= 1, a name used twice.
std::vector<Preset> loadPresets(const std::filesystem::path& file);
const Preset* findPreset(const std::vector<Preset>& presets, const std::string& name);
// "unknown preset 'Marbel' (did you mean 'Marble'? known: Apple, …)": the message for a name
// findPreset did not find, with the nearest name when one is close (core::nearestName).
std::string unknownPresetMessage(const std::vector<Preset>& presets, const std::string& name);
// σs = σ′s/(1−g), σa and η from the preset; g and scale kept. Throws core::Error naming the
// preset when it is `unusable` (σs = 0 in a channel).
MaterialParams applyPreset(const Preset& preset, MaterialParams base);

// Derived quantities of the classical diffusion theory (thesis 2.4): per channel.
glm::dvec3 reducedAlbedo(const MaterialParams& p);       // α′ = σ′s/σ′t
glm::dvec3 diffuseMeanFreePath(const MaterialParams& p); // l_d = 1/σtr, σtr = √(3σa σ′t)

// R_dr / l_d → σ given the solved α′ (thesis eqs. 3.3–3.5 and 2.24). Throws core::Error when
// α′ = 1 or l_d is not positive/finite.
struct SigmaPair {
    glm::dvec3 sigmaA, sigmaS;
};
SigmaPair sigmaFromAlphaPrime(const glm::dvec3& alphaPrime, const glm::dvec3& ld, double g);

// Bisection of thesis 3.4 over α′ ∈ [0,1]: `evaluate` returns R_dr for a batch of α′ values
// (one call per round, `subdivisions`+1 points per channel, evaluated on the GPU by the
// caller); `rounds` rounds. Grid points are float32 values (what the GPU sees); once a bracket
// holds no more floats than points, the round uses consecutive floats, and the result is
// linearly interpolated inside the last bracket. Returns α′ per channel or throws core::Error
// when a target lies outside [R_dr(0), R_dr(1)] (the message names the channel and range).
using RdrBatch = std::function<std::vector<glm::dvec3>(const std::vector<glm::dvec3>& alphaPrime)>;
glm::dvec3 solveAlphaPrime(const glm::dvec3& targetRdr, const RdrBatch& evaluate,
                           int subdivisions = 512, int rounds = 3);

// Thesis 3.6.1: interpret an RGB triple as a colour rescaled to Rec.709 luminance 0.75
// (core::luminance).
glm::dvec3 swatch(const glm::dvec3& rgb);

} // namespace material
