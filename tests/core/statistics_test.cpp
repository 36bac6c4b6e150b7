// The normal quantile every z-test uses (core/statistics.h) against tabulated values; the median.
#include "core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>

TEST(CoreStatistics, NormalUpperQuantileMatchesKnownValues) {
    // Φ⁻¹(1 − p), values from standard normal tables
    EXPECT_NEAR(core::normalUpperQuantile(0.025), 1.959964, 1e-5);
    EXPECT_NEAR(core::normalUpperQuantile(0.5), 0.0, 1e-9);
    EXPECT_NEAR(core::normalUpperQuantile(1e-5), 4.264891, 1e-5);
    EXPECT_NEAR(core::normalUpperQuantile(0.975), -1.959964, 1e-5); // lower half: symmetric
    // the defining identity erfc(z/√2)/2 = p holds to double precision
    for (double p : {0.3, 1e-3, 1e-9}) {
        const double z = core::normalUpperQuantile(p);
        EXPECT_NEAR(0.5 * std::erfc(z / std::sqrt(2.0)), p, 1e-12 * p) << p;
    }
}

TEST(CoreStatistics, BonferroniSplitsAlphaOverTestsAndTails) {
    // 100 two-sided tests at family alpha 1e-3: each tail gets 5e-6
    EXPECT_DOUBLE_EQ(core::bonferroniZ(1e-3, 100), core::normalUpperQuantile(5e-6));
    EXPECT_NEAR(core::bonferroniZ(0.05, 1), 1.959964, 1e-5);
}

TEST(CoreStatistics, MedianIsTheMiddleValueOrTheMeanOfTheTwoMiddleOnes) {
    EXPECT_EQ(core::median({3.0, 1.0, 2.0}), 2.0);
    EXPECT_EQ(core::median({4.0, 1.0, 3.0, 2.0}), 2.5);
    EXPECT_EQ(core::median({7.0}), 7.0);
    EXPECT_TRUE(std::isnan(core::median({})));
}
