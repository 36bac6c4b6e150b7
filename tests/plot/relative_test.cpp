// plot::relativeTo: ratio and difference against a reference interpolated linearly, bands
// transformed alike, points outside the reference dropped, unrelated series dropped.
#include "plot/plot.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

plot::Series line(std::vector<double> x, std::vector<double> y, int compareTo) {
    plot::Series s;
    s.x = std::move(x);
    s.y = std::move(y);
    s.compareTo = compareTo;
    return s;
}

} // namespace

TEST(RelativeTo, RatioAndDifferenceAgainstTheInterpolatedReference) {
    // reference y = 2x + 1 sampled at 0, 1, 2, 3 (exact under linear interpolation)
    plot::Series ref = line({0, 1, 2, 3}, {1, 3, 5, 7}, 1);
    ref.bandLo = {0.5, 2.5, 4.5, 6.5};
    ref.bandHi = {1.5, 3.5, 5.5, 7.5};
    const plot::Series model = line({0.5, 1.5, 2.5, 3.5}, {4, 8, 12, 99}, 1); // 3.5: outside
    const plot::Series alone = line({0, 1}, {1, 1}, -1);
    const std::vector<plot::Series> in{model, ref, alone};

    const auto ratio = plot::relativeTo(in, plot::Relation::Ratio);
    ASSERT_EQ(ratio.size(), 2u); // the series compared with nothing is dropped
    ASSERT_EQ(ratio[0].x.size(), 3u);
    EXPECT_DOUBLE_EQ(ratio[0].y[0], 4.0 / 2.0);
    EXPECT_DOUBLE_EQ(ratio[0].y[1], 8.0 / 4.0);
    EXPECT_DOUBLE_EQ(ratio[0].y[2], 12.0 / 6.0);
    for (double y : ratio[1].y)
        EXPECT_DOUBLE_EQ(y, 1.0);
    EXPECT_DOUBLE_EQ(ratio[1].bandLo[1], 2.5 / 3.0);
    EXPECT_DOUBLE_EQ(ratio[1].bandHi[1], 3.5 / 3.0);

    const auto diff = plot::relativeTo(in, plot::Relation::Difference);
    EXPECT_DOUBLE_EQ(diff[0].y[1], 8.0 - 4.0);
    for (double y : diff[1].y)
        EXPECT_DOUBLE_EQ(y, 0.0);
    EXPECT_DOUBLE_EQ(diff[1].bandLo[2], -0.5);

    EXPECT_EQ(plot::relativeTo(in, plot::Relation::Values).size(), 3u);
}

TEST(RelativeTo, RatioSkipsNonPositiveReferenceValues) {
    const plot::Series ref = line({0, 1, 2}, {0, -1, 2}, 1);
    const plot::Series model = line({0, 1, 2}, {1, 1, 1}, 1);
    const auto ratio = plot::relativeTo({model, ref}, plot::Relation::Ratio);
    ASSERT_EQ(ratio[0].x.size(), 1u);
    EXPECT_DOUBLE_EQ(ratio[0].x[0], 2.0);
    EXPECT_DOUBLE_EQ(ratio[0].y[0], 0.5);
}
