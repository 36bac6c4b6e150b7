// Shared by the splitting and expected-value-exit tests: whether independent runs' spread matches
// the standard errors they report, bin by bin from `firstBin` on. Pooled over the bins,
// Σ (x − x̄)²/se² ~ χ² with (runs − 1) · bins degrees of freedom; the ratio to its mean lies
// within ±5 of its standard deviations (reported errors that are too small give a ratio well
// above 1).
#pragma once

#include "pathtrace/pathtrace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

inline void expectSpreadMatchesStandardErrors(const std::vector<pathtrace::SlabResult>& r,
                                              size_t firstBin) {
    const double runs = double(r.size());
    double sum = 0;
    int dof = 0;
    for (size_t b = firstBin; b < r[0].rd.size(); ++b) {
        double mean = 0, se2 = 0;
        for (const pathtrace::SlabResult& x : r) {
            mean += x.rd[b] / runs;
            se2 += x.rdStderr[b] * x.rdStderr[b] / runs;
        }
        for (const pathtrace::SlabResult& x : r)
            sum += (x.rd[b] - mean) * (x.rd[b] - mean) / se2;
        dof += int(r.size()) - 1;
    }
    const double ratio = sum / dof, sd = std::sqrt(2.0 / dof);
    EXPECT_LT(std::fabs(ratio - 1.0), 5 * sd) << "spread / reported error² = " << ratio;
}
