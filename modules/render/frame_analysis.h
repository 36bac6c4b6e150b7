// render/frame_analysis: what the workbench reads off a rendered frame (CPU, no GL) — the
// traversal heatmaps of the Render panel, the radiance the camera sees at given surface
// points (the point cloud panel's "radiance" colouring), and the brute-force sum of thesis
// eq. 3.3 at one surface point for the traversal debugger:
//     M(xo) = Σ_i E_i A_i · S(xi, xo)   over every point of the cloud (no hierarchy),
// with positions scaled to mm as the shader does (A_i in mesh units², scale² to mm²); and the
// Errors text of a frame whose radiance has NaN, infinite or negative pixels.
#pragma once

#include "core/color.h"
#include "octree/octree.h"
#include "render/camera.h"
#include "render/render.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <string>
#include <vector>

namespace render {

// Per pixel quantities of a frame's traversal.
enum class HeatQuantity {
    Steps,         // traversal iterations (stats.x)
    StackDepth,    // maximum stack depth (stats.y)
    RelativeError, // |L(M) − L(M_brute)| / L(M_brute) of the exitance's luminance L
};
// The quantity per pixel of `rb` (−1 where the pixel shows no surface, or for RelativeError
// where `brute` has no value for it; 0 where the brute-force luminance is 0) and its maximum
// over the frame in `maxValue` (0 when no pixel has a value).
std::vector<float> heatValues(const Readback& rb, HeatQuantity q,
                              const std::vector<glm::vec4>& brute, float& maxValue);

// The luminance of the rendered radiance L_o at the pixel each point projects to through
// `cam` (its aspect taken from the frame), when the surface seen there lies within `tol`
// (mesh units) of the point — the point is the one the camera sees; −1 otherwise (outside the
// frame, behind the camera, hidden or background).
std::vector<float> radianceAtPoints(const Readback& rb, Camera cam,
                                    const std::vector<glm::vec3>& points, float tol);

// The BSSRDF pairs of every octree point (slot order) towards the surface point (xo, no), in
// the shader's convention (scale·xi, ni, scale·xo, no); evaluate them (evaluatePairs), then
// bruteForceExitance sums M(xo) = Σ E_i A_i scale² S_i.
std::vector<BssrdfPair> allPointPairs(const octree::Octree& tree, glm::vec3 xo, glm::vec3 no,
                                      float scale);
glm::vec3 bruteForceExitance(const octree::Octree& tree, const std::vector<glm::vec3>& values,
                             float scale);

// "" when the frame has no invalid pixel, else e.g. "L_o is NaN at 812 of 5210 surface pixels
// (magenta), negative at 3 (black)".
std::string invalidPixelsProblem(const InvalidPixels& n);

} // namespace render
