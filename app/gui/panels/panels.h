// One function per panel: each only shows and edits its stage's settings and its own state
// (ui_state.h); no algorithms. The registry (registry.h) lists them for the menu and the frame.
// A panel draws its contents only: the workspace (workspace.cpp) gives it a tab in its area
// or a floating window.
#pragma once

#include "gui/ui_state.h"
#include "pipeline/workbench.h"

namespace app {

void drawMenuBar(Workbench& wb, UiState& ui);
// View → a panel: closes it if open, else opens it and brings it to the front (its tab shown).
void togglePanel(UiShared& ui, PanelId id);
// Opens a model file (relative: to the current folder, else to the root) and remembers it
// among the recent files; a failure is an Errors entry.
void openModelFile(Workbench& wb, UiShared& ui, const std::filesystem::path& file);
// Opens an MCML output as the pencil plot's MCML reference; a file that cannot be one is an
// Errors entry (and the previous reference stays).
void openMcmlFile(Workbench& wb, UiShared& ui, const std::filesystem::path& file);
// Every open panel: docked as tabs in the workspace's areas, or floating (workspace_layout.h).
void drawWorkspace(Workbench& wb, UiState& ui);
// The panels drawn this frame: the shown tab of each area (a pending UiShared::show request
// first) and every floating panel.
std::array<bool, kPanelCount> shownPanels(const UiShared& ui);
void drawModelsPanel(Workbench& wb, UiShared& ui);
void drawParametersPanel(Workbench& wb, ParametersPanelState& ps, UiShared& ui);
// The Parameters panel's "From albedo and length" section (artist_mapping.cpp) for `s`.
void drawArtistMapping(Workbench& wb, MaterialSettings& s, ArtistMappingState& st);
void drawPencilPanel(Workbench& wb, PencilPanelState& ps, UiShared& ui);
void drawErrorsPanel(Workbench& wb, ErrorsPanelState& ps, UiShared& ui);
void drawLogPanel(Workbench& wb, ErrorsPanelState& ps, UiShared& ui);
void drawTimingsPanel(Workbench& wb, UiShared& ui);
void drawLitSpherePanel(Workbench& wb, LitSpherePanelState& ps, UiShared& ui);
void drawPointCloudPanel(Workbench& wb, PointCloudPanelState& ps, UiShared& ui);
void drawOctreePanel(Workbench& wb, OctreePanelState& ps, UiShared& ui);
void drawIrradiancePanel(Workbench& wb, IrradiancePanelState& ps, UiShared& ui);
void drawRenderPanel(Workbench& wb, RenderPanelState& ps, UiShared& ui);
// The Render panel's texture-space controls and status (texspace_view.cpp). Sets `tex` to the
// texture-space image of the frame's size when it shows the render and returns false; draws a
// stage's image (E′, a CDF level, the samples, the atlas) itself and returns true.
bool drawTextureSpaceView(Workbench& wb, RenderPanelState& ps, const render::Frame& f, GLuint& tex);
// The last sample set's texels as dots over the render image drawn at ps.imageRect.
void drawSamplesOnMesh(Workbench& wb, RenderPanelState& ps, const render::Settings& r,
                       float pixelScale);
// The shown frame's read-back (the pixel probe, the export, the misses of another renderer's
// image), read again only when a new frame is shown; nullptr while a frame is in progress.
const render::Readback* shownReadback(SceneStage& scene, RenderPanelState& ps);
// Shows another renderer's estimate of the frame (Monte Carlo, texture space) in `tex`: tone
// mapped as the frame, its misses in the frame's background colour (paintMisses), and kept as
// ps.shown for the pixel probe and the export. Returns the texture to draw.
GLuint showEstimate(SceneStage& scene, RenderPanelState& ps, const std::string& what,
                    const pathtrace::Image& img, gl::Texture& tex);
// Writes the Render panel's shown image: .exr (HDR L_o, linear, with the variance of the mean
// where it is an estimate) or .png (tone-mapped, as shown): the frame, or the Monte Carlo or
// texture-space render or the heatmap shown over it (a heatmap only as .png). Throws
// core::Error naming the path (no finished frame, other extension, I/O).
void exportRenderView(Workbench& wb, RenderPanelState& ps, const std::filesystem::path& path);
void drawCapturesPanel(Workbench& wb, CapturesPanelState& ps, UiShared& ui);
void drawFitPanel(Workbench& wb, FitPanelState& ps, UiShared& ui);
// Starts replaying captures/NAME in a child process (core::Error when it cannot start).
void startReplay(Workbench& wb, CapturesPanelState& ps, const std::string& name);
// File → Record capture: the current state recorded by a child process (CapturesPanelState).
// startRecording throws core::Error when the state cannot be written or a recording runs;
// pollRecording, called every frame, ends one: status line, log, or an Errors entry.
void startRecording(Workbench& wb, CapturesPanelState& ps, const std::string& name);
void pollRecording(Workbench& wb, CapturesPanelState& ps, UiShared& ui);
// "Open in a window": captures/NAME's state in a window of its own, a child process
// (`gui --capture NAME`; core::Error when it cannot start). pollCaptureWindows, called every
// frame, reads their output and makes the error of one that fails (no display, a capture that
// cannot be applied) an Errors entry.
void startCaptureWindow(Workbench& wb, CapturesPanelState& ps, const std::string& name);
void pollCaptureWindows(Workbench& wb, CapturesPanelState& ps);
// A window opened on a capture (`gui --capture`, `screenshot --capture`) shows what it recorded:
// the render with its traced pixel traced again in the Traversal debugger (a capture of the
// mesh pipeline), else the lit spheres (side by side), the BSSRDF slice or the pencil plot; the
// status line names the capture.
void showCapturedState(Workbench& wb, UiState& ui, const std::string& name, int traceX, int traceY);
// The stage a record or replay child reported last ("what: stage NAME" lines), "" before any.
std::string lastStage(const std::string& output, const std::string& what);
void drawSlicePanel(Workbench& wb, SlicePanelState& ps, UiShared& ui);
void drawScoreboardPanel(Workbench& wb, ScoreboardPanelState& ps, UiShared& ui);
// The Scoreboard's geometry tab (scoreboard_geometry.cpp).
void drawGeometryScores(Workbench& wb, ScoreboardPanelState& ps);
void drawTraversalPanel(Workbench& wb, TraversalPanelState& ps, UiShared& ui);

} // namespace app
