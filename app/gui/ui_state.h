// UI-only state, one struct per panel (each panel's draw function takes its own), plus the
// few things panels share: which panels are open, the status line, the scene inspector (its
// camera, the traced pixel and what the point splats show), pending export requests.
// Modes are enums. The panels themselves are listed once, in panels/registry.h.
#pragma once

#include "gl/gl.h"
#include "gui/file_dialog.h"
#include "gui/scene_view.h"
#include "gui/workspace_layout.h"
#include "pathtrace/lit_sphere.h"
#include "pipeline/params_lab.h"
#include "pipeline/scene_stage.h"
#include "probe/child_process.h"

#include <array>
#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace app {

// Every panel, in View-menu order (panels/registry.cpp holds their titles and draw functions).
enum class PanelId {
    Models,
    Parameters,
    Render,
    Pencil,
    LitSpheres,
    PointCloud,
    Octree,
    Irradiance,
    Traversal,
    Captures,
    Slice,
    Scoreboard,
    Fit,
    Errors,
    Log,
    Timings,
    Count
};
constexpr size_t kPanelCount = static_cast<size_t>(PanelId::Count);

// What the point splats of the scene inspector are coloured by.
enum class PointColor { Normal, Area, Irradiance, Radiance };
// What the Render panel shows: the image or a heatmap of the traversal.
enum class Heatmap { Image, Steps, StackDepth, RelativeError };
// Which lit sphere(s) the Lit spheres panel shows.
enum class SphereView { PathTraced, Integrated, SideBySide, Difference };

// Shared by the scene panels (point cloud, octree, render, traversal debugger).
struct SceneInspect {
    render::Camera camera; // the 3D inspector views' camera (not the render camera)
    bool cameraSet = false;
    PointColor colorBy = PointColor::Normal;
    std::optional<PixelDebug> debug; // the traced pixel
    std::string debugProblem;
    // A click on the Render image waiting for a finished full-resolution frame (the click
    // itself may start a half-resolution one): where, as a fraction of the image.
    std::optional<std::pair<float, float>> pendingPick;
    bool highlightTrace = true; // draw the traced pixel's visited nodes in 3D
    // The traced pixel follows the render: once a new full-resolution frame is done (ε, the
    // model, a parameter, a shader, the camera changed) the same pixel is traced again, and the
    // trace it replaced is kept as `previous` to show what changed; `pinned`, when set, is the
    // baseline shown instead (the Traversal debugger's Pin).
    bool follow = true;
    long long tracedFrame = -1; // the render's frame count (scene.render runs) traced on
    std::optional<PixelDebug> previous, pinned;
};

// Where the panels are: the splitters, which panels float (and where), the tab shown in each
// area (saved with the layout; View → Reset layout restores the defaults).
struct WorkspaceState {
    WorkspaceSplits splits;
    std::array<bool, kPanelCount> floating{};
    std::array<Rect, kPanelCount> floatRect{}; // zero width: not placed yet
    std::array<int, kAreaCount> selected;      // PanelId shown in each area, -1: the first
    std::array<bool, kPanelCount> placed{};    // its floating window has been positioned
    WorkspaceState() { selected.fill(-1); }
};

// What every panel may read and write besides its own state.
struct UiShared {
    std::array<bool, kPanelCount> open{}; // filled from the registry's defaults
    bool& isOpen(PanelId id) { return open[static_cast<size_t>(id)]; }
    // Opens a panel and brings it to the front (its tab selected, or its window focused).
    void show(PanelId id) {
        isOpen(id) = true;
        showRequest = static_cast<int>(id);
    }
    int showRequest = -1; // served by the workspace in the next frame
    WorkspaceState workspace;
    std::vector<std::string> recent;       // recently opened model files, newest first (saved)
    int windowWidth = 0, windowHeight = 0; // the window's size, saved to open at it next time
    Rect resetDefaults; // the Models panel's last "reset to the file's defaults" (screen px)
    bool quit = false;
    std::string status; // one-line status shown in the menu bar
    SceneInspect inspect;
    // PNG export of a region of the frame: set by a panel, served after the frame is drawn
    std::string pngExportPath;
    float pngRect[4] = {0, 0, 0, 0}; // x0, y0, x1, y1 in framebuffer pixels (top-left origin)
};

struct MenuState {
    bool openModelPopup = false;
    bool recordPopup = false;
    bool mcmlPopup = false;
    FileDialogState openDialog; // File → Open model
    FileDialogState mcmlDialog; // File → Open MCML reference
    char nameBuffer[128] = "my_capture";
    // File → New model: its name and the model it starts from (a display path; empty: the
    // template, pipeline/new_model.h)
    bool newModelPopup = false;
    char newModelName[128] = "my_model";
    std::string newModelFrom;
};

struct ErrorsPanelState {
    int logMinLevel = 1;      // 0 debug .. 3 error (core log levels)
    Rect copyErrors, copyLog; // the Copy buttons last frame (screen px)
};

