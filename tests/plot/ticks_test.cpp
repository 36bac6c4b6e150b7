// plot: tick placement (linear 1-2-5, log decades, sqrt) and number formatting.
#include "plot/plot.h"

#include "plot_helpers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace {

using plot_test::axis;

std::vector<plot::Tick> labelled(const std::vector<plot::Tick>& t) {
    std::vector<plot::Tick> out;
    for (const plot::Tick& k : t)
        if (!k.text.empty()) out.push_back(k);
    return out;
}

bool isPowerOfTen(double v) {
    const double e = std::log10(v);
    return std::abs(e - std::round(e)) < 1e-12;
}

void expectAscendingInRange(const std::vector<plot::Tick>& t, const plot::Axis& a) {
    const double slack = a.scale == plot::Scale::Log ? a.lo * 1e-9 : (a.hi - a.lo) * 1e-9;
    const double hiSlack = a.scale == plot::Scale::Log ? a.hi * 1e-9 : slack;
    for (size_t i = 0; i < t.size(); ++i) {
        EXPECT_GE(t[i].value, a.lo - slack) << i;
        EXPECT_LE(t[i].value, a.hi + hiSlack) << i;
        if (i > 0) {
            EXPECT_LT(t[i - 1].value, t[i].value) << i;
        }
    }
}

TEST(PlotTicks, LogLabelledDecadesAreThinnedSubset) {
    const plot::Axis a = axis(1e-9, 1e2, plot::Scale::Log);
    for (int target = 1; target <= 14; ++target) {
        const std::vector<plot::Tick> ticks = plot::makeTicks(a, target);
        expectAscendingInRange(ticks, a);
        const std::vector<plot::Tick> lab = labelled(ticks);
        ASSERT_GE(lab.size(), 1u) << target;
        EXPECT_LE(static_cast<int>(lab.size()), target);
        for (const plot::Tick& t : lab) {
            EXPECT_TRUE(isPowerOfTen(t.value)) << t.text;
            EXPECT_TRUE(t.major);
            EXPECT_NEAR(std::strtod(t.text.c_str(), nullptr), t.value, t.value * 1e-12) << t.text;
        }
        int decades = 0;
        for (const plot::Tick& t : ticks)
            decades += isPowerOfTen(t.value);
        EXPECT_EQ(decades, 12) << "every decade keeps a grid line";
    }
    // 12 decades, target 5: every third decade (1e-9, 1e-6, 1e-3, 1).
    const std::vector<plot::Tick> lab = labelled(plot::makeTicks(a, 5));
    ASSERT_EQ(lab.size(), 4u);
    EXPECT_EQ(lab[0].text, "1e-9");
    EXPECT_EQ(lab[1].text, "1e-6");
    EXPECT_EQ(lab[2].text, "1e-3");
    EXPECT_EQ(lab[3].text, "1");
    // Everything labelled when there is room; 2..9 minors unlabelled.
    const std::vector<plot::Tick> all = plot::makeTicks(a, 12);
    EXPECT_EQ(labelled(all).size(), 12u);
    size_t minors = 0;
    for (const plot::Tick& t : all)
        if (!t.major) {
            ++minors;
            EXPECT_TRUE(t.text.empty());
        }
    EXPECT_EQ(minors, 11u * 8u);
}

TEST(PlotTicks, LogManyDecadesDropsMinors) {
    const plot::Axis a = axis(1e-300, 1e300, plot::Scale::Log);
    const std::vector<plot::Tick> ticks = plot::makeTicks(a, 6);
    expectAscendingInRange(ticks, a);
    EXPECT_LE(labelled(ticks).size(), 6u);
    EXPECT_GE(labelled(ticks).size(), 1u);
    for (const plot::Tick& t : ticks)
        EXPECT_TRUE(isPowerOfTen(t.value));
}

TEST(PlotTicks, LogNarrowRangesStillGetLabels) {
    for (const plot::Axis& a :
         {axis(2, 80, plot::Scale::Log), axis(2, 8, plot::Scale::Log),
          axis(0.31, 0.97, plot::Scale::Log), axis(2.1, 2.9, plot::Scale::Log)}) {
        const std::vector<plot::Tick> ticks = plot::makeTicks(a, 6);
        expectAscendingInRange(ticks, a);
        const std::vector<plot::Tick> lab = labelled(ticks);
        EXPECT_GE(lab.size(), 2u) << a.lo << ".." << a.hi;
        for (const plot::Tick& t : lab)
            EXPECT_NEAR(std::strtod(t.text.c_str(), nullptr), t.value, t.value * 1e-9) << t.text;
    }
    const std::vector<plot::Tick> lab = labelled(plot::makeTicks(axis(2, 80, plot::Scale::Log), 6));
    ASSERT_EQ(lab.size(), 5u); // one decade in range: 2, 5, 10, 20, 50
    EXPECT_EQ(lab[0].text, "2");
    EXPECT_EQ(lab[4].text, "50");
}

