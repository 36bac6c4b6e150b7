// Series relative to a reference (plot.h, relativeTo): ratio or difference, with the
// reference linearly interpolated at each abscissa.
#include "plot.h"

#include <algorithm>
#include <cmath>

namespace plot {
namespace {

// y of `s` at x by linear interpolation; NaN outside its range.
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
    const size_t n = std::min(xs.size(), ys.size());
    if (n == 0 || x < xs[0] || x > xs[n - 1]) return NAN;
    const size_t hi = size_t(std::lower_bound(xs.begin(), xs.begin() + long(n), x) - xs.begin());
    if (hi == 0) return ys[0];
    const size_t lo = hi - 1;
    const double t = xs[hi] > xs[lo] ? (x - xs[lo]) / (xs[hi] - xs[lo]) : 0.0;
    return ys[lo] + t * (ys[hi] - ys[lo]);
}

} // namespace

std::vector<Series> relativeTo(const std::vector<Series>& series, Relation relation) {
    if (relation == Relation::Values) return series;
    std::vector<Series> out;
    for (const Series& s : series) {
        if (s.compareTo < 0 || size_t(s.compareTo) >= series.size()) continue;
        const Series& ref = series[size_t(s.compareTo)];
        Series r = s;
        r.x.clear();
        r.y.clear();
        r.bandLo.clear();
        r.bandHi.clear();
        r.compareTo = -1;
        const size_t n = std::min(s.x.size(), s.y.size());
        const bool band = s.bandLo.size() >= n && s.bandHi.size() >= n;
        for (size_t i = 0; i < n; ++i) {
            const double base = interpolate(ref.x, ref.y, s.x[i]);
            if (!std::isfinite(base) || (relation == Relation::Ratio && base <= 0)) continue;
            auto rel = [&](double v) { return relation == Relation::Ratio ? v / base : v - base; };
            r.x.push_back(s.x[i]);
            r.y.push_back(rel(s.y[i]));
            if (band) {
                r.bandLo.push_back(rel(s.bandLo[i]));
                r.bandHi.push_back(rel(s.bandHi[i]));
            }
        }
        out.push_back(std::move(r));
    }
    return out;
}

} // namespace plot
