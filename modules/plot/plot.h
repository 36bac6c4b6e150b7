// plot: the pure half of a small 2D line plot for radial profiles R(r) (pencil plot,
// thesis §3.6.3). No ImGui here: the widget that draws it is plot/plot_draw.h (app/ only).
//   - Axes with linear, logarithmic and square-root scales (§3.6.3: log for the far field,
//     sqrt "as a useful addition to logarithmic plots" for an accurate comparison near the
//     source). The sqrt scale is signed, sign(v)·sqrt(|v|), so negative values stay legal.
//   - Ticks: "nice" 1-2-5 steps on linear axes; decades (+ 2..9 minors) on log axes, with
//     the labelled decades thinned so labels never crowd; on sqrt axes nice values chosen
//     coarse-first so they are evenly spread in sqrt space.
//   - Series: polylines with optional error bands (e.g. a Monte Carlo reference ±2σ);
//     NaN/inf samples and non-positive samples on a log axis break the line.
//   - Hover readout (value of every curve at the mouse x, linear interpolation), CSV export.
// Geometry helpers (clipping, dashing, label thinning) live in plot/detail/geometry.h.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace plot {

enum class Scale { Linear, Log, Sqrt };
constexpr auto enumNames(Scale) {
    return std::array{std::pair{Scale::Linear, "linear"}, std::pair{Scale::Log, "log"},
                      std::pair{Scale::Sqrt, "sqrt"}};
}
const char* scaleName(Scale s); // "linear", "log", "sqrt"

struct Series {
    std::string label;                  // empty: not shown in the legend / hover table
    std::vector<double> x, y;           // x ascending (needed by sampleAt); n = min(sizes)
    std::vector<double> bandLo, bandHi; // optional error band: same size as x, or empty
    uint32_t color = 0xffffffff;        // ImU32 (IM_COL32 packing: A<<24 | B<<16 | G<<8 | R)
    float thickness = 1.5f;             // pixels
    bool dashed = false;
    bool marker = false; // legend shows an error-bar mark (for reference / measured curves)
    int compareTo = -1;  // index of the series this one is compared with (relativeTo), -1: none
    std::string tooltip; // shown while the pointer is on its legend entry ("" for none)
};

// What a plot shows of its series: the values, or each series relative to the one it is
// compared with (Series::compareTo): their ratio, or their difference.
enum class Relation { Values, Ratio, Difference };
constexpr auto enumNames(Relation) {
    return std::array{std::pair{Relation::Values, "values"}, std::pair{Relation::Ratio, "ratio"},
                      std::pair{Relation::Difference, "difference"}};
}
// The series in `relation` to the series they are compared with: y / y_ref or y − y_ref, with
// y_ref linearly interpolated at each x (points outside the reference's x range, or where a
// ratio's y_ref ≤ 0, are dropped). A reference (compareTo its own index) becomes the constant
// 1 or 0 with its error band transformed alike, so the band shows the reference's own
// uncertainty on the same axis. Series compared with nothing are dropped; Values returns the
// series unchanged.
std::vector<Series> relativeTo(const std::vector<Series>& series, Relation relation);

struct Axis {
    double lo = 0, hi = 1;
    Scale scale = Scale::Linear;
    std::string label; // e.g. "r [mm]"
};

struct Tick {
    double value;
    std::string text; // empty: no label (minor ticks, thinned decades)
    bool major;       // major grid line (brighter)
};

// Distinct, readable-on-dark colours (Tableau 10), cycling.
uint32_t defaultColor(size_t index);

// ---- axis mapping (axis.cpp) ---------------------------------------------------------------
// A usable copy of `a`: finite, hi > lo, and lo > 0 on a log axis (swaps / widens as needed).
Axis sanitized(const Axis& a);
// Maps a value to [0,1] along the axis (log: log10, sqrt: signed sqrt). Values outside the
// range map outside [0,1]. Non-finite input, non-positive input on a log axis, or an unusable
// axis (hi == lo, log with lo <= 0) give NaN.
double toUnit(double v, const Axis& a);
double fromUnit(double u, const Axis& a); // inverse of toUnit
// A range that shows every finite sample of `series` (x or y; y includes the bands). Ignores
// NaN/inf and, on log, values <= 0. y is padded by 5% of the span (in scale space) but never
// across zero when the data do not cross it; x is not padded (curves touch the frame).
// Empty or single-valued data give a sane non-empty range. On a log y axis with
// maxLogDecades > 0 the range is cut to at most that many decades below the top.
Axis autoRange(const std::vector<Series>& series, Scale scale, bool isY, double maxLogDecades = 0);

// ---- ticks and labels (ticks.cpp) ----------------------------------------------------------
// Ticks inside [lo, hi], ascending. At most max(targetCount, 2) labelled ticks on linear and
// sqrt axes, max(targetCount, 1) labelled decades on log axes.
//   linear: majors at k·s with s = {1,2,5}·10^n, unlabelled minors at s/5 (s/4 for 2·10^n).
//   log:    every decade is a major; labelled decades are multiples of a 1-2-5 stride;
//           unlabelled 2..9 minors. Less than two decades in range: 2 and 5 (then all
//           mantissas, then linear ticks) get labels too. Very many decades (> 4·target):
//           no 2..9 minors and only the labelled decades are majors.
//   sqrt:   values i·s (|i| <= 10, s = {1,2,5}·10^n) picked coarse-first wherever they keep
//           an even spacing in sqrt space (0, 0.1, 0.5, 1, 2, 3, 5, 8, 10, 15, 20, 25); all
//           major and labelled. A narrow range far from zero falls back to linear majors.
std::vector<Tick> makeTicks(const Axis& a, int targetCount);
// Compact number for readouts: 4 significant digits, "%g"-style ("0.0123", "1.23e-05").
std::string formatValue(double v);

// ---- hover readout (sample.cpp) -----------------------------------------------------------
struct HoverRow {
    std::string label;
    double x, y;   // y NaN when x lies outside the series' samples (or it has none)
    double lo, hi; // interpolated band, NaN when the series has no band
    uint32_t color;
};
// One row per series: y at x, interpolated linearly between the two neighbouring samples.
std::vector<HoverRow> sampleAt(const std::vector<Series>& series, double x);
// A row of the hover readout: "label: y" ("n/a" outside the series' samples; "series N" for an
// unlabelled one, N from 1), its band as " [lo, hi]" where it has one. The readout's first line
// names x once for every row (each row is sampled at it).
std::string hoverRowText(const HoverRow& r, size_t index);

// ---- CSV export (csv.cpp) -----------------------------------------------------------------
// When every series has the same x grid: wide format "xName,label1,label2,..." with one row
// per x (a series with a band adds "label lo" and "label hi" columns). Otherwise long format
// "label,xName,y" (+ ",lo,hi" when any series has a band). Numbers are written with the
// shortest text that parses back to the same double (std::to_chars); labels are quoted when
// they contain ',', '"' or a line break. Non-finite values are written as nan / inf / -inf.
std::string toCsv(const std::vector<Series>& series, const std::string& xName);
// Writes toCsv() atomically; throws core::Error(path, 0, reason) when it cannot.
void writeCsv(const std::filesystem::path& path, const std::vector<Series>& series,
              const std::string& xName);

} // namespace plot
