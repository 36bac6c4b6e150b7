// pathtrace: mean and standard error of the mean of scale·x from per-path sums Σx, Σx² over n
// paths — the one estimator every tally (slab histogram, images, totals) is finalised with:
//   mean = scale·Σx/n,  stderr = |scale|·sqrt((Σx²/n − (Σx/n)²)/(n − 1)).
// n = 0: mean 0, stderr ∞. n = 1: stderr ∞, or 0 when `zeroWhenSumsZero` and both sums are 0
// (image pixels nothing reached are exactly 0 with no uncertainty).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace pathtrace::detail {

inline void meanStderr(double sum, double sumSq, uint64_t n, double scale, double& mean,
                       double& err, bool zeroWhenSumsZero = true) {
    if (n == 0) {
        mean = 0;
        err = std::numeric_limits<double>::infinity();
        return;
    }
    const double N = static_cast<double>(n);
    const double m = sum / N;
    mean = scale * m;
    if (n < 2) {
        err = zeroWhenSumsZero && sum == 0 && sumSq == 0 ? 0
                                                         : std::numeric_limits<double>::infinity();
        return;
    }
    err = std::fabs(scale) * std::sqrt(std::max(0.0, sumSq / N - m * m) / (N - 1.0));
}

} // namespace pathtrace::detail
