// plot::detail: pure geometry behind drawPlot (no ImGui): series → clipped polylines and band
// polygons in unit space, dash patterns, and label thinning. Unit space: [0,1] on both axes
// (y up) is the plot area; callers map it to pixels.
// Algorithms: Liang–Barsky segment clipping, Sutherland–Hodgman polygon clipping.
#pragma once

#include "plot/plot.h"

#include <cstddef>
#include <vector>

namespace plot::detail {

struct Vec2d {
    double x, y;
    bool operator==(const Vec2d&) const = default;
};
using Polyline = std::vector<Vec2d>;

// Clips the segment a-b to the box [lo,hi]²; false (a, b unspecified) when nothing is left.
// Ends that are inside stay bit-identical.
bool clipSegment(Vec2d& a, Vec2d& b, double lo, double hi);
// Clips a convex polygon to the box [lo,hi]²; empty when nothing is left.
std::vector<Vec2d> clipPolygon(const std::vector<Vec2d>& poly, double lo, double hi);

// Unit-space polylines of a series. A sample that does not map (NaN/inf, <= 0 on a log axis)
// breaks the line; segments are clipped to [-margin, 1+margin]² and a clipped segment ends
// its polyline. A valid sample with no valid neighbour gives a one-point polyline (a dot).
std::vector<Polyline> curvePolylines(const Series& s, const Axis& x, const Axis& y, double margin);
// Unit-space convex polygons (one per sample interval) of the error band, clipped likewise.
// On a log axis a band bottom <= 0 extends below the plot; intervals with a non-finite end
// or top are skipped.
std::vector<std::vector<Vec2d>> bandPolygons(const Series& s, const Axis& x, const Axis& y,
                                             double margin);

// Splits a polyline (any units) into dashes of length `dash` separated by gaps of `gap`.
std::vector<Polyline> dashPolyline(const Polyline& line, double dash, double gap);

// A label's extent along its axis (pixels) and its importance.
struct LabelSpan {
    double lo, hi;
    int priority;
};
// Indices of the labels to draw: by priority (higher first), then in order, a label is kept
// when it stays at least `gap` away from every label kept before it. Ascending indices.
std::vector<size_t> pickNonOverlapping(const std::vector<LabelSpan>& spans, double gap);

} // namespace plot::detail
