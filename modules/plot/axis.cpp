// plot: axis mapping (linear / log10 / signed sqrt), sanitising and automatic ranges.
#include "plot/plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plot {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The scale's transform: identity, log10, signed sqrt. NaN where undefined.
double forward(double v, Scale s) {
    if (!std::isfinite(v)) return kNaN;
    switch (s) {
    case Scale::Linear:
        return v;
    case Scale::Log:
        return v > 0 ? std::log10(v) : kNaN;
    case Scale::Sqrt:
        return v < 0 ? -std::sqrt(-v) : std::sqrt(v);
    }
    return kNaN;
}

double inverse(double t, Scale s) {
    switch (s) {
    case Scale::Linear:
        return t;
    case Scale::Log:
        return std::pow(10.0, t);
    case Scale::Sqrt:
        return t < 0 ? -(t * t) : t * t;
    }
    return kNaN;
}

bool usable(double v, Scale s) {
    return std::isfinite(v) && (s != Scale::Log || v > 0);
}

} // namespace

const char* scaleName(Scale s) {
    for (const auto& [v, n] : enumNames(s))
        if (v == s) return n;
    return "?";
}

uint32_t defaultColor(size_t index) {
    // Tableau 10, as IM_COL32(r, g, b, 255).
    static const uint32_t rgb[] = {0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2, 0x59a14f,
                                   0xedc948, 0xb07aa1, 0xff9da7, 0x9c755f, 0xbab0ac};
    const uint32_t c = rgb[index % (sizeof(rgb) / sizeof(rgb[0]))];
    const uint32_t r = (c >> 16) & 0xff, g = (c >> 8) & 0xff, b = c & 0xff;
    return 0xff000000u | (b << 16) | (g << 8) | r;
}

Axis sanitized(const Axis& a) {
    Axis out = a;
    const bool logScale = a.scale == Scale::Log;
    double lo = a.lo, hi = a.hi;
    const bool loOk = usable(lo, a.scale), hiOk = usable(hi, a.scale);
    if (!loOk && !hiOk) {
        lo = logScale ? 1e-3 : 0.0;
        hi = 1.0;
    } else if (!loOk) {
        lo = logScale ? hi * 1e-3 : hi - 1.0;
    } else if (!hiOk) {
        hi = logScale ? lo * 1e3 : lo + 1.0;
    }
    if (lo > hi) std::swap(lo, hi);
    const double tlo = forward(lo, a.scale), thi = forward(hi, a.scale);
    if (!(thi > tlo) || !std::isfinite(thi - tlo)) {
        if (logScale) {
            lo /= 10.0;
            hi *= 10.0;
        } else {
            const double half = lo != 0 ? std::abs(lo) * 0.1 : 1.0;
            lo -= half;
            hi += half;
        }
        if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo)) {
            lo = logScale ? 1e-3 : 0.0;
            hi = 1.0;
        }
    }
    out.lo = lo;
    out.hi = hi;
    return out;
}

double toUnit(double v, const Axis& a) {
    const double t = forward(v, a.scale);
    const double t0 = forward(a.lo, a.scale), t1 = forward(a.hi, a.scale);
    const double span = t1 - t0;
    if (!std::isfinite(t) || !std::isfinite(span) || span == 0) return kNaN;
    return (t - t0) / span;
}

double fromUnit(double u, const Axis& a) {
    const double t0 = forward(a.lo, a.scale), t1 = forward(a.hi, a.scale);
    if (!std::isfinite(u) || !std::isfinite(t0) || !std::isfinite(t1)) return kNaN;
    return inverse(t0 + u * (t1 - t0), a.scale);
}

Axis autoRange(const std::vector<Series>& series, Scale scale, bool isY, double maxLogDecades) {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    auto take = [&](const std::vector<double>& values, size_t n) {
        for (size_t i = 0; i < n && i < values.size(); ++i) {
            const double v = values[i];
            if (!usable(v, scale)) continue;
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    };
    for (const Series& s : series) {
        const size_t n = std::min(s.x.size(), s.y.size());
        if (!isY) {
            take(s.x, n);
            continue;
        }
        take(s.y, n);
        take(s.bandLo, n);
        take(s.bandHi, n);
    }

    Axis a;
    a.scale = scale;
    if (!(hi >= lo)) { // no usable value
        a.lo = scale == Scale::Log ? 1e-3 : 0.0;
        a.hi = 1.0;
        return a;
    }
    if (isY && scale == Scale::Log && maxLogDecades > 0)
        lo = std::max(lo, hi * std::pow(10.0, -maxLogDecades));
    a.lo = lo;
    a.hi = hi;
    if (!(hi > lo)) return sanitized(a); // single value: widened around it

    if (isY) {
        const double t0 = forward(lo, scale), t1 = forward(hi, scale);
        const double pad = 0.05 * (t1 - t0);
        double p0 = t0 - pad, p1 = t1 + pad;
        if (scale != Scale::Log) { // do not invent a sign change the data do not have
            if (t0 >= 0 && p0 < 0) p0 = 0;
            if (t1 <= 0 && p1 > 0) p1 = 0;
        }
        a.lo = inverse(p0, scale);
        a.hi = inverse(p1, scale);
    }
    return sanitized(a);
}

} // namespace plot
