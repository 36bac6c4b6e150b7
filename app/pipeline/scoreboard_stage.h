// The Scoreboard stage: the table of `compare` (compare.h, the same scoreAgainstReference and
// rankRows) for the current parameters, live in the GUI. The reference is the pencil plot's
// path-traced reference (reference_stage.h: the source model's medium per colour channel, on
// the plot's radial bins), and every usable model is scored against it with its own σ, per
// channel over [0.1, 4] l_d of that channel (over what the plot's range covers of it when the
// range is shorter: the row says so). Re-scored when a model changes (hot reload, parameters)
// or the reference gains paths, at most every kRescoreSeconds while the reference runs. The
// pencil plot's legend shows the same rows (pencil_series.h). Each model is evaluated once per
// re-scoring, averaged over the reference's bins for all three channels. When an MCML run is open
// as a reference, every model is also scored against it (its medium, one channel: the rows of
// `compare --mco`).
#pragma once

#include "bssrdf/program_library.h"
#include "capture/scores.h"
#include "pipeline/model_stages.h"
#include "pipeline/reference_stage.h"
#include "pipeline/stage.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace app {

struct ScoreboardInputs {
    bool enabled = false; // while the Scoreboard panel shows or the reference runs (the legend)
    bssrdf::ModelLibrary* library = nullptr;
    const std::map<std::string, ModelView>* views = nullptr;
    const ReferenceSnapshot* reference = nullptr;
    std::string referenceModel; // display path of the model whose σ the reference uses
    std::optional<material::MaterialParams> params; // that σ (the reference's media)
    // An MCML run opened as a reference (File → Open MCML reference): every model is also scored
    // against its R_d(r) with the medium the file declares, as `compare --mco` does.
    const pathtrace::SlabResult* mcml = nullptr;
    std::optional<pathtrace::Medium> mcmlMedium;
    std::string mcmlName;
};

struct ScoreboardRow {
    capture::ScoreRow score;
    std::string displayPath; // the model's file, to open it in the pencil plot
    int channel = 0;
    double coveredLd = 4; // the reference's range in l_d when < 4 (scored up to there)
};

class ScoreboardStage : public StageOf<ScoreboardInputs> {
  public:
    static constexpr double kRescoreSeconds = 0.5;
    const char* name() const override { return "scoreboard"; }
    bool update(const ScoreboardInputs& in) override;
    StageStatus status() const override;
    const std::vector<ScoreboardRow>& rows() const { return m_rows; }
    uint64_t referencePaths() const { return m_paths; } // per channel, of the scored reference
    const std::vector<std::string>& notes() const { return m_notes; } // channels not scored
    // The rows against the MCML run (empty when none is open), ranked; and its name.
    const std::vector<ScoreboardRow>& mcmlRows() const { return m_mcmlRows; }
    const std::string& mcmlName() const { return m_mcmlName; }

  private:
    bool updateMcml(const ScoreboardInputs& in);
    bool updateReference(const ScoreboardInputs& in);
    std::string m_key, m_mcmlKey, m_mcmlName;
    std::vector<ScoreboardRow> m_mcmlRows;
    std::vector<std::string> m_mcmlProblems;
    double m_lastScored = -1e9;
    std::vector<ScoreboardRow> m_rows;
    std::vector<std::string> m_notes, m_problems;
    uint64_t m_paths = 0;
    // 2π∫R r dr per (model state, channel): it does not change with the reference, so the
    // re-scoring while paths arrive does not evaluate 2048 radii per model again
    std::map<std::string, double> m_totals;
};

} // namespace app
