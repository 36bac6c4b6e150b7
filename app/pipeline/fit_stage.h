// The Fit stage (the GUI's Fit panel): a model's parameters fitted to the pencil plot's
// path-traced reference (pipeline/fitting.h: the same objective and search as `fit`) while the
// workbench runs. The search runs in a worker thread; each evaluation of the model is a GL
// dispatch, so the worker hands its parameter values to update() on the GL thread and waits for
// the objective: update() serves evaluations for at most kFrameBudgetMs per frame, so the UI
// never waits for the fit. The targets are the reference's channels as they were when the fit
// started (a copy). A hot reload of the model during a fit restarts it from its best point so
// far; a model that becomes unusable ends it with a problem. Apply sets the fitted values.
#pragma once

#include "core/fields.h"
#include "core/limits.h"
#include "pipeline/fitting.h"
#include "pipeline/reference_stage.h"
#include "pipeline/stage.h"

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace app {

// The fit a capture records (settings section "fit"): the Fit panel's last request. Recording
// and replay run it again from the recorded values on the recorded reference (the search is
// deterministic), so the fitted values replay exactly up to float evaluation.
struct FitRequestSettings {
    std::string model;  // display path; "" for none
    std::string params; // comma-separated NAME or NAME=LO,HI
    int maxEvaluations = FitSettings{}.maxEvaluations;
    double xtolRel = FitSettings{}.xtolRel;
};
template <class V> void fields(V& v, FitRequestSettings& s) {
    v("model", s.model, "model fitted (display path; empty: none)");
    v("params", s.params, "its free parameters, comma-separated NAME or NAME=LO,HI");
    v("max_evaluations", s.maxEvaluations, "evaluation budget", core::Limits{1, 1e6});
    v("xtol_rel", s.xtolRel, "relative parameter tolerance of convergence", core::Limits{1e-12, 1});
}
// "a,b=1,2,c" → {"a", "b=1,2", "c"}: a comma starts a new name unless a range is open.
std::vector<std::string> splitParams(const std::string& params);

struct FitInputs {
    bssrdf::ModelLibrary* library = nullptr;
    const ReferenceSnapshot* reference = nullptr;
    std::optional<material::MaterialParams> params; // the reference's medium
    double rMaxMm = 0; // the pencil plot's range and samples: the fitted profile is drawn there
    int samples = 0;
};

struct FitSnapshot {
    bool running = false;
    std::string model;
    std::vector<FitVariable> vars;
    std::vector<std::string> targets; // "R", "G", "B" fitted
    std::vector<double> trace;        // best mean rel_err² after each evaluation
    std::vector<double> bestX;        // the best point so far
    std::optional<FitResult> result;  // when the search has ended
    std::string problem;              // why it could not start or went on
    int restarts = 0;                 // after hot reloads
    bssrdf::Profile fitted;           // the model at the fitted values on the plot's radii
    bssrdf::ParamValues fittedValues; // the model's values with the fit applied
};

class FitStage : public StageOf<FitInputs> {
  public:
    static constexpr double kFrameBudgetMs = 12;
    // update() serves evaluations until this many ms have passed, and at least one; tests set 0
    // to have exactly one served a frame, so that frames counted show the fit never held one.
    double frameBudgetMs = kFrameBudgetMs;
    FitStage() = default;
    ~FitStage() override;
    FitStage(const FitStage&) = delete;
    FitStage& operator=(const FitStage&) = delete;
    const char* name() const override { return "fit"; }
    // Starts fitting `params` (NAME or NAME=LO,HI) of `model` to the reference's channels that
    // have an l_d the reference's bins resolve. Throws core::Error for a model that is not
    // usable, bad names or ranges (fitVariables), or a reference without paths.
    void start(const FitInputs& in, const std::string& model,
               const std::vector<std::string>& params, const FitSettings& s = {});
    bool update(const FitInputs& in) override; // serves evaluations; true when the state changed
    StageStatus status() const override;
    void cancel() override;
    FitSnapshot snapshot() const;
    // The fitted values set into the model's values; false without a result.
    bool apply(bssrdf::ModelLibrary& library);
    // Runs the fit to its end on this thread (tests, captures): update() until it has ended.
    void finish(const FitInputs& in);
    // Captures: with a request, the fit run again from the current values to its end and
    // `fit`, one row per variable (start, fitted) and one per target (rel_err before, after).
    // A request without the reference recorded is noted in out.missing.
    void capture(const FitInputs& in, const FitRequestSettings& request, CaptureEntries& out);

  private:
    void launch(const std::vector<double>& start);
    void stopWorker();

    mutable std::mutex m_mutex;
    std::condition_variable m_cv;
    std::thread m_worker;
    std::atomic<bool> m_cancel{false};
    bool m_workerDone = true;
    // the rendezvous: the worker's pending point, and the GL thread's answer
    std::optional<std::vector<double>> m_request;
    std::optional<std::pair<double, std::string>> m_answer;

    FitSnapshot m_snap;
    std::vector<FitTarget> m_targets;
    FitSettings m_settings;
    std::vector<double> m_start;
    uint64_t m_generation = 0;
    std::optional<SearchResult> m_searched; // set by the worker when it ends
};

} // namespace app
