// A capture's recorded state opened in the window (`gui --capture NAME`, the Captures panel's
// "Open in a window"): the workbench a replay would build from the manifest's inputs (the
// project's models from disk, hot-reloaded; models recorded from outside the project from
// their recorded text; every parameter and setting; the traced pixel), to look at, change and
// debug interactively what a replay (or CI) only compares. What differs from the recording (a
// model edited since, a model gone) is an Errors entry, and the model's recorded text is opened
// beside today's as NAME.recorded with the recorded parameters: the state as recorded and the
// model as it is now, on one plot (a capture of the pencil plot alone with one model edited
// shows every curve as its ratio to the recorded model's: what the edit changed).
#pragma once

#include "captures/capture_io.h"
#include "pipeline/workbench.h"

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace app {

// The capture folder `nameOrFolder` names: a folder holding a manifest.json, else
// <root>/captures/NAME. Throws core::Error naming it (and the captures there) when it is neither.
std::filesystem::path findCapture(const std::filesystem::path& root,
                                  const std::string& nameOrFolder);

struct OpenedCapture {
    std::string name; // the manifest's
    std::filesystem::path folder;
    std::unique_ptr<Workbench> wb;
    int traceX = -1, traceY = -1; // the recorded traced pixel of the render, if any
    // the models recorded from outside the project, and the recorded texts of the project's
    // models edited or gone since (NAME.recorded.bssrdf): kept while the workbench runs
    std::unique_ptr<ExternalModels> files;
};

// What a capture holds, a line each, for the Captures panel: when, by which program version and
// on which GL driver it was recorded; each model and whether the project's file is as recorded,
// edited since (or in comments only), gone, or from outside the project; the preset; the
// traced pixel; the stages by kind. Throws core::Error naming the manifest when it cannot be
// read.
std::vector<std::string> describeCapture(const std::filesystem::path& root,
                                         const std::filesystem::path& folder);

// The workbench with the capture's inputs (as replay builds it; `watch`: hot reload). Throws
// core::Error naming the manifest for a capture that cannot be read or applied.
OpenedCapture openCapture(const std::filesystem::path& root, const std::filesystem::path& folder,
                          bool watch);

} // namespace app
