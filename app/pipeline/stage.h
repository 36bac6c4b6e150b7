// The one interface of every pipeline stage of the workbench (docs/ARCHITECTURE.md, "Modules
// and stages"): a stage has explicit inputs (its own Inputs struct, gathered by the Workbench
// from the outputs of the stages before it), update(inputs) → whether its output changed (it
// re-runs only what the inputs' change requires), progress, cancel, problems and stats; it
// rebuilds its own GL programs on hot reload and lists them (reloadShaders, shaderRecords), and
// a stage with outputs to record gives its capture entries (capture(inputs, entries), wired by
// the Workbench's PipelineStep). The Workbench is an ordered list of stages (workbench.cpp);
// the Errors panel lists every stage's problems under its name. How to add one:
// docs/ARCHITECTURE.md, "How to add a stage".
#pragma once

#include "pipeline/capture_entries.h"
#include "shader/program.h"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace app {

struct StageStatus {
    bool running = false;              // work in progress (a background thread or slices per frame)
    double progress = 1.0;             // of the current run, 0..1
    std::vector<std::string> problems; // shown in Errors, last good kept
    std::vector<std::pair<std::string, std::string>> stats; // name, value (for panels)
};

class Stage {
  public:
    virtual ~Stage() = default;
    virtual const char* name() const = 0; // the Errors panel's source, e.g. "reference"
    virtual StageStatus status() const = 0;
    virtual void cancel() {}
    // Hot reload: rebuilds exactly this stage's GL programs whose recorded shader files include
    // one of `changed` (a failure keeps the old program and is one of its problems). Returns true
    // when a program was rebuilt. Stages without programs keep the default.
    virtual bool reloadShaders(const std::vector<std::filesystem::path>& changed) {
        (void)changed;
        return false;
    }
    // This stage's GL programs, each by "owner:program" (the owner: the stage or its sub-stage,
    // e.g. "reference:…", "render:…"), with the files it was built from and its build count.
    virtual shader::Records shaderRecords() const { return {}; }
};

// A stage with its inputs' type: update(inputs) returns true when an output changed.
template <class In> class StageOf : public Stage {
  public:
    using Inputs = In;
    virtual bool update(const In& in) = 0;
};

} // namespace app
