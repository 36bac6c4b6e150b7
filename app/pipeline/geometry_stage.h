// The geometry stage (the Scoreboard's geometry tab): the scores of `compare --geometry`
// (geometry_scoring.h: the same cases, images, rel_l2 and ranks) for one preset and channel and
// the shapes ticked, live in the GUI. The path-traced references run in a worker thread (the
// CPU mesh tracer, cancellable, progress per path; the disk cache is shared with the CLI); each
// model's image is integrated on the GL thread in update(), a few samples per pixel per frame
// within kFrameBudgetMs, so the UI keeps drawing. A model that changes (hot reload, parameter
// edits: ModelEntry::generation and values) has its images made again against the references
// already there; a model that cannot be integrated on a shape says so in its cell and in the
// Errors panel. Changing the preset, channel, shapes or settings starts over.
#pragma once

#include "bssrdf/program_library.h"
#include "material/material.h"
#include "pipeline/geometry_scoring.h"
#include "pipeline/stage.h"

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace app {

// The geometry tab's request; its defaults are the CLI's (GeometrySettings), on a handful of the
// suite's shapes so that a run takes about a minute on 2 CPU cores.
struct GeometryTabSettings {
    bool enabled = false; // Run pressed (Cancel or a finished run leaves the results)
    std::string preset = "Marble";
    int channel = 1;
    std::vector<std::string> shapes = {"slab:t=0.3,w=20,view=front",
                                       "slab:t=0.3,w=20,view=back",
                                       "edge:s=8",
                                       "corner:s=8",
                                       "fin:t=0.5,h=5",
                                       "sphere:r=1",
                                       "tessellation:level=1"};
    GeometrySettings settings;
};

struct GeometryInputs {
    const GeometryTabSettings* request = nullptr;
    bssrdf::ModelLibrary* library = nullptr;
    const std::vector<material::Preset>* presets = nullptr;
};

// One cell of the tab's table: a model on a shape.
struct GeometryCell {
    std::string model, displayPath, shape;
    std::optional<ChannelImage> image; // the model's image, when made
    ImageScore score;                  // valid when image and score.problem is empty
    int rank = 0;
    bool tie = false;
    std::string key; // the model state the image was made with
};

class GeometryStage : public StageOf<GeometryInputs> {
  public:
    static constexpr double kFrameBudgetMs = 40;
    // update() integrates until this many ms have passed, and at least one step; tests set 0 to
    // have exactly one step a frame, so that frames counted show the run never held one.
    double frameBudgetMs = kFrameBudgetMs;
    GeometryStage();
    ~GeometryStage() override;
    const char* name() const override { return "geometry"; }
    bool update(const GeometryInputs& in) override;
    StageStatus status() const override;
    void cancel() override;

    const std::vector<std::string>& shapes() const { return m_shapes; }
    const std::vector<std::string>& models() const { return m_models; } // display paths
    // The cell of (model display path, shape), or nullptr.
    const GeometryCell* cell(const std::string& displayPath, const std::string& shape) const;
    // The reference of a shape (nullptr while it runs).
    const ChannelImage* reference(const std::string& shape) const;
    double ldMm() const { return m_ldMm; }

  private:
    void restart(const GeometryInputs& in, const std::string& key);
    void stopWorker();
    void rank();

    std::string m_key;
    std::vector<GeometryCase> m_cases; // one per shape
    std::vector<std::string> m_shapes, m_models;
    std::vector<GeometryCell> m_cells; // shape-major: m_cells[k·models + m]
    double m_ldMm = 0;
    GeometrySettings m_settings;
    std::vector<std::string> m_problems;
    // references: written by the worker under m_mutex
    mutable std::mutex m_mutex;
    std::vector<std::optional<ChannelImage>> m_refs;
    std::atomic<uint64_t> m_refDone{0}, m_refTotal{1};
    std::atomic<bool> m_cancel{false}, m_workerDone{true};
    std::thread m_worker;
    std::string m_workerProblem;
    // the model image being integrated over frames
    struct Work;
    std::unique_ptr<Work> m_work;
};

} // namespace app
