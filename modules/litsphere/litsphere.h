// litsphere: the shared setup of the thesis's lit-sphere widgets (3.5, 3.6.2), used by the
// path-traced sphere (and mesh) images (pathtrace) and the BSSRDF-integrated sphere (bssrdf), so
// that the two are the same picture of the same quantity. Plain data, below both modules.
//   Geometry: a sphere of radius `radiusMm` centred at the origin (meshes: normalised to one
//   unit on the longest axis, centred, times `scaleMm`). Light: directional, travelling along
//   −lightDir (lightDir points from the surface towards the light), irradiance 1 W/mm² on a
//   plane perpendicular to it. Camera: orthographic, looking along −z from +z, the image
//   square [−extent, extent]² in x (right) and y (up) with extent = 1.1 · radius, pixel (0,0)
//   at the top left.
//   Pixel value: radiant exitance M(xo) (W/mm² per W/mm² of irradiance, i.e. unitless) at the
//   first surface point xo the pixel's camera ray hits, per colour channel; pixels that miss
//   the object are 0 with variance 0. Path tracer: light enters through the lit surface with
//   Fresnel refraction; the exitance estimate of a pixel is the power leaving through its
//   surface footprint (pixel area / |n·z|) divided by that footprint. BSSRDF integration:
//   M(xo) = ∫_A Bssrdf(xi, wi, xo, wo) · Ft(η, cos θi) · max(0, n(xi)·lightDir) dA(xi), with
//   wi = lightDir, wo = n(xo), estimated by uniform area sampling (thesis 3.5).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace litsphere {

struct Setup {
    double radiusMm = 10.0;
    double lightDir[3] = {0.0, 0.0, 1.0}; // unit, towards the light (normalised on use)
    int width = 128, height = 128;
    uint64_t samplesPerPixel = 64; // path tracer: paths per pixel-equivalent (see tracer)
    uint64_t seed = 1;
    int threads = 0;
    double extent() const { return 1.1 * radiusMm; }
};

// A per-pixel estimate with its variance of the mean, RGB, row-major, top row first.
struct Image {
    int width = 0, height = 0;
    std::vector<float> mean;     // 3 floats per pixel
    std::vector<float> variance; // 3 floats per pixel: variance of the mean (stderr²)
    uint64_t samples = 0;        // samples (paths or BSSRDF evaluations) that made it
};

} // namespace litsphere
