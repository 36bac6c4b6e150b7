// core/statistics.h: the median of a sample; the standard normal quantile behind every z-test of a
// Monte Carlo result (capture comparison of csv_stat/exr_stat outputs, statistical tests): DESIGN's
// "z-scores against stored means and variances, with a multiple-comparison correction"
// (Bonferroni).
#pragma once

#include <vector>

namespace core {

// The middle value of `v` (the mean of the two middle ones for an even count); NaN when empty.
double median(std::vector<double> v);

// Φ⁻¹(1 − p) for 0 < p < 1: z with P(Z > z) = erfc(z/√2)/2 = p, by bisection on erfc
// (monotone) over [−40, 40] to double precision.
double normalUpperQuantile(double p);

// Two-sided threshold for `tests` z-tests at family-wise error `alpha` (Bonferroni):
// P(|Z| > z) = alpha / tests.
double bonferroniZ(double alpha, double tests);

} // namespace core
