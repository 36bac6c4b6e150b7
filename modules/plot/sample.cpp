// plot: the hover readout, each series sampled at one x by linear interpolation.
#include "plot/plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plot {

namespace {
constexpr double kMissing = std::numeric_limits<double>::quiet_NaN(); // no value here

// Value of v at position (i, t) between samples i and i+1; NaN when v is too short.
double lerpAt(const std::vector<double>& v, size_t i, double t) {
    if (i + 1 >= v.size()) return i < v.size() && t == 0 ? v[i] : kMissing;
    if (t == 0) return v[i];
    if (t == 1) return v[i + 1];
    return v[i] + t * (v[i + 1] - v[i]);
}

} // namespace

std::vector<HoverRow> sampleAt(const std::vector<Series>& series, double x) {
    std::vector<HoverRow> rows;
    rows.reserve(series.size());
    for (const Series& s : series) {
        HoverRow row{s.label, x, kMissing, kMissing, kMissing, s.color};
        const size_t n = std::min(s.x.size(), s.y.size());
        if (n == 0 || !std::isfinite(x) || x < s.x[0] || x > s.x[n - 1]) {
            rows.push_back(row);
            continue;
        }
        // First sample with x_i > x; the segment is [i-1, i] (or the last sample itself).
        const auto end = s.x.begin() + static_cast<std::ptrdiff_t>(n);
        size_t i = static_cast<size_t>(std::upper_bound(s.x.begin(), end, x) - s.x.begin());
        size_t i0;
        double t;
        if (i >= n) { // x == last sample
            i0 = n - 1;
            t = 0;
        } else {
            i0 = i - 1; // i >= 1 because x >= x[0]
            const double dx = s.x[i] - s.x[i0];
            t = dx > 0 ? (x - s.x[i0]) / dx : 0;
        }
        row.y = lerpAt(s.y, i0, t);
        if (s.bandLo.size() >= n && s.bandHi.size() >= n) {
            row.lo = lerpAt(s.bandLo, i0, t);
            row.hi = lerpAt(s.bandHi, i0, t);
        }
        rows.push_back(row);
    }
    return rows;
}

} // namespace plot
