// Tests' one normal quantile: thresholds for z-tests of Monte Carlo results against references
// (DESIGN: "per-bin or per-pixel z-scores ... with a multiple-comparison correction").
#pragma once

#include <cmath>

namespace testsupport {

// Upper standard normal quantile: z with P(Z > z) = erfc(z/√2)/2 = p (0 < p < 1/2), by
// bisection on erfc (monotone), to double precision.
inline double normalQuantileUpper(double p) {
    double lo = 0, hi = 40;
    for (int i = 0; i < 200; ++i) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

// Two-sided threshold for `tests` z-tests at family-wise error `alpha` (Bonferroni):
// P(|Z| > z) = alpha / tests.
inline double bonferroniZ(double alpha, double tests) {
    return normalQuantileUpper(0.5 * alpha / tests);
}

} // namespace testsupport
