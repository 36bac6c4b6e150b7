// plot: axis mapping, sanitising, automatic ranges and hover sampling.
#include "plot/plot.h"

#include "plot_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

using plot_test::axis;
using plot_test::series;

TEST(PlotAxis, EndsMapToZeroAndOne) {
    for (plot::Scale s : {plot::Scale::Linear, plot::Scale::Log, plot::Scale::Sqrt}) {
        const plot::Axis a = axis(1e-3, 250.0, s);
        EXPECT_DOUBLE_EQ(plot::toUnit(a.lo, a), 0.0) << plot::scaleName(s);
        EXPECT_DOUBLE_EQ(plot::toUnit(a.hi, a), 1.0) << plot::scaleName(s);
    }
    EXPECT_DOUBLE_EQ(plot::toUnit(10.0, axis(1, 100, plot::Scale::Log)), 0.5);
    EXPECT_DOUBLE_EQ(plot::toUnit(25.0, axis(0, 100, plot::Scale::Sqrt)), 0.5);
    EXPECT_DOUBLE_EQ(plot::toUnit(-25.0, axis(-100, 100, plot::Scale::Sqrt)), 0.25);
    EXPECT_DOUBLE_EQ(plot::toUnit(3.0, axis(2, 4, plot::Scale::Linear)), 0.5);
}

TEST(PlotAxis, RoundTripAllScales) {
    const plot::Axis axes[] = {
        axis(-3.5, 12.0, plot::Scale::Linear), axis(0, 1e-6, plot::Scale::Linear),
        axis(1e-9, 1e2, plot::Scale::Log),     axis(0.5, 0.7, plot::Scale::Log),
        axis(0, 40.0, plot::Scale::Sqrt),      axis(-2.0, 8.0, plot::Scale::Sqrt)};
    for (const plot::Axis& a : axes) {
        for (double u = -0.25; u <= 1.25; u += 0.03125) {
            const double v = plot::fromUnit(u, a);
            ASSERT_TRUE(std::isfinite(v));
            EXPECT_NEAR(plot::toUnit(v, a), u, 1e-12) << plot::scaleName(a.scale) << " u=" << u;
            const double back = plot::fromUnit(plot::toUnit(v, a), a);
            EXPECT_NEAR(back, v, 1e-12 * std::max(std::abs(v), std::abs(a.hi)))
                << plot::scaleName(a.scale) << " v=" << v;
        }
    }
}

TEST(PlotAxis, InvalidValuesGiveNaN) {
    const plot::Axis lg = axis(1e-3, 1, plot::Scale::Log);
    EXPECT_TRUE(std::isnan(plot::toUnit(0.0, lg)));
    EXPECT_TRUE(std::isnan(plot::toUnit(-1.0, lg)));
    EXPECT_TRUE(std::isnan(plot::toUnit(kNaN, lg)));
    EXPECT_TRUE(std::isnan(plot::toUnit(kInf, axis(0, 1, plot::Scale::Linear))));
    EXPECT_TRUE(std::isnan(plot::toUnit(0.5, axis(1, 1, plot::Scale::Linear)))); // empty
    EXPECT_TRUE(std::isnan(plot::toUnit(0.5, axis(0, 1, plot::Scale::Log))));    // lo <= 0
    EXPECT_TRUE(std::isnan(plot::fromUnit(kNaN, axis(0, 1, plot::Scale::Linear))));
}

