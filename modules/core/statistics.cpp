// core statistics: the median; the normal quantile by bisection (see statistics.h).
#include "core/statistics.h"

#include <algorithm>
#include <cmath>

namespace core {

double median(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double normalUpperQuantile(double p) {
    // bisection on the upper tail Q(z) = erfc(z/√2)/2, monotone decreasing in z
    double lo = -40, hi = 40;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (0.5 * std::erfc(mid / std::sqrt(2.0)) > p)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

double bonferroniZ(double alpha, double tests) {
    return normalUpperQuantile(0.5 * alpha / tests);
}

} // namespace core
