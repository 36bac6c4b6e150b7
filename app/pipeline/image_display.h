// Lit-sphere image helpers (pure CPU): merging independent progressive passes, HDR display
// (exposure, gamma), the signed difference and z-score views with their colour bars, each
// image's relative standard error, pixel readouts.
#pragma once

#include "pathtrace/lit_sphere.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace app {

// Combines two independent estimates of the same image made from n_a and n_b samples:
// mean = (n_a m_a + n_b m_b)/(n_a + n_b), variance of the mean likewise with squared weights.
pathtrace::Image combine(const pathtrace::Image& a, const pathtrace::Image& b);

// RGBA8 for display: value · 2^exposure, then ^(1/gamma), clamped; a pixel with a NaN or
// infinite value (a model that returned one) is magenta, never black.
std::vector<uint8_t> tonemap(const pathtrace::Image& img, float exposure, float gamma);

// The pixels of `rgba` (RGBA8, as tonemap makes it) whose `hits` entry has w < 0.5 (a G-buffer
// or read-back of the same frame: w = 1 hit, 0 miss) in `background`, a display colour, as the
// renderer's tone mapping shows a miss (render::Settings::background, render_tonemap.comp): an
// image of the frame by another renderer (Monte Carlo, texture space) shows its misses as the
// frame does. Nothing changes when the sizes differ.
void paintMisses(std::vector<uint8_t>& rgba, const std::vector<glm::vec4>& hits,
                 glm::vec3 background);

// Signed difference a − b of the luminance, mapped to blue (negative) – black – red
// (positive) with |a − b| = range at full saturation.
std::vector<uint8_t> differenceMap(const pathtrace::Image& a, const pathtrace::Image& b,
                                   float range);
std::array<uint8_t, 3> divergingColor(float t); // t in [−1, 1]; NaN: magenta
// A sequential colour map (dark violet → yellow, lightness increasing) for t in [0, 1].
std::array<uint8_t, 3> sequentialColor(float t);

// Largest |a − b| of the luminance over the pixels (a default range for the difference view).
float maxAbsDifference(const pathtrace::Image& a, const pathtrace::Image& b);

// The difference in standard errors: z = (L_a − L_b)/√(Var L_a + Var L_b) per pixel, L the
// luminance and Var L = Σ w_c² Var_c (channels traced apart, so independent), mapped like
// differenceMap with |z| = zRange at full saturation; |z| < 2 (noise) is grey, a pixel both
// images leave black is black, and a difference with no variance to weigh it is magenta.
std::vector<uint8_t> zMap(const pathtrace::Image& a, const pathtrace::Image& b, float zRange);

// The relative standard error of an image: the median over its lit pixels (luminance > 0) of
// √Var L / L. NaN when no pixel is lit.
double relativeStandardError(const pathtrace::Image& img);

struct PixelValue {
    bool valid = false;
    std::array<float, 3> mean{}, stderr_{};
};
PixelValue pixelAt(const pathtrace::Image& img, int x, int y);

} // namespace app
