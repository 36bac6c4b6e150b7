// The workbench's state kept from one run of the window to the next, and across the program's
// restart after a GPU driver reset: a capture's inputs (every model with its text, the
// parameters, the settings: captureInputs) as request.json, and session.json with the project's
// root and where each model from outside the project was opened, so that it is opened there
// again (its edits hot-reloaded) rather than from a copy of its text.
#pragma once

#include "pipeline/workbench.h"

#include <filesystem>
#include <memory>

namespace app {

// Where the window keeps the session of the project at `root`, under the user's configuration
// folder `configDir`: configDir/sessions/<the root's hash>.
std::filesystem::path sessionDir(const std::filesystem::path& configDir,
                                 const std::filesystem::path& root);

// Writes wb's state into `dir`, replacing what was there only once all of it is written. Throws
// core::Error (a folder that cannot be written; two models from outside the project with the
// same file name, which a capture's inputs cannot tell apart).
void saveSession(Workbench& wb, const std::filesystem::path& dir);

// The workbench as the session in `dir` left it: every model of the project, as a fresh start
// finds them; the models from elsewhere opened again where they were; the parameters and
// settings applied. A model from elsewhere that is gone, or a session that cannot be read (its
// parameters and settings then the defaults), is an Errors entry naming the file. nullptr when
// `dir` holds no session, or one of another project.
std::unique_ptr<Workbench> restoreSession(const std::filesystem::path& dir,
                                          const std::filesystem::path& root, bool watch);

} // namespace app
