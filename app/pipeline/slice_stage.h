// The BSSRDF slice stage: the whole BSSRDF at oblique incidence, path traced and modelled on
// the same bins. The reference is the estimate of pathtrace/bssrdf_estimate.h (seed 001, the
// connections estimator by default) for one colour channel of the source model's medium, run
// progressively in a background thread chunk by chunk, so the UI never waits and the table at
// any moment is exactly the table of the paths done so far (bitwise the CLI `estimate` of that
// many paths); or, where the GL tracer measured faster (device auto, tracer_device.h) or the
// user chose gpu, on the GL walk a slice per frame (slice_gpu.h). Every usable model is evaluated
// on the same bins on the GPU with its own parameters and σ (slice_model.h), whenever its key
// changes. Problems (bad settings, a failed energy check, a model that cannot be evaluated) go to
// the Errors panel; the last good table stays on screen.
#pragma once

#include "core/limits.h"
#include "pipeline/stage.h"

#include "bssrdf/program_library.h"
#include "material/material.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pipeline/model_stages.h"
#include "pipeline/slice_gpu.h"
#include "pipeline/slice_model.h"
#include "pipeline/slice_settings.h"
#include "pipeline/tracer_device.h"

#include <atomic>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace app {

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
    // walkShader: the GL walk (shaders/bssrdf_walk.comp); slabShader: the GL slab tracer whose
    // measured throughput decides `auto` (tracer_device.h)
    SliceStage(std::filesystem::path walkShader, std::filesystem::path slabShader)
        : m_gpu(std::move(walkShader)), m_slabShader(std::move(slabShader)) {}
    const char* name() const override { return "slice"; }
    // Restarts the estimate when the medium or the settings changed, and evaluates the
    // models whose key changed (on the calling GL thread). True when anything changed.
    bool update(const SliceInputs& in) override;
    StageStatus status() const override;
    void cancel() override {
        m_runner.cancel();
        m_gpu.cancel();
    }
    void restart() { m_key.clear(); }
    // Runs to the target and evaluates the models (captures, CLI, tests).
    SliceSnapshot finish(const SliceInputs& in);
    // Captures (when enabled): runs to the target, then `slice`, the path-traced table with its
    // standard errors (z-tested on replay; the last row, bin -1, holds the total diffuse
    // reflectance), and slice_model.<model>, every model on its bins (float32 GPU evaluations
    // summed in double). core::Error with the run's problem.
    void capture(const SliceInputs& in, CaptureEntries& out);
    SliceSnapshot snapshot() const { return m_gpuMode ? m_gpu.snapshot() : m_runner.snapshot(); }
    // Hot reload of the GL walk when one of `changed` is a file its program was built from.
    bool reloadShaders(const std::vector<std::filesystem::path>& changed) override {
        return m_gpu.reloadShaders(changed);
    }
    shader::Records shaderRecords() const override; // "slice:PROGRAM"
    const std::map<std::string, ModelSliceResult>& models() const { return m_models; }
    const std::string& model() const { return m_model; }
    // With device auto: what the measurement found (tracer_device.h), else "".
    std::string deviceChoice() const { return m_choice; }

  private:
    // Evaluates the models whose key changed; true when any result was recomputed or removed.
    bool evaluateModels(const SliceInputs& in);

    SliceRunner m_runner;
    GpuSliceRunner m_gpu;
    std::filesystem::path m_slabShader;
    bool m_gpuMode = false;
    std::string m_choice;
    std::string m_key, m_model, m_problem;
    uint64_t m_seen = 0;
    std::map<std::string, ModelSliceResult> m_models; // by display path
};

} // namespace app
