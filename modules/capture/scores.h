// The scoreboard's file, scores.json (written by `bssrdf-workbench compare`, app/compare.h):
// one row per model × preset × channel × θi with its error figures against the path-traced
// reference, under {"schema": "bssrdf-workbench-scores", "version": 2}. Version 2 scores by
// rel_err (core/relative_error.h); version 1 scored by rel_l2, a different measure, so its files
// are refused rather than compared. Read back as the
// baseline of a later run (--baseline), so it is an input and is fuzzed (tests/fuzz).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace capture {

inline constexpr const char* kScoresSchema = "bssrdf-workbench-scores";
inline constexpr int kScoresVersion = 2;

struct ScoreRow {
    std::string model, preset, channel;
    double thetaI = 0, ldMm = 0;
    double relErr = 0, relErrSe = 0; // rel_err, rel_err_se
    double relErrSquared = 0;        // rel_err² before its clamp at 0 (what `fit` minimises;
                                     // not written to scores.json)
    double ratio1 = 0, ratio1Se = 0, ratio4 = 0, ratio4Se = 0;
    double totalRatio = 0, totalRatioSe = 0;
    std::optional<double> rErr5Ld;
    // θi > 0 only: rel_err over the plane and the exit directions (app/pipeline/scoring_oblique.h)
    std::optional<double> relErrDir, relErrDirSe;
    int rank = 1;
    bool tie = false;
};

// The rows of a scores.json (model, preset, channel, theta_i, rel_err, rel_err_se: what a
// baseline comparison needs). Throws core::Error(file, 0, ...) naming the JSON path for a file
// that is not JSON, of another schema or version, or with a field of the wrong type or a
// number that is not finite and >= 0 where it must be.
std::vector<ScoreRow> readScores(const std::string& file);

} // namespace capture