// "From albedo and length" in the Parameters panel: an artist mapping (pipeline/param_mappings.h)
// and its measurement by the path tracer, run in the background.
struct ArtistMeasurement {
    std::atomic<bool> done{false}, cancel{false};
    std::vector<LabCase> cases; // one per channel, filled when done
};
struct ArtistMappingState {
    std::string mapping = "rdr_ld_better_dipole";
    glm::dvec3 albedo{0.8, 0.6, 0.4}, lengthMm{4.0, 2.0, 1.0};
    std::string problem; // the mapping could not make σ from these values
    std::shared_ptr<ArtistMeasurement> measurement;
    uint64_t measurePaths = kLabPaths; // reference paths per channel of Measure
    std::string measuredKey;           // mapping, values, g and η the measurement was made for
    Rect header, applyButton, measureButton; // last frame (screen px)
};

struct ParametersPanelState {
    std::string target; // display path edited, "" = shared
    ArtistMappingState artist;
};

struct PencilPanelState {
    std::string plotPngRequest;           // Export PNG: turned into UiShared's export request
    char exportName[256] = "pencil_plot"; // export file name without extension
    ExportState exporter;                 // where to export (Export CSV / PNG ask)
    std::vector<std::array<float, 4>> exportButtons; // Export CSV, PNG last frame (screen px)
};

struct LitSpherePanelState {
    float exposure = 0.0f, gamma = 2.2f, diffRange = 0.0f; // diffRange 0: automatic
    bool diffZ = false;       // the difference in standard errors (z) instead of in value
    float zRange = 4.0f;      // |z| at full colour
    Rect zRadio;              // the z-score choice last frame (screen px)
    double relSe[2] = {0, 0}; // each image's relative standard error shown last frame
    SphereView view = SphereView::PathTraced;
    int viewShown = -1; // the tab last shown (to select a tab programmatically once)
    int pickX = -1, pickY = -1;
    char meshBuffer[512] = "";
    gl::Texture tex[3];
};

struct PointCloudPanelState {
    std::unique_ptr<SceneView> view;
    int picked = -1;                 // input index into the cloud
    glm::vec3 pickedExitance{-1.0f}; // M at the picked point (x < 0: not available)
    std::string colorsKey;           // what the uploaded colours show
    float colorMin = 0, colorMax = 1;
    char meshBuffer[512] = "third_party/bunny/bunny.obj";
    char plyBuffer[512] = "";
    Rect imageRect; // where the 3D view was drawn last frame (UI units), for clicks in tests
    // Where the picked point's ring was drawn last frame (UI units; x < 0: none) and whether
    // the point faced the camera (yellow) or away from it (grey, seen through the mesh).
    glm::vec2 pickedMarker{-1.0f};
    bool pickedFacing = false;
};

struct OctreePanelState {
    std::unique_ptr<SceneView> view;
    int level = 2;
    int selectedNode = 0;
    std::string boxesKey;
};

struct IrradiancePanelState {
    char envBuffer[512] = "materials/env/default_sky.exr";
    char textureBuffer[512] = "";
    gl::Texture cubeTex;
};

// What the Render panel shows: the point-cloud renderer (hierarchical or brute force: its
// render settings say which), the Monte Carlo render of the same view (monte_carlo_stage.h) or
// the texture-space render (texspace_stage.h).
enum class RenderMode { PointCloud, MonteCarlo, TextureSpace };

// What the texture-space view shows: the render, or one of its stages.
enum class TextureSpaceView { Render, Irradiance, CdfLevel, Samples, Atlas, Local, Global };

struct RenderPanelState {
    RenderMode mode = RenderMode::PointCloud;
    gl::Texture mcTex; // the Monte Carlo image, tone mapped
    gl::Texture tsTex; // the texture-space image or stage view
    TextureSpaceView tsView = TextureSpaceView::Render;
    int tsLevel = 0;              // the CDF mip level shown
    bool tsSamplesOnMesh = false; // the last set's texels as dots over the render
    Heatmap heatmap = Heatmap::Image;
    Rect imageRect;            // where the image was drawn last frame (screen pixels)
    render::Readback readback; // of the shown frame, for the pixel probe and export
    long long readbackRuns = -1;
    char exportName[256] = "render"; // export file name without extension
    ExportState exporter;            // where to export (Export EXR / PNG ask)
    Rect exportButtons[2];           // Export EXR, Export PNG last frame (screen px)
    bool abSplit = false;            // A/B: the render left of the divider, B right of it
    std::string abWith;              // B: "" brute force, else a model's display path
    float split = 0.5f;              // the divider, as a fraction of the image width
    gl::Texture abTex;               // the brute-force image
    long long abFrame = -1;          // the render (run count) whose brute force abTex holds
    Rect abLabels[2];                // where the "A: ..." and "B: ..." labels were drawn last
    gl::Texture heatTex;
    float heatMax = 0;
    // The image shown when it is not the frame's own (the Monte Carlo or texture-space render,
    // a heatmap): the pixel probe and the export read it. Width 0 while the frame is shown.
    struct ShownImage {
        std::string what; // "Monte Carlo render", "steps heatmap", ...
        int width = 0, height = 0;
        std::vector<uint8_t> rgba;           // as shown: tone mapped, misses in the background
        std::optional<pathtrace::Image> hdr; // the estimate (mean, variance); none: a colour map
    } shown;
};

