// Record and replay captures of the workbench state (format v1: modules/capture, README in
// captures/): record.cpp writes the manifest and every stage's outputs, replay.cpp makes them
// again and compares. What each stage records is its own (its capture(), listed in
// pipeline/capture_entries.h's users): per model the effective material and the pencil-beam
// profile; the path-traced reference and slice; the lit-sphere images; the mesh pipeline's
// stages and the texture-space stages.
#pragma once

#include "pipeline/workbench.h"

#include "capture/capture.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace app {

// Writes one stage output into the capture folder `dir` as its kind says and describes it for
// the manifest (file, kind, tolerance, content hash).
capture::StageOutput writeCaptureEntry(const std::filesystem::path& dir, const CaptureEntry& e);

// Writes <dir>/manifest.json + stage outputs for the current state, into a temporary folder
// beside <dir> renamed over it when complete (an existing <dir> is replaced whole; a failure
// leaves nothing). Throws core::Error.
// With the scene on (wb.scene().settings().enabled), its stages are recorded too
// (pipeline/scene_capture.cpp), with the traversal of pixel (traceX, traceY) when both are >= 0.
// onStage, when given, is told each stage's name as its outputs are made (progress lines).
void recordCaptureTo(Workbench& wb, const std::filesystem::path& dir, const std::string& name,
                     int traceX = -1, int traceY = -1,
                     const std::function<void(const std::string&)>& onStage = {});

// The manifest of the current state without outputs: name, program and GL driver, every model
// with its text, params and settings. Throws core::Error for an invalid name or two models
// from outside the project with the same file name.
capture::Manifest captureInputs(Workbench& wb, const std::string& name, int traceX = -1,
                                int traceY = -1);

// Where writeRecordRequest(wb, name) writes: <root>/captures/.<name>.request/request.json.
std::filesystem::path recordRequestPath(const std::filesystem::path& root, const std::string& name);
// A recording done by another process (the GUI records in a child, so it never waits): the
// current state's inputs written as <root>/captures/.<name>.request/request.json (returned),
// and in the child the workbench made from them (as replay makes it) recorded into `dir`.
std::filesystem::path writeRecordRequest(Workbench& wb, const std::string& name, int traceX = -1,
                                         int traceY = -1);
void recordFromRequest(const std::filesystem::path& request, const std::filesystem::path& root,
                       const std::filesystem::path& dir, const std::string& name,
                       const std::function<void(const std::string&)>& onStage = {});

// A temporary folder for models recorded from outside the project, removed with this object.
struct ExternalModels {
    ExternalModels();
    ~ExternalModels();
    ExternalModels(const ExternalModels&) = delete;
    ExternalModels& operator=(const ExternalModels&) = delete;
    std::filesystem::path dir;
};
// A workbench with a manifest's recorded inputs: the project's models by path, the others from
// their recorded text written under `externalDir`; params and settings applied (errors name
// `where`), the point-cloud cache off (the scene is generated); the traced pixel, if any, in
// traceX/traceY. `watch`: hot reload (the GUI).
std::unique_ptr<Workbench> workbenchFromInputs(const capture::Manifest& m,
                                               const std::filesystem::path& root,
                                               const std::filesystem::path& externalDir,
                                               const std::string& where, int& traceX, int& traceY,
                                               bool watch = false);

// The input files the settings of a capture's workbench name (mesh, point cloud, environment,
// projected texture, lit-sphere mesh) resolve inside the capture folder or the project, never
// elsewhere ("../../etc/passwd", an absolute path outside, a symlink out): a capture may come
// from someone else. Throws core::Error naming `where` and the setting; checked before anything
// is read.
void checkCaptureInputFiles(Workbench& wb, const std::filesystem::path& captureDir,
                            const std::string& where);

// Records the current state as <root>/captures/<name> (File → Record capture); returns that
// folder relative to the root.
std::string recordCapture(Workbench& wb, const std::string& name);
// Replays a capture headless (needs a current GL context): recomputes every stage from the
// recorded inputs and compares with the recorded outputs. Prints one line per stage to
// `out`. Returns 0 when everything passes, 1 on any failure, 2 when the capture is unreadable.
// update: rewrite the outputs (and their hashes) from this run instead of comparing.
// onStage as for recordCaptureTo.
int replayCapture(const std::filesystem::path& captureDir, const std::filesystem::path& root,
                  bool update, std::string& out,
                  const std::function<void(const std::string&)>& onStage = {});

} // namespace app
