// `bssrdf-workbench compare --geometry`: every model × shape × preset × channel, the model's
// BSSRDF-integrated image of a shape of the suite against the volumetric path-traced image
// (pipeline/geometry_scoring.h has every definition). References are cached on disk by shape,
// medium and settings (compareCacheDir()/geometry). Outputs in DIR: scores.json (schema below),
// report.md and report.html (a model × shape summary and per shape a table and, per preset and
// channel, one picture: reference and models in the top row, signed error maps below),
// images/*.png (--pictures: of the channels listed; --no-plots: none).
//
// scores.json = {"schema": "bssrdf-workbench-geometry-scores", "version": 1,
//   "settings": {"size", "reference_spp", "model_spp", "sampling", "seed"},
//   "rel_l2": "<its definition>", "shapes": [{"spec", "kind", "light": [x, y, z],
//   "longest_axis_ld"}], "presets": [...], "models": [...],
//   "rows": [{"case", "model", "shape", "preset", "channel": "R"|"G"|"B", "ld_mm", "radius_mm",
//   "rel_l2", "rel_l2_se", "mean_ratio", "mean_ratio_se", "pixels", "rank", "tie",
//   "problem" (null, or why the model has no image of this case: its scores are then null)}],
//   "skipped": [{"preset", "channel", "reason"}]}
// Rows are in case order (shape, preset, channel), models in the library's (name) order within a
// case; rank 1 is the best of its (shape, preset, channel), ties as the scoreboard's.
//
// --shard K/N runs cases K−1, K−1+N, … only and writes DIR/shard.json (the same rows, unranked,
// with the run's "cases" count and "shard") and their pictures; `merge --geometry DIR… --out D`
// checks that the shards are of one run and complete, ranks, and writes D as one process would
// (scores.json byte for byte). --baseline FILE --fail-if-worse PCT: exit 1 when a row's rel_l2
// grew by more than PCT % over the baseline's same (model, shape, preset, channel) and by more
// than 3 standard errors of the difference.
#pragma once

#include "pipeline/geometry_scoring.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace app {

// The options of `compare --geometry` (compare_command.cpp fills the ones it shares with
// `compare`: models, presets, baseline, fail-if-worse, out, plots).
struct GeometryArgs {
    std::vector<std::string> models;  // default: every materials/*.bssrdf
    std::vector<std::string> presets; // default: Marble and Skin1
    std::vector<std::string> shapes;  // default: mesh::defaultSuite()
    GeometrySettings settings;
    std::string sampling;         // uniform | disk (default: the settings')
    std::string shard;            // K/N
    std::string pictures = "RGB"; // the channels whose cases get a picture ("" none)
    bool plots = true;
    std::string baseline;
    std::optional<double> failIfWorse;
    std::string out;
};

int runCompareGeometryCli(const std::filesystem::path& root, const GeometryArgs& a);
int runMergeGeometryCli(const std::vector<std::string>& dirs, const std::string& out);

// The report of a finished run (geometry_report.cpp): report.md and report.html in `dir`, the
// pictures already in dir/images (named by geometryPictureName).
struct GeometryReport {
    GeometrySettings settings;
    std::vector<std::string> shapes, presets, models;
    std::vector<GeometryRow> rows;
};
void writeGeometryReports(const std::filesystem::path& dir, const GeometryReport& r);
// The reports' model × shape summary as plain text: what `compare --geometry` prints.
std::string geometrySummaryText(const GeometryReport& r);
std::string geometryPictureName(const std::string& shape, const std::string& preset,
                                const std::string& channel);

} // namespace app
