// What a stage contributes to a capture (format v1: captures/README.md): its outputs, each a
// table or an image with the kind and tolerance replay compares it by, and the input files it
// read besides the models. Each stage makes its own entries (its capture(), wired in
// Workbench::capture in pipeline order); captures/ writes and compares them without knowing any
// stage. The tolerances' reasons are stated in each entry's note (written into the manifest).
#pragma once

#include "capture/capture.h"
#include "core/text.h"
#include "irradiance/irradiance.h"
#include "pathtrace/lit_sphere.h"

#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace app {

struct CaptureEntry {
    enum class Kind {
        Csv,     // a table, compared value by value within absTol + relTol·|recorded|
        CsvStat, // a Monte Carlo table (values with standard errors): z-tests at alpha
        Exr,     // an image (EXR), compared pixel by pixel within absTol + relTol·|recorded|
        ExrStat, // a Monte Carlo image with a variance per pixel: per-pixel z-tests at alpha
        // an image recorded as the stage's input for replays (CaptureEntries::recordedImage):
        // not compared, its hash checked
        ExrInput,
    };
    Kind kind = Kind::Csv;
    std::string stage, file; // "pencil_plot.dipole", "pencil_plot_dipole.csv"
    std::string key;         // tables: the column rows are matched by ("" = row order)
    capture::Table table;    // Csv, CsvStat
    pathtrace::Image image;  // Exr, ExrStat
    double absTol = 0, relTol = 0;
    double alpha = 0; // the statistical kinds' false-alarm rate, Bonferroni over all values
    std::string note; // why this tolerance
    // Csv: one more absolute tolerance per value (same shape as `table`), made on the replaying
    // driver: the spread the GLSL precision rules allow the model's values (bssrdf/conditioning.h),
    // doubled; empty: none. Not recorded; `conditioningNote` says what it is, or why there is none.
    capture::Table conditioning;
    std::string conditioningNote;
    // false: made only to replay captures recorded before the stage was split into others
    // (record leaves it out; a replay compares it where the manifest lists it)
    bool recorded = true;
};

// An entry of `kind` for `stage`: its file is the stage's name with '.' → '_' and the kind's
// extension ("scene.render" → scene_render.exr), its rows matched by the column `key` ("": by
// row order).
inline CaptureEntry captureEntry(CaptureEntry::Kind kind, const std::string& stage,
                                 const std::string& key = "") {
    CaptureEntry e;
    e.kind = kind;
    e.stage = stage;
    e.file = stage;
    std::replace(e.file.begin(), e.file.end(), '.', '_');
    const bool image = kind == CaptureEntry::Kind::Exr || kind == CaptureEntry::Kind::ExrStat ||
                       kind == CaptureEntry::Kind::ExrInput;
    e.file += image ? ".exr" : ".csv";
    e.key = key;
    return e;
}

struct CaptureEntries {
    int traceX = -1, traceY = -1; // the scene's traced pixel (-1: none is recorded)
    // Set by a replay: the stages also make what only a comparison uses (CaptureEntry::
    // conditioning, one more program and several dispatches per model); a record leaves it out.
    bool forReplay = false;
    // Set by a replay (not by --update): the recorded image of an output of kind exr_input, or
    // none, for a stage that takes its own recorded output as an input (the scene's G-buffer: a
    // different rasteriser's sub-pixel placement must not move what is traced from it).
    // Throws core::Error when the recorded file cannot be read.
    std::function<std::optional<pathtrace::Image>(const std::string& stage)> recordedImage;
    // Set by a replay (not by --update): the recorded table of an output of kind csv, or none,
    // for a stage whose later stages take it as their input (the scene's irradiance: another
    // sampler's shadow-map weights must not move the render traced from it). Throws
    // core::Error when the recorded file cannot be read.
    std::function<std::optional<capture::Table>(const std::string& stage)> recordedTable;
    // What a stage tells the replay's reader about its inputs (printed as NOTE lines).
    std::vector<std::string> notes;
    std::vector<CaptureEntry> entries;      // in pipeline order
    std::vector<capture::ModelFile> inputs; // input files besides the models (meshes)
    std::vector<std::string> missing;       // "model: why" for outputs a stage could not make
    // Settings as they ran where the settings left the choice to the machine: `auto` tracer
    // devices become the device that traced ("reference", "device", "cpu"). The manifest keeps
    // these, so a replay runs the same estimator on any machine (the CPU walk splits paths, the
    // GL tracer does not: their far bins differ in variance though not in mean).
    struct Resolved {
        std::string section, key, value;
    };
    std::vector<Resolved> resolved;
};

