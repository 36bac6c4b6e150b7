// `bssrdf-workbench compare`: every model × preset × channel scored against the path-traced
// reference (the scoreboard), with the scores of pipeline/scoring.h. The reference is cached on
// disk by medium and settings (BSSRDF_WORKBENCH_CACHE, else ~/.cache/bssrdf-workbench/reference,
// pipeline/scoring.h: compareCacheDir), so a second run costs only the models. Outputs:
// DIR/scores.json (schema below), DIR/report.md and DIR/report.html (one self-contained page, cells
// coloured by rel_err).
//
// scores.json = {"schema": "bssrdf-workbench-scores", "version": 2, "theta_i": [0],
//   "paths": P, "rel_err": "<its definition>", "rel_err_range_ld": [0.1, 4],
//   "rows": [{"model", "preset", "channel": "R"|"G"|"B", "theta_i", "ld_mm",
//   "rel_err", "rel_err_se", "ratio_1ld", "ratio_1ld_se", "ratio_4ld", "ratio_4ld_se",
//   "total_ratio", "total_ratio_se", "r_err5_ld" (or null), "rank", "tie"}],
//   "skipped": [{"preset", "channel", "reason"}]}   (channels with σa = 0 have no l_d)
//
// At θi > 0 (--theta-i) the rows are scored against the seed 001 estimate of the whole BSSRDF,
// over the plane and the exit directions (pipeline/scoring_oblique.h); such rows add
// "rel_err_dir" and "rel_err_dir_se" (null at θi = 0). The report adds per preset and channel the
// pencil plot of every model with the reference band, the ratio to the reference against r, and at
// θi > 0 polar heatmaps of the relative difference (compare_report.cpp), drawn headless by the
// panels' own plot code.
//
// --baseline FILE --fail-if-worse PCT: exit 1 when a row's rel_err grew by more than PCT % over
// the baseline's same (model, preset, channel, theta_i) and by more than 3 standard errors of
#pragma once

#include "pathtrace/bssrdf_estimate.h"
#include "pipeline/scoring.h"

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace app {

struct CompareArgs {
    std::vector<std::string> models;  // default: every materials/*.bssrdf
    std::vector<std::string> presets; // default: the first table of presets.json (Jensen 2001)
    std::vector<std::string> mco;    // MCML outputs (one, or two independent runs) as the reference
    std::vector<double> thetaI{0.0}; // incidence angles, degrees in [0, 90)
    bool plots = true;               // PNG plots in the reports
    uint64_t paths = 200000;         // per preset and channel
    std::string baseline;            // an earlier scores.json
    std::optional<double> failIfWorse; // percent
    std::string out;                   // output folder
    std::string shard;                 // K/N: every N-th unit (medium and angle), from K
};

// What the report draws besides the table (compare_report.cpp).
struct ProfileCurves { // θi = 0, one preset and channel
    std::string preset;
    int channel = 0;
    double ld = 0;
    std::vector<double> r, ref, refSe; // R_d/(1 − R_sp) and its standard error at bin centres
    std::vector<std::pair<std::string, std::vector<double>>> models; // name, R at r
};
struct SliceMaps { // θi > 0, one preset, channel and angle
    std::string preset;
    int channel = 0;
    double thetaI = 0, ld = 0;
    pathtrace::BssrdfBins bins;
    std::vector<double> refR, refSe;                                 // per spatial bin
    std::vector<std::pair<std::string, std::vector<double>>> models; // name, R per bin
};
struct CompareReport {
    uint64_t paths = 0;
    std::vector<double> thetaI;
    std::vector<ScoreRow> rows;
    std::vector<ProfileCurves> profiles;
    std::vector<SliceMaps> slices;
};
// The radial profiles and the ratio to the reference of one preset and channel, written into
// `dir` as PNG (drawn headless by the pencil plot's code); each picture's file name and caption.
std::vector<std::pair<std::string, std::string>>
writeProfilePictures(const std::filesystem::path& dir, const ProfileCurves& p);
// report.md and report.html in `dir` (and the pictures in dir/plots when `pictures`).
void writeReports(const std::filesystem::path& dir, const CompareReport& r, bool pictures);

// Each model over every row (pipeline/scoring.h, summarizeModels) as a plain-text table: what
// `compare` prints.
std::string modelSummaryText(const std::vector<ScoreRow>& rows);
// rel_err → a report cell's colour from green (0) through yellow (10 %) to red (>= 30 %).
std::string scoreCellColour(double rel);
std::string htmlEscape(const std::string& s);

int runCompareCli(const std::filesystem::path& root, const CompareArgs& a);

// A run's results before ranking, with the unit (preset, channel, angle in enumeration order) of
// each row, profile and slice: what a shard writes and `merge` reads back (compare_shards.cpp).
struct CompareRun {
    CompareReport report;
    nlohmann::json skipped;
    std::vector<size_t> unitOfRow, unitOfProfile, unitOfSlice;
    size_t units = 0;
    std::vector<std::string> presets, models;
};
nlohmann::json scoreRowJson(const ScoreRow& r);
// Ranks, writes scores.json and the reports into `out`, and applies the baseline gate.
int finishCompare(const std::filesystem::path& out, CompareReport& report,
                  const nlohmann::json& skipped, bool plots, const std::vector<ScoreRow>& baseline,
                  std::optional<double> failIfWorse);
// --shard K/N: DIR/shard.json (schema bssrdf-workbench-scores-shard) with the unranked rows and
// the report's curves of this shard's units.
void writeCompareShard(const std::filesystem::path& out, const CompareRun& run, size_t k, size_t n);
// `merge DIR... --out D` of `compare --shard` folders: checks they are the N shards of one run
// and writes what one process writes (scores.json byte for byte, the reports).
int runMergeCompareCli(const std::vector<std::string>& dirs, const std::string& out, bool plots);

} // namespace app
