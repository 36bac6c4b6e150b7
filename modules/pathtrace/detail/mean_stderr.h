// pathtrace: mean and standard error of the mean of scale·x from per-path sums Σx, Σx² over n
// paths — the one estimator every tally (slab histogram, images, totals) is finalised with:
//   mean = scale·Σx/n,  stderr = |scale|·sqrt((Σx²/n − (Σx/n)²)/(n − 1)).
// n = 0: mean 0, stderr ∞. n = 1: stderr ∞, or 0 when `zeroWhenSumsZero` and both sums are 0
// (image pixels nothing reached are exactly 0 with no uncertainty).
#pragma once

#include "core/relative_error.h"
#include "pathtrace/pathtrace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

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

namespace pathtrace::detail {

// The batch of path `path` (the tallies' batchSum): the paths' indices modulo kBatches.
inline size_t batchOf(uint64_t path) {
    return size_t(path % kBatches);
}

// The batch means of bins from their per-batch sums (batch-major, `bins` per batch) and the
// batches' path counts: mean[b][i] = scale(i)·Σ_b,i / N_b. Empty (not known) without sums or
// while a batch has fewer than 2 paths.
template <class Scale>
core::BatchMeans batchMeans(const std::vector<double>& sums,
                            const std::array<uint64_t, kBatches>& n, size_t bins, Scale&& scale) {
    core::BatchMeans out;
    if (sums.size() != kBatches * bins || bins == 0) return out;
    uint64_t total = 0;
    for (uint64_t k : n) {
        if (k < 2) return out;
        total += k;
    }
    out.fraction.resize(kBatches);
    out.mean.assign(kBatches, std::vector<double>(bins));
    for (size_t b = 0; b < kBatches; ++b) {
        out.fraction[b] = double(n[b]) / double(total);
        for (size_t i = 0; i < bins; ++i)
            out.mean[b][i] = scale(i) * sums[b * bins + i] / double(n[b]);
    }
    return out;
}

} // namespace pathtrace::detail
