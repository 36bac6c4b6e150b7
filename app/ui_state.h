// UI-only state: which panels are open, pending popups and export requests.
#pragma once

#include "gl/gl.h"
#include "scene_stage.h"
#include "scene_view.h"

#include <memory>
#include <optional>
#include <vector>

#include <string>

namespace app {

struct UiState {
    bool showModels = true;
    bool showParameters = true;
    bool showPencil = true;
    bool showErrors = true;
    bool showTimings = true;
    bool showLitSpheres = false; // View → Lit spheres
    bool quit = false;
    bool openModelPopup = false;
    bool recordPopup = false;
    char pathBuffer[512] = "";
    char nameBuffer[128] = "my_capture";
    std::string plotPngRequest; // Export PNG: the pencil panel turns it into the two below
    std::string pngExportPath;  // set by the pencil panel; the runner reads pixels after render
    float pngRect[4] = {0, 0, 0, 0};      // x0, y0, x1, y1 in framebuffer pixels (top-left origin)
    std::string status;                   // one-line status shown in the menu bar
    std::string paramsTarget;             // Parameters panel: display path edited, "" = shared
    char exportName[256] = "pencil_plot"; // Pencil plot: export file name without extension
    int logMinLevel = 1;                  // Errors / Log panel: 0 debug .. 3 error
    // Lit spheres panel: display settings, textures, the clicked pixel
    float sphereExposure = 0.0f, sphereGamma = 2.2f, diffRange = 0.0f; // 0: automatic
    int sphereView = 0; // 0 path traced, 1 integrated, 2 side by side, 3 difference
    int sphereViewShown = -1;
    int pickX = -1, pickY = -1;
    char meshBuffer[512] = "";
    gl::Texture sphereTex[3];
    // Scene panels (point cloud, octree, irradiance, render, traversal debugger)
    bool showPointCloud = true, showOctree = false, showIrradiance = false, showRender = true,
         showTraversal = false;
    std::unique_ptr<SceneView> pointView, octreeView;
    render::Camera inspectCamera; // the 3D inspector views' camera (not the render camera)
    bool inspectCameraSet = false;
    int colorBy = 0;                 // 0 normal, 1 area, 2 irradiance, 3 radiance (from the frame)
    int pickedPoint = -1;            // input index into the cloud
    glm::vec3 pickedExitance{-1.0f}; // M at the picked point (x < 0: not available)
    std::string pointColorsKey;      // what the uploaded colours show
    float colorMin = 0, colorMax = 1;
    int octreeLevel = 2;
    int selectedNode = 0;
    bool highlightTrace = true;
    std::string octreeBoxesKey;
    char sceneMeshBuffer[512] = "third_party/bunny/bunny.obj";
    char plyBuffer[512] = "";
    char envBuffer[512] = "materials/env/default_sky.exr";
    char textureBuffer[512] = "";
    int heatmap = 0; // 0 image, 1 steps, 2 max stack depth, 3 relative error vs brute force
    gl::Texture heatTex, cubeTex;
    float heatMax = 0;
    std::optional<PixelDebug> debug;
    std::string debugProblem;
    char traceFilter[64] = "";
    bool showRecurse = true, showNodeEval = true, showPointEval = true;
};

} // namespace app
