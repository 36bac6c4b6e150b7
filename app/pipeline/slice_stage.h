// The BSSRDF slice stage: the whole BSSRDF at oblique incidence, path traced and modelled on
// the same bins. The reference is the estimate of pathtrace/bssrdf_estimate.h (seed 001, the
// connections estimator by default) for one colour channel of the source model's medium, run
// progressively in a background thread chunk by chunk, so the UI never waits and the table at
// any moment is exactly the table of the paths done so far (bitwise the CLI `estimate` of that
// many paths). Every usable model is evaluated on the same bins on the GPU with its own
// parameters and σ (slice_model.h), whenever its key changes. Problems (bad settings, a failed
// energy check, a model that cannot be evaluated) go to the Errors panel; the last good table
// stays on screen.
#pragma once

#include "core/limits.h"
#include "pipeline/stage.h"

#include "bssrdf/program_library.h"
#include "material/material.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pipeline/model_stages.h"
#include "pipeline/slice_model.h"

#include <atomic>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace app {

struct SliceSettings {
    bool enabled = false; // the GUI sets it while the slice panel shows
    int channel = 0;      // the medium of colour channel 0 R, 1 G, 2 B
    double thetaIDeg = 45.0;
    double rangeLd = 3.0; // r_max = range_ld · l_d of the channel
    int rBins = 16;
    bool logR = false;
    int thetaSBins = 12;
    int dirCosBins = 2, dirPhiBins = 6;
    uint64_t paths = 200000;
    uint64_t seed = 1;
    pathtrace::BssrdfEstimator estimator = pathtrace::BssrdfEstimator::Connections;
    pathtrace::ScatterOrders orders = pathtrace::ScatterOrders::All;
};
template <class V> void fields(V& v, SliceSettings& s) {
    v("enabled", s.enabled, "path-trace the BSSRDF slice");
    v("channel", s.channel, "medium of colour channel 0 R, 1 G, 2 B", core::Limits{0, 2});
    v("theta_i_deg", s.thetaIDeg, "incidence angle, degrees [0, 90)", core::Limits{0, 90});
    v("range_ld", s.rangeLd, "radius of the last bin edge in l_d of the channel",
      core::Limits{0.01, 1000});
    v("r_bins", s.rBins, "radial bins", core::Limits{1, 1e4});
    v("log_r", s.logR, "logarithmic radial bins");
    v("theta_s_bins", s.thetaSBins, "bins of theta_s over [0, 180] deg", core::Limits{1, 1e4});
    v("dir_cos_bins", s.dirCosBins, "exit-direction rings (equal solid angle)",
      core::Limits{1, 1e3});
    v("dir_phi_bins", s.dirPhiBins, "exit-direction azimuth sectors", core::Limits{1, 1e3});
    v("paths", s.paths, "photon paths", core::Limits{1, 1e18});
    v("seed", s.seed, "random seed");
    v("estimator", s.estimator, "estimator");
    v("orders", s.orders, "scattering orders tallied");
}

// The estimate settings and medium of a slice (validated by the runner, not here). r_max is
// range_ld · l_d; where l_d is infinite (σa = 0) it is range_ld · 10 transport mean free paths.
pathtrace::EstimateSettings estimateSettings(const SliceSettings& s, const pathtrace::Medium& m);

struct SliceSnapshot {
    bool running = false;
    uint64_t pathsDone = 0, pathsTarget = 0;
    double pathsPerSecond = 0;
    pathtrace::Medium medium;
    pathtrace::EstimateSettings settings;        // of the table below (paths = pathsDone)
    std::optional<pathtrace::BssrdfSlice> slice; // none until the first chunks are done
    std::string problem;                         // bad settings: nothing new runs
    std::string energy;                          // the table's own energy check failed
};

// The background estimate (one medium, one incidence angle).
class SliceRunner {
  public:
    SliceRunner() = default;
    ~SliceRunner();
    SliceRunner(const SliceRunner&) = delete;
    SliceRunner& operator=(const SliceRunner&) = delete;
    // Restarts for this medium and these settings (thetaIDeg must hold one angle). A bad
    // input becomes snapshot().problem; the last table stays.
    void start(const pathtrace::Medium& m, const pathtrace::EstimateSettings& s);
    void cancel(); // stops after the chunk in progress; the table keeps the chunks done
    void wait();
    SliceSnapshot snapshot() const;
    uint64_t version() const { return m_version.load(); }

  private:
    void run(pathtrace::Medium m, pathtrace::EstimateSettings s);

    std::thread m_thread;
    std::atomic<bool> m_cancel{false};
    std::atomic<uint64_t> m_version{0};
    mutable std::mutex m_mutex;
    SliceSnapshot m_snapshot;
    std::string m_runKey;               // the run whose chunks are done: (medium, settings)
    pathtrace::BssrdfTally m_doneTally; // its sums over chunks [0, m_doneChunk)
    uint64_t m_doneChunk = 0;
};

// One model on the slice's bins.
struct ModelSliceResult {
    std::string key; // what it was computed for
    std::optional<ModelSlice> slice;
    pathtrace::Medium medium; // the model's own σ in the slice's channel
    std::string problem;
};

struct SliceInputs {
    bssrdf::ModelLibrary* library = nullptr;
    const std::map<std::string, ModelView>* views = nullptr;
    std::optional<material::MaterialParams> params; // source model's σ; none: nothing runs
    std::string model;                              // its display path
    SliceSettings settings;
};

class SliceStage : public StageOf<SliceInputs> {
  public:
    const char* name() const override { return "slice"; }
    // Restarts the estimate when the medium or the settings changed, and evaluates the
    // models whose key changed (on the calling GL thread). True when anything changed.
    bool update(const SliceInputs& in) override;
    StageStatus status() const override;
    void cancel() override { m_runner.cancel(); }
    void restart() { m_key.clear(); }
    // Runs to the target and evaluates the models (captures, CLI, tests).
    SliceSnapshot finish(const SliceInputs& in);
    // Captures (when enabled): runs to the target, then `slice`, the path-traced table with its
    // standard errors (z-tested on replay; the last row, bin -1, holds the total diffuse
    // reflectance), and slice_model.<model>, every model on its bins (float32 GPU evaluations
    // summed in double). core::Error with the run's problem.
    void capture(const SliceInputs& in, CaptureEntries& out);
    SliceSnapshot snapshot() const { return m_runner.snapshot(); }
    const std::map<std::string, ModelSliceResult>& models() const { return m_models; }
    const std::string& model() const { return m_model; }

  private:
    // Evaluates the models whose key changed; true when any result was recomputed or removed.
    bool evaluateModels(const SliceInputs& in);

    SliceRunner m_runner;
    std::string m_key, m_model, m_problem;
    uint64_t m_seen = 0;
    std::map<std::string, ModelSliceResult> m_models; // by display path
};

} // namespace app