// The shadow-map visibility V per point or texel (`key`: its index column), recorded apart from
// the unshadowed irradiance (irradiance::Stage::factors) with V's own tolerance.
inline CaptureEntry visibilityEntry(const std::string& stage, const std::string& key) {
    CaptureEntry v = captureEntry(CaptureEntry::Kind::Csv, stage, key);
    v.absTol = irradiance::kVisibilityTolerance;
    v.note = "shadow-map visibility, a mean of bilinear depth comparisons: 2^-7 absolute (2^-8 "
             "per weight axis, the samplers' subtexel precision)";
    v.table.columns = {key, "V"};
    return v;
}

// The tail of an unshadowed irradiance entry's note for the projected texture's spread
// (irradiance::Stage::unshadowedSpread, already in its absTol): "" when there is none.
inline std::string projectedSpreadNote(double spread) {
    return spread > 0 ? " + " + core::formatNumber(spread, 3) +
                            " (the projected texture's weights, uv a few ulp apart)"
                      : std::string();
}

// Occluded image based lighting: the per-value allowance of a table of E_t (columns key, R, G,
// B; its rows those of `unshadowed` and `raster`) for another driver. E_t sums K shadow-mapped
// samples, each V_k within irradiance::kVisibilityTolerance between samplers, so the sums lie
// within kVisibilityTolerance · U of each other, U the same sum with every V = 1
// (irradiance::Stage::occludedUnshadowed); plus how far E_t moves with every sample's map drawn
// 1/16 texel aside, another rasteriser's sub-pixel precision (Stage::occludedRasterSpread).
// Both made on the replaying machine.
inline void addOcclusionAllowance(CaptureEntry& e, const std::vector<glm::vec3>& unshadowed,
                                  const std::vector<glm::vec3>& raster) {
    e.conditioning.columns = e.table.columns;
    for (size_t i = 0; i < unshadowed.size(); ++i) {
        const glm::dvec3 a = irradiance::kVisibilityTolerance * glm::dvec3(unshadowed[i]) +
                             glm::dvec3(i < raster.size() ? raster[i] : glm::vec3(0.0f));
        e.conditioning.rows.push_back({0.0, a.x, a.y, a.z});
    }
    e.conditioningNote = "2^-7 of each value's sum without shadows (the K samples' visibilities, "
                         "each a mean of bilinear depth comparisons another sampler weights "
                         "differently), plus how far it moves with every sample's shadow map "
                         "drawn 1/16 texel aside (along either axis or both; the rasterisers' "
                         "sub-pixel precision)";
}

// The per-value allowance of a visibility entry (columns key, V; its rows those of `spread`) for
// another driver's rasteriser: how far V moves with the shadow map drawn
// irradiance::kRasterShiftTexels aside (irradiance::Stage::visibilitySpread, made on the
// replaying machine).
inline void addRasterAllowance(CaptureEntry& e, const std::vector<float>& spread) {
    e.conditioning.columns = e.table.columns;
    for (float x : spread)
        e.conditioning.rows.push_back({0.0, double(x)});
    e.conditioningNote = "how far V moves with the shadow map drawn 1/16 texel aside (along "
                         "either axis or both; the rasterisers' sub-pixel precision)";
}

// GPU float32 evaluation: GLSL guarantees exp/pow to (3 + 2|x|) ulp; with |x| up to ~30 in
// the profile's tail that is ~63 ulp, i.e. 63 · 2^-24 ≈ 3.8e-6 relative, plus the same again
// for the arithmetic around it. 1e-5 relative covers a different driver where the model does not
// cancel; where it does, the pencil plot adds each value's conditioning (CaptureEntry::
// conditioning, bssrdf/conditioning.h). On the same driver replays are bit-exact.
inline constexpr double kProfileRelTol = 1e-5;
// Monte Carlo outputs (path-traced reference, slice, images): per-value z-tests, Bonferroni over
// every value of the output.
inline constexpr double kMonteCarloAlpha = 1e-3;

} // namespace app