TEST(PlotAxis, SanitizedIsAlwaysUsable) {
    const plot::Axis bad[] = {
        axis(1, 1, plot::Scale::Linear),  axis(0, 0, plot::Scale::Linear),
        axis(5, -5, plot::Scale::Linear), axis(kNaN, kInf, plot::Scale::Linear),
        axis(0, 1, plot::Scale::Log),     axis(-1, -0.5, plot::Scale::Log),
        axis(3, 3, plot::Scale::Log),     axis(kNaN, 10, plot::Scale::Log),
        axis(2, 2, plot::Scale::Sqrt),    axis(0, 0, plot::Scale::Sqrt)};
    for (const plot::Axis& b : bad) {
        const plot::Axis a = plot::sanitized(b);
        EXPECT_LT(a.lo, a.hi) << b.lo << " " << b.hi;
        EXPECT_DOUBLE_EQ(plot::toUnit(a.lo, a), 0.0);
        EXPECT_DOUBLE_EQ(plot::toUnit(a.hi, a), 1.0);
    }
    EXPECT_EQ(plot::sanitized(axis(5, -5, plot::Scale::Linear)).lo, -5);
    const plot::Axis lg = plot::sanitized(axis(0, 10, plot::Scale::Log)); // keeps the top
    EXPECT_EQ(lg.hi, 10);
    EXPECT_GT(lg.lo, 0);
    const plot::Axis one = plot::sanitized(axis(2, 2, plot::Scale::Linear)); // around the value
    EXPECT_LT(one.lo, 2);
    EXPECT_GT(one.hi, 2);
}

TEST(PlotAxis, AutoRangeIgnoresNonFiniteAndNonPositiveOnLog) {
    std::vector<plot::Series> s = {series({0, 1, 2, 3, 4}, {0.0, -1.0, 1e-4, kNaN, 2.0}),
                                   series({0.5, 1.5}, {kInf, 1e-2})};
    const plot::Axis y = plot::autoRange(s, plot::Scale::Log, true);
    EXPECT_EQ(y.scale, plot::Scale::Log);
    EXPECT_GT(y.lo, 0);
    EXPECT_LT(y.lo, 1e-4);
    EXPECT_GT(y.lo, 1e-5); // padded by a fraction of the 4.3 decades, not more
    EXPECT_GT(y.hi, 2.0);
    EXPECT_LT(y.hi, 4.0);

    const plot::Axis yl = plot::autoRange(s, plot::Scale::Linear, true);
    EXPECT_LT(yl.lo, -1.0);
    EXPECT_GT(yl.hi, 2.0);
    EXPECT_LT(yl.hi, 2.0 + 0.1 * 3.0 + 1e-12);

    const plot::Axis x = plot::autoRange(s, plot::Scale::Linear, false); // x: no padding
    EXPECT_EQ(x.lo, 0);
    EXPECT_EQ(x.hi, 4);
    const plot::Axis xl = plot::autoRange(s, plot::Scale::Log, false); // x = 0 ignored
    EXPECT_EQ(xl.lo, 0.5);
    EXPECT_EQ(xl.hi, 4);
}

TEST(PlotAxis, AutoRangeDoesNotCrossZeroAndIncludesBands) {
    plot::Series s = series({0, 1, 2}, {1.0, 0.5, 0.25});
    s.bandLo = {0.9, 0.4, 0.0};
    s.bandHi = {1.5, 0.6, 0.3};
    const plot::Axis y = plot::autoRange({s}, plot::Scale::Linear, true);
    EXPECT_EQ(y.lo, 0.0);
    EXPECT_GT(y.hi, 1.5);
    const plot::Axis ys = plot::autoRange({s}, plot::Scale::Sqrt, true);
    EXPECT_EQ(ys.lo, 0.0);
    EXPECT_GT(ys.hi, 1.5);
}

TEST(PlotAxis, AutoRangeDegenerateCases) {
    for (plot::Scale sc : {plot::Scale::Linear, plot::Scale::Log, plot::Scale::Sqrt}) {
        for (bool isY : {false, true}) {
            const plot::Axis empty = plot::autoRange({}, sc, isY);
            EXPECT_LT(empty.lo, empty.hi);
            EXPECT_TRUE(std::isfinite(plot::toUnit(empty.lo, empty)));
            const plot::Axis allBad =
                plot::autoRange({series({kNaN, -1}, {kNaN, -1})}, plot::Scale::Log, isY);
            EXPECT_LT(allBad.lo, allBad.hi);
            EXPECT_GT(allBad.lo, 0);
            const plot::Axis one = plot::autoRange({series({3, 3}, {3, 3})}, sc, isY);
            EXPECT_LT(one.lo, 3.0);
            EXPECT_GT(one.hi, 3.0);
            const plot::Axis zero = plot::autoRange({series({0}, {0})}, sc, isY);
            EXPECT_LT(zero.lo, zero.hi);
        }
    }
}

