// The BSSRDF slice's estimate on the GL compute walk (pathtrace/gpu_bssrdf.h,
// shaders/bssrdf_walk.comp): the same walk, estimators and bins as the CPU runner of
// slice_stage.h, stepped by the frame loop on the GL thread for a time budget per frame, so the
// UI keeps its frame rate while paths accumulate. The snapshot after each step is the table of
// the paths done so far (no radial splitting on the GL walk; its settings say levels 0). A
// shader edit that fails to compile keeps the previous program running and names file:line.
#pragma once

#include "pathtrace/gpu_bssrdf.h"
#include "pipeline/slice_settings.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace app {

class GpuSliceRunner {
  public:
    explicit GpuSliceRunner(std::filesystem::path walkShader)
        : m_shaderFile(std::move(walkShader)) {}
    // Restarts for this medium and these settings (one angle). A bad input becomes
    // snapshot().problem; the last table stays.
    void start(const pathtrace::Medium& m, const pathtrace::EstimateSettings& s);
    // Traces for about `budgetMs`; true when new paths arrived.
    bool step(double budgetMs);
    void cancel(); // the table keeps the paths done
    bool running() const;
    SliceSnapshot snapshot() const { return m_snap; }
    // Hot reload: recompiles when one of `changed` is a file the walk was built from; a
    // successful build starts the run over.
    bool reloadShaders(const std::vector<std::filesystem::path>& changed);
    shader::Records shaderRecords() const;

  private:
    void publish();

    std::filesystem::path m_shaderFile;
    std::unique_ptr<pathtrace::GpuBssrdfEstimator> m_gpu;
    pathtrace::Medium m_medium;
    pathtrace::EstimateSettings m_settings;
    uint64_t m_target = 0;
    uint64_t m_perStep = 1024; // paths per step(), adapted to the budget
    double m_seconds = 0;
    std::string m_problem;       // the run cannot go on (bad input, tally error)
    std::string m_shaderProblem; // the last edit failed to compile: the old program runs
    SliceSnapshot m_snap;
};

} // namespace app
