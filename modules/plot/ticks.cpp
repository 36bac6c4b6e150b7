// plot: tick placement and labels for linear, log and sqrt axes, and readout formatting.
#include "plot/plot.h"

#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace plot {

namespace {

constexpr double kEps = 1e-9; // relative slack so range ends count as inside

long floorDiv(long x, long d) {
    return x >= 0 ? x / d : -((-x + d - 1) / d);
}

// The n-th "nice" step: {1, 2, 5}[n mod 3] · 10^floor(n / 3).
int mantissaOf(long n) {
    static const int mant[] = {1, 2, 5};
    return mant[n - 3 * floorDiv(n, 3)];
}
// i · niceStep(n), computed so that e.g. 3 · 0.1 gives the double nearest 0.3.
double gridValue(double i, long n) {
    const long e = floorDiv(n, 3);
    const double im = i * mantissaOf(n);
    return e >= 0 ? im * std::pow(10.0, static_cast<double>(e))
                  : im / std::pow(10.0, static_cast<double>(-e));
}
double niceStep(long n) {
    return gridValue(1, n);
}
// Largest n with niceStep(n) <= s (s > 0).
long niceIndexBelow(double s) {
    long n = 3 * static_cast<long>(std::floor(std::log10(s)));
    while (niceStep(n + 1) <= s)
        ++n;
    while (niceStep(n) > s)
        --n;
    return n;
}

std::string compactExponent(std::string s) { // "1.5e-05" -> "1.5e-5", "2e+06" -> "2e6"
    const size_t e = s.find('e');
    if (e == std::string::npos) return s;
    std::string mant = s.substr(0, e), exp = s.substr(e + 1);
    bool neg = false;
    if (!exp.empty() && (exp[0] == '+' || exp[0] == '-')) {
        neg = exp[0] == '-';
        exp.erase(0, 1);
    }
    exp.erase(0, std::min(exp.find_first_not_of('0'), exp.size() - 1));
    return mant + "e" + (neg ? "-" : "") + exp;
}

// Label of a tick at v on a grid of step `step`; `sci` forces scientific notation.
std::string tickText(double v, double step, bool sci) {
    if (std::abs(v) < step * kEps) return "0";
    char buf[64];
    const int stepExp = static_cast<int>(std::floor(std::log10(step) + kEps));
    if (!sci) {
        std::snprintf(buf, sizeof buf, "%.*f", std::max(0, -stepExp), v);
        return buf;
    }
    // Fewest mantissa digits that still name the grid value ("1e-4", "1.5e-4").
    const int vExp = static_cast<int>(std::floor(std::log10(std::abs(v)) + kEps));
    for (int digits = 0; digits < std::max(0, vExp - stepExp); ++digits) {
        std::snprintf(buf, sizeof buf, "%.*e", digits, v);
        if (std::abs(std::strtod(buf, nullptr) - v) < 1e-6 * step) return compactExponent(buf);
    }
    std::snprintf(buf, sizeof buf, "%.*e", std::max(0, vExp - stepExp), v);
    return compactExponent(buf);
}
bool useScientific(const Axis& a, double step) {
    return std::max(std::abs(a.lo), std::abs(a.hi)) >= 1e6 || step < 1e-4;
}

// "0.01", "0.1", "1", "10", "100" near 1; "2e-5", "1e3" further away.
std::string logText(int mantissa, int exponent) {
    char buf[32];
    if (std::abs(exponent) <= 2)
        std::snprintf(buf, sizeof buf, "%g", mantissa * std::pow(10.0, exponent));
    else
        std::snprintf(buf, sizeof buf, "%de%d", mantissa, exponent);
    return buf;
}

void sortTicks(std::vector<Tick>& t) {
    std::sort(t.begin(), t.end(), [](const Tick& a, const Tick& b) { return a.value < b.value; });
}

std::vector<Tick> linearTicks(const Axis& a, int target) {
    target = std::max(target, 2);
    const double range = a.hi - a.lo;
    const double slack = range * kEps;
    auto countFor = [&](double s) {
        return std::floor((a.hi + slack) / s) - std::ceil((a.lo - slack) / s) + 1;
    };
    long n = niceIndexBelow(range / (4.0 * target));
    while (countFor(niceStep(n)) > target)
        ++n;
    const double step = niceStep(n);
    std::vector<Tick> ticks;
    const double i0 = std::ceil((a.lo - slack) / step), i1 = std::floor((a.hi + slack) / step);
    if (std::max(std::abs(i0), std::abs(i1)) > 1e14) { // range too narrow for its magnitude
        for (double v : {a.lo, a.hi})
            ticks.push_back({v, core::formatNumber(v, 12), true});
        return ticks;
    }
    const bool sci = useScientific(a, step);
    for (double i = i0; i <= i1; ++i) {
        const double v = gridValue(i, n);
        ticks.push_back({v, tickText(v, step, sci), true});
    }
    const int sub = mantissaOf(n) == 2 ? 4 : 5;
    const double ms = step / sub;
    const double j0 = std::ceil((a.lo - slack) / ms), j1 = std::floor((a.hi + slack) / ms);
    for (double j = j0; j <= j1; ++j) {
        const double r = std::fmod(j, static_cast<double>(sub));
        if (r == 0) continue;
        ticks.push_back({j * ms, "", false}); // unlabelled: exact value does not matter
    }
    sortTicks(ticks);
    return ticks;
}

std::vector<Tick> logTicks(const Axis& a, int target) {
    target = std::max(target, 1);
    const double e0 = std::log10(a.lo), e1 = std::log10(a.hi);
    const int kMin = static_cast<int>(std::ceil(e0 - kEps));
    const int kMax = static_cast<int>(std::floor(e1 + kEps));
    const int nDec = kMax - kMin + 1;
    const double loS = a.lo * (1 - kEps), hiS = a.hi * (1 + kEps);
    std::vector<Tick> ticks;

    if (nDec >= 2) {
        // Smallest stride in 1, 2, 3, 5, 10, 20, 30, 50, ... labelling <= target decades.
        static const int strideMant[] = {1, 2, 3, 5};
        auto multiples = [&](long s) { return floorDiv(kMax, s) - floorDiv(kMin - 1, s); };
        long stride = 1;
        for (long p = 1, i = 0;; ++i) {
            stride = strideMant[i % 4] * p;
            if (i % 4 == 3) p *= 10;
            if (multiples(stride) <= target) break;
        }
        const bool huge = nDec > 4 * target;
        const bool none = multiples(stride) == 0;
        for (int k = kMin; k <= kMax; ++k) {
            const bool labelled = none ? k == kMax : k % stride == 0;
            ticks.push_back({std::pow(10.0, k), labelled ? logText(1, k) : "", !huge || labelled});
        }
        if (!huge) {
            for (int k = kMin - 1; k <= kMax; ++k)
                for (int m = 2; m <= 9; ++m) {
                    const double v = m * std::pow(10.0, k);
                    if (v >= loS && v <= hiS) ticks.push_back({v, "", false});
                }
        }
        sortTicks(ticks);
        return ticks;
    }

    // Less than two decades: label mantissas too.
    struct Cand {
        double v;
        int m, k;
    };
    std::vector<Cand> cands;
    for (int k = static_cast<int>(std::floor(e0)) - 1; k <= static_cast<int>(std::ceil(e1)); ++k)
        for (int m = 1; m <= 9; ++m) {
            const double v = m * std::pow(10.0, k);
            if (v >= loS && v <= hiS) cands.push_back({v, m, k});
        }
    for (const std::vector<int>& labelSet :
         {std::vector<int>{1, 2, 5}, std::vector<int>{1, 2, 3, 4, 5, 6, 7, 8, 9}}) {
        ticks.clear();
        int labelled = 0;
        for (const Cand& c : cands) {
            const bool lab = std::find(labelSet.begin(), labelSet.end(), c.m) != labelSet.end();
            labelled += lab;
            ticks.push_back({c.v, lab ? logText(c.m, c.k) : "", c.m == 1});
        }
        if (labelled >= 2) return ticks; // already ascending
    }
    Axis lin = a; // within one mantissa step: plain linear ticks (all positive here)
    lin.scale = Scale::Linear;
    return linearTicks(lin, target);
}

std::vector<Tick> sqrtTicks(const Axis& a, int target) {
    target = std::max(target, 2);
    auto T = [](double v) { return v < 0 ? -std::sqrt(-v) : std::sqrt(v); };
    const double t0 = T(a.lo), t1 = T(a.hi);
    const double minGap = 0.7 * (t1 - t0) / (target - 1);
    const double range = a.hi - a.lo, slack = range * kEps;
    struct Pick {
        double v, t, step;
    };
    std::vector<Pick> picks;
    // Values i·step with |i| <= 10 only, so labels stay short: 0.5, 3, 15, 40 (never 6.4).
    const long nMin = niceIndexBelow(range / (100.0 * target));
    const long nMax = niceIndexBelow(std::max(std::abs(a.lo), std::abs(a.hi))) + 1;
    for (long n = nMax; n >= nMin && (int)picks.size() < target; --n) {
        const double step = niceStep(n);
        const double i0 = std::max(-10.0, std::ceil((a.lo - slack) / step));
        const double i1 = std::min(10.0, std::floor((a.hi + slack) / step));
        for (double i = i0; i <= i1 && (int)picks.size() < target; ++i) {
            const double v = gridValue(i, n);
            const double t = T(v);
            bool ok = true;
            for (const Pick& p : picks)
                if (std::abs(p.t - t) < minGap) {
                    ok = false;
                    break;
                }
            if (ok) picks.push_back({v, t, step});
        }
    }
    if (picks.size() < 2) { // narrow range far from zero: sqrt is nearly linear there
        Axis lin = a;
        lin.scale = Scale::Linear;
        std::vector<Tick> ticks = linearTicks(lin, target);
        std::erase_if(ticks, [](const Tick& t) { return !t.major; });
        return ticks;
    }
    std::sort(picks.begin(), picks.end(), [](const Pick& x, const Pick& y) { return x.v < y.v; });
    std::vector<Tick> ticks;
    for (const Pick& p : picks)
        ticks.push_back({p.v, tickText(p.v, p.step, useScientific(a, p.step)), true});
    return ticks;
}

} // namespace

std::vector<Tick> makeTicks(const Axis& axis, int targetCount) {
    const Axis a = sanitized(axis);
    switch (a.scale) {
    case Scale::Linear:
        return linearTicks(a, targetCount);
    case Scale::Log:
        return logTicks(a, targetCount);
    case Scale::Sqrt:
        return sqrtTicks(a, targetCount);
    }
    return {};
}

std::string formatValue(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    if (v == 0) return "0";
    return core::formatNumber(v, 4);
}

} // namespace plot