// The Captures panel: the captures found, the selected one, a replay running in a child
// process and what it reported, the difference pictures of failing image stages.
// How often the Captures panel lists the captures folder again while it shows.
inline constexpr double kCapturesListSeconds = 1.0;
struct CapturesPanelState {
    std::vector<std::string> names;
    double listedAt = -1e9; // when `names` was read
    std::string selected, replaying;
    std::filesystem::path exe; // empty: this executable (tests name bssrdf-workbench)
    std::unique_ptr<ReplayProcess> proc;
    double started = 0;
    std::string report;
    struct Picture {
        std::string file, problem;
        gl::Texture tex;
        int width = 0, height = 0;
    };
    std::vector<Picture> pictures;
    // File → Record capture: recorded by a child process (`record --from-request`), so the GUI
    // never waits; its stage lines show progress, Cancel kills it and nothing is left
    std::unique_ptr<ChildProcess> recorder;
    std::string recording;               // the capture being recorded
    std::filesystem::path recordRequest; // the state it records (removed when it ends)
    double recordStarted = 0;
    std::string recordOutcome; // how the last recording ended ("" while none has)
    // "Open in a window": a capture's state in a workbench window of its own (`gui --capture`),
    // a child process, so this window's state stays as it is; stopped when this window closes
    struct CaptureWindow {
        std::string name;
        std::unique_ptr<ChildProcess> proc;
    };
    std::vector<CaptureWindow> windows;
    Rect openWindow;             // its button last frame (screen px; zero while none shows)
    std::vector<Rect> nameRects; // each listed capture last frame (screen px)
    // what the selected capture holds (captures/open_capture.h: describeCapture), read when it is
    // selected and again as the list is
    std::string described;
    std::vector<std::string> about;
    double describedAt = -1e9;
};

// The Scoreboard panel: which channels it lists (the table is ScoreboardStage's).
struct ScoreboardPanelState {
    int channel = 3;            // 0 R, 1 G, 2 B, 3 all
    std::vector<Rect> rowRects; // where each listed row was drawn last frame (screen px)
    // the geometry tab: the selected cell (model display path, shape), its picked pixel, the
    // cells' and the Run button's rectangles last frame (screen px), the images' textures
    std::string geometryModel, geometryShape;
    int pickX = -1, pickY = -1;
    std::vector<std::pair<std::string, Rect>> geometryCells; // "model|shape", where drawn
    Rect geometryRun, geometryTabRect;
    bool geometryTab = false; // the geometry tab was shown last frame
    gl::Texture tex[3];
};

// The Fit panel: the model and the parameters to fit (the fit itself is Workbench::fit()).
struct FitPanelState {
    std::string model;               // display path ("": the reference's model)
    std::vector<std::string> params; // the parameters ticked
    Rect fitButton, applyButton;     // last frame (screen px)
};

// The BSSRDF slice panel: what it compares and shows (the run's settings are SliceSettings).
enum class SliceQuantity { R, S };
struct SlicePanelState {
    std::string model;                         // the compared model's display path ("": first)
    SliceQuantity quantity = SliceQuantity::R; // R over the plane, or S in one exit cell
    int cell = 0;                              // S: the exit-direction cell shown
    int bin = -1;                              // the selected spatial bin (click), -1: none
    float decades = 4.0f;                      // log colour scale: this many decades below the max
    float diffRange = 0.5f;                    // relative difference at full colour
    bool greyTies = true;                      // differences within 2 standard errors drawn grey
    Rect refRect;                              // the reference heatmap last frame (screen px)
    Rect diffRect;                             // the difference heatmap last frame
    std::string summary;                       // the rel_err line last frame ("": none)
    float thetaEdit = 0, rangeEdit = 0;        // θi and r_max while their fields are edited
    bool editing[2] = {false, false};
};

struct TraversalPanelState {
    char filter[64] = "";
    bool showRecurse = true, showNodeEval = true, showPointEval = true;
    Rect copySteps;      // the Copy steps button last frame (screen px)
    Rect followBox, pin; // the follow checkbox and the Pin / Unpin button last frame
};

struct UiState {
    UiState(); // panels open as the registry's defaults say
    UiShared shared;
    MenuState menu;
    ErrorsPanelState errors;
    ParametersPanelState parameters;
    PencilPanelState pencil;
    LitSpherePanelState litSpheres;
    FitPanelState fit;
    PointCloudPanelState pointCloud;
    OctreePanelState octree;
    IrradiancePanelState irradiance;
    RenderPanelState render;
    TraversalPanelState traversal;
    CapturesPanelState captures;
    SlicePanelState slice;
    ScoreboardPanelState scoreboard;
    // While recordText is on (tests of what a panel says; off in the program), the text each
    // panel drew in the last frame it was drawn, as ImGui's log records it: a line per row of
    // widgets, tree nodes as they are. Text drawn after the panel opened a tooltip or a popup
    // is not in it (ImGui ends its log at the end of any top-level window).
    bool recordText = false;
    std::map<PanelId, std::string> panelText;
};

} // namespace app
