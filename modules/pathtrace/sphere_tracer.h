// pathtrace/sphere_tracer: the path-traced lit sphere (thesis 3.2 on the geometry of 3.5 /
// 3.6.2), CPU. Setup and pixel definition: lit_sphere.h; estimator and determinism: camera.h;
// the walk inside: sphere_walk.h (the slab tracer's physics and implicit estimator).
//   Source: entry points are sampled uniformly on the light's projected disk (radius R, area
//   A_src = πR², power πR² W at 1 W/mm²), each path carrying πR²/N. The entry ray along
//   −lightDir meets the lit hemisphere at x with cos θi = n·lightDir; the Fresnel reflectance
//   F(cos θi) is specular reflection, not subsurface exitance: it is tallied per path
//   (ChannelStats::specular) and dropped; the path refracts in (Snell) with weight 1 − F.
//   Exit: at a transmission through the boundary at xo the path leaves with its weight; the
//   total is tallied (ChannelStats::exited, every exit, visible or not); xo is visible iff
//   n(xo)·z > 0 (convex sphere), and then the weight goes to the pixel xo projects into.
//   Pixels: a pixel is covered iff its centre ray hits the sphere (centre inside the disk of
//   radius R); its footprint A_pix is the exact visible sphere area over the pixel square,
//       A_pix = ∫∫_{pixel ∩ disk} R / √(R² − x² − y²) dx dy
//             = R ∫ [asin(y/√(R² − x²))]_{y0}^{y1} dx   (inner integral exact, y/√ clamped to ±1),
//   the outer integral by 32-point Gauss–Legendre on each piece between the kinks
//   (x = ±√(R² − y0²), ±√(R² − y1²), ±R) after the substitution x = a + (b − a)(3t² − 2t³),
//   which removes the square-root endpoint singularities (relative error < 1e-9, tested
//   against Archimedes: every column sums to πR·width). The value M = power into the pixel /
//   A_pix is the area average of M over the footprint, the lit_sphere.h value at the pixel's
//   centre point to O(pixel²); pixels partially outside the disk use the part inside.
//   Path count: N = samplesPerPixel × (number of covered pixels), so a pixel gets about
//   samplesPerPixel paths' worth of entries when the light is along the view axis.
//   RGB: channel c is traced with media[c] and its own streams (camera.h).
#pragma once

#include "pathtrace/camera.h"
#include "pathtrace/lit_sphere.h"
#include "pathtrace/pathtrace.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>

namespace pathtrace {

// Paths per channel of traceLitSphere: samplesPerPixel × covered pixels (validates).
uint64_t litSpherePaths(const LitSphereSetup& s);
// Footprint areas (mm², 0 where the centre ray misses) and n·lightDir at the centre points.
PixelGeometry sphereFootprints(const LitSphereSetup& s);
// Visible sphere area (mm²) over the rectangle [x0, x1] × [y0, y1] (any rectangle).
double sphereAreaOver(double radius, double x0, double x1, double y0, double y1);

// The RGB exitance image (lit_sphere.h) of the sphere with media[c] per channel. Validates the
// media, setup and options first (core::Error). progress(done paths) is called from the
// calling thread about every 50 ms; when `cancel` is set the image covers the completed
// prefix of path chunks (fewer samples, still unbiased). Bitwise the same for any thread
// count. `stats` (optional) receives the totals and pixel geometry.
Image traceLitSphere(const std::array<Medium, 3>& media, const LitSphereSetup& setup,
                     const std::function<void(uint64_t done)>& progress = {},
                     const std::atomic<bool>* cancel = nullptr, const TraceOptions& options = {},
                     ImageStats* stats = nullptr);

} // namespace pathtrace