TEST(PlotAxis, AutoRangeMaxLogDecades) {
    const plot::Axis y =
        plot::autoRange({series({0, 1, 2}, {1e-40, 1e-3, 10.0})}, plot::Scale::Log, true, 6);
    EXPECT_GT(y.lo, 1e-6);
    EXPECT_LT(y.lo, 1e-5);
    EXPECT_GT(y.hi, 10.0);
}

TEST(PlotSample, InterpolatesLinearly) {
    plot::Series a = series({0, 1, 2, 4}, {10, 20, 0, 8});
    a.label = "a";
    a.color = 0xff00ff00u;
    a.bandLo = {9, 18, -1, 7};
    a.bandHi = {11, 22, 1, 9};
    plot::Series b = series({1.5, 3}, {1, 4});
    const std::vector<plot::Series> s = {a, b};

    auto rows = plot::sampleAt(s, 0.25);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].label, "a");
    EXPECT_EQ(rows[0].color, 0xff00ff00u);
    EXPECT_DOUBLE_EQ(rows[0].x, 0.25);
    EXPECT_DOUBLE_EQ(rows[0].y, 12.5);
    EXPECT_DOUBLE_EQ(rows[0].lo, 11.25);
    EXPECT_DOUBLE_EQ(rows[0].hi, 13.75);
    EXPECT_TRUE(std::isnan(rows[1].y));  // outside b's samples
    EXPECT_TRUE(std::isnan(rows[1].lo)); // b has no band

    // the readout names x once above the rows: a row is its label and y (and band)
    EXPECT_EQ(plot::hoverRowText(rows[0], 0), "a: " + plot::formatValue(12.5) + " [" +
                                                  plot::formatValue(11.25) + ", " +
                                                  plot::formatValue(13.75) + "]");
    EXPECT_EQ(plot::hoverRowText(rows[1], 1), "series 2: n/a"); // unlabelled, outside
    rows = plot::sampleAt(s, 3.0);
    EXPECT_DOUBLE_EQ(rows[0].y, 4.0);
    EXPECT_DOUBLE_EQ(rows[1].y, 4.0); // last sample exactly
    rows = plot::sampleAt(s, 1.0);
    EXPECT_DOUBLE_EQ(rows[0].y, 20.0); // a sample exactly
    rows = plot::sampleAt(s, 0.0);
    EXPECT_DOUBLE_EQ(rows[0].y, 10.0);
    EXPECT_TRUE(std::isnan(rows[1].y));
}

TEST(PlotSample, EdgeCases) {
    const std::vector<plot::Series> s = {series({}, {}), series({1}, {5}),
                                         series({0, 1, 2}, {1, kNaN, 3}),
                                         series({0, 1, 1, 2}, {0, 1, 3, 4})};
    auto rows = plot::sampleAt(s, 1.0);
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_TRUE(std::isnan(rows[0].y));
    EXPECT_DOUBLE_EQ(rows[1].y, 5.0);
    EXPECT_TRUE(std::isnan(rows[2].y));    // the sample itself is NaN
    EXPECT_TRUE(std::isfinite(rows[3].y)); // duplicate x: one of the two values
    rows = plot::sampleAt(s, 0.5);
    EXPECT_TRUE(std::isnan(rows[2].y)); // next to a NaN sample
    EXPECT_DOUBLE_EQ(rows[3].y, 0.5);
    rows = plot::sampleAt(s, kNaN);
    for (const plot::HoverRow& r : rows)
        EXPECT_TRUE(std::isnan(r.y));
}

} // namespace