// Majors of a linear axis: equal 1/2/5·10^k steps covering [lo, hi].
void checkLinear(const plot::Axis& a, int target) {
    SCOPED_TRACE(testing::Message() << a.lo << ".." << a.hi << " target " << target);
    const std::vector<plot::Tick> ticks = plot::makeTicks(a, target);
    expectAscendingInRange(ticks, a);
    std::vector<plot::Tick> majors;
    for (const plot::Tick& t : ticks) {
        if (t.major) {
            majors.push_back(t);
            EXPECT_FALSE(t.text.empty());
        } else {
            EXPECT_TRUE(t.text.empty());
        }
    }
    ASSERT_GE(majors.size(), 2u);
    EXPECT_LE(static_cast<int>(majors.size()), std::max(target, 2));
    const double step = majors[1].value - majors[0].value;
    const double e = std::floor(std::log10(step) + 1e-9);
    const double mant = step / std::pow(10.0, e);
    EXPECT_TRUE(std::abs(mant - 1) < 1e-6 || std::abs(mant - 2) < 1e-6 || std::abs(mant - 5) < 1e-6)
        << "step " << step;
    for (size_t i = 1; i < majors.size(); ++i)
        EXPECT_NEAR(majors[i].value - majors[i - 1].value, step, step * 1e-6);
    for (const plot::Tick& t : majors) {
        EXPECT_NEAR(t.value / step, std::round(t.value / step), 1e-6) << "on the step grid";
        EXPECT_NEAR(std::strtod(t.text.c_str(), nullptr), t.value, step * 1e-6) << t.text;
    }
    EXPECT_LT(majors.front().value - a.lo, step * (1 + 1e-9)); // covers the range
    EXPECT_LT(a.hi - majors.back().value, step * (1 + 1e-9));
}

TEST(PlotTicks, LinearNiceSteps) {
    const plot::Axis axes[] = {
        axis(0, 1, plot::Scale::Linear),        axis(0, 10, plot::Scale::Linear),
        axis(-3.7, 12.2, plot::Scale::Linear),  axis(0.001, 0.0173, plot::Scale::Linear),
        axis(-1e-7, 3e-7, plot::Scale::Linear), axis(123456, 987654, plot::Scale::Linear),
        axis(-5e9, -1e9, plot::Scale::Linear),  axis(0, 1, plot::Scale::Linear)};
    for (const plot::Axis& a : axes)
        for (int target : {4, 5, 7, 10, 20})
            checkLinear(a, target);
}

TEST(PlotTicks, LinearLabelsAreClean) {
    const std::vector<plot::Tick> lab =
        labelled(plot::makeTicks(axis(0, 1, plot::Scale::Linear), 11));
    ASSERT_EQ(lab.size(), 11u);
    EXPECT_EQ(lab[0].text, "0");
    EXPECT_EQ(lab[3].text, "0.3");
    EXPECT_EQ(lab[3].value, 0.3); // 3 · 0.1 computed as 3 / 10
    EXPECT_EQ(lab[10].text, "1.0");
    const std::vector<plot::Tick> sci =
        labelled(plot::makeTicks(axis(0, 4e-6, plot::Scale::Linear), 5));
    ASSERT_GE(sci.size(), 2u);
    EXPECT_EQ(sci[1].text, "1e-6");
    const std::vector<plot::Tick> neg =
        labelled(plot::makeTicks(axis(-1.05e-4, 0, plot::Scale::Linear), 3));
    ASSERT_EQ(neg.size(), 3u);
    EXPECT_EQ(neg[0].text, "-1e-4");
    EXPECT_EQ(neg[1].text, "-5e-5");
    EXPECT_EQ(neg[2].text, "0");
    const std::vector<plot::Tick> big =
        labelled(plot::makeTicks(axis(1.5e7, 2.6e7, plot::Scale::Linear), 3));
    ASSERT_EQ(big.size(), 3u);
    EXPECT_EQ(big[0].text, "1.5e7");
    EXPECT_EQ(big[1].text, "2e7");
}

TEST(PlotTicks, SqrtTicksSpreadInSqrtSpace) {
    for (const plot::Axis& a :
         {axis(0, 1, plot::Scale::Sqrt), axis(0, 7, plot::Scale::Sqrt),
          axis(0, 0.0372, plot::Scale::Sqrt), axis(-4, 9, plot::Scale::Sqrt),
          axis(2, 300, plot::Scale::Sqrt), axis(1000, 1001, plot::Scale::Sqrt)}) {
        for (int target : {3, 5, 8}) {
            SCOPED_TRACE(testing::Message() << a.lo << ".." << a.hi << " target " << target);
            const std::vector<plot::Tick> ticks = plot::makeTicks(a, target);
            expectAscendingInRange(ticks, a);
            EXPECT_GE(ticks.size(), 2u);
            EXPECT_LE(static_cast<int>(ticks.size()), target);
            for (size_t i = 0; i < ticks.size(); ++i) {
                EXPECT_FALSE(ticks[i].text.empty());
                EXPECT_NEAR(std::strtod(ticks[i].text.c_str(), nullptr), ticks[i].value,
                            1e-9 * (a.hi - a.lo));
                if (i > 0) { // evenly spread: no two closer than 0.7 of the ideal spacing
                    EXPECT_GE(plot::toUnit(ticks[i].value, a) - plot::toUnit(ticks[i - 1].value, a),
                              0.7 / (target - 1) - 1e-12);
                }
            }
        }
    }
    // On [0, 1] more than one tick lies in the lowest quarter of the values (sqrt space
    // gives the near field room), unlike nice linear ticks.
    const std::vector<plot::Tick> t = plot::makeTicks(axis(0, 1, plot::Scale::Sqrt), 6);
    int low = 0;
    for (const plot::Tick& k : t)
        low += k.value < 0.25;
    EXPECT_GE(low, 3);
    EXPECT_EQ(t.front().value, 0.0);
    EXPECT_EQ(t.back().value, 1.0);
}

TEST(PlotTicks, FormatValue) {
    EXPECT_EQ(plot::formatValue(0.0123), "0.0123");
    EXPECT_EQ(plot::formatValue(1.23e-5), "1.23e-05");
    EXPECT_EQ(plot::formatValue(0.0), "0");
    EXPECT_EQ(plot::formatValue(-0.0), "0");
    EXPECT_EQ(plot::formatValue(12.345678), "12.35");
    EXPECT_EQ(plot::formatValue(std::nan("")), "nan");
    EXPECT_EQ(plot::formatValue(-INFINITY), "-inf");
}

} // namespace
