// plot::detail: clipping, series polylines with breaks, band polygons, dashes, label thinning.
#include "plot/detail/geometry.h"

#include "plot_helpers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

using plot::detail::Polyline;
using plot::detail::Vec2d;

using plot_test::axis;
using plot_test::series;

TEST(PlotGeometry, ClipSegment) {
    Vec2d a{0.5, 0.5}, b{0.25, 0.75};
    ASSERT_TRUE(plot::detail::clipSegment(a, b, 0, 1)); // inside: untouched
    EXPECT_EQ(a, (Vec2d{0.5, 0.5}));
    EXPECT_EQ(b, (Vec2d{0.25, 0.75}));
    a = {0.5, 0.5};
    b = {0.5, 3.0};
    ASSERT_TRUE(plot::detail::clipSegment(a, b, 0, 1));
    EXPECT_EQ(a, (Vec2d{0.5, 0.5}));
    EXPECT_DOUBLE_EQ(b.y, 1.0);
    a = {-1, -1};
    b = {2, 2};
    ASSERT_TRUE(plot::detail::clipSegment(a, b, 0, 1));
    EXPECT_DOUBLE_EQ(a.x, 0);
    EXPECT_DOUBLE_EQ(b.y, 1);
    a = {-1, 2};
    b = {2, 2};
    EXPECT_FALSE(plot::detail::clipSegment(a, b, 0, 1));
    a = {0.5, 0.5}; // a spike (e.g. R(r) near r = 0 on a linear axis): still exact
    b = {0.75, 1e18};
    ASSERT_TRUE(plot::detail::clipSegment(a, b, 0, 1));
    EXPECT_EQ(b.y, 1.0);
    EXPECT_NEAR(b.x, 0.5, 1e-15);
}

TEST(PlotGeometry, ClipPolygon) {
    const std::vector<Vec2d> square = {{-1, -1}, {2, -1}, {2, 2}, {-1, 2}};
    const std::vector<Vec2d> c = plot::detail::clipPolygon(square, 0, 1);
    ASSERT_EQ(c.size(), 4u);
    for (const Vec2d& v : c) {
        EXPECT_TRUE(v.x == 0 || v.x == 1);
        EXPECT_TRUE(v.y == 0 || v.y == 1);
    }
    EXPECT_TRUE(plot::detail::clipPolygon({{2, 2}, {3, 2}, {3, 3}}, 0, 1).empty());
    EXPECT_EQ(plot::detail::clipPolygon({{0.1, 0.1}, {0.9, 0.1}, {0.5, 0.9}}, 0, 1).size(), 3u);
}

TEST(PlotGeometry, CurveBreaksAtInvalidSamples) {
    const plot::Axis x = axis(0, 10, plot::Scale::Linear);
    const plot::Axis y = axis(1e-3, 1, plot::Scale::Log);
    // 0,1,2 good | 3 NaN | 4,5 good | 6 zero (log) | 7 alone | 8 inf | 9,10 good
    const plot::Series s = series({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10},
                                  {0.5, 0.4, 0.3, NAN, 0.2, 0.1, 0.0, 0.05, INFINITY, 0.02, 0.01});
    const std::vector<Polyline> p = plot::detail::curvePolylines(s, x, y, 0.0);
    ASSERT_EQ(p.size(), 4u);
    EXPECT_EQ(p[0].size(), 3u);
    EXPECT_EQ(p[1].size(), 2u);
    EXPECT_EQ(p[2].size(), 1u); // isolated sample: a dot
    EXPECT_DOUBLE_EQ(p[2][0].x, 0.7);
    EXPECT_EQ(p[3].size(), 2u);
    for (const Polyline& l : p)
        for (const Vec2d& v : l) {
            EXPECT_TRUE(std::isfinite(v.x) && std::isfinite(v.y));
            EXPECT_GE(v.y, 0.0);
            EXPECT_LE(v.y, 1.0);
        }
}

TEST(PlotGeometry, CurveClippedAtTheFrame) {
    const plot::Axis x = axis(0, 4, plot::Scale::Linear);
    const plot::Axis y = axis(0, 1, plot::Scale::Linear);
    // Goes out through the top and comes back: two pieces, both ending on the margin line.
    const plot::Series s = series({0, 1, 2, 3, 4}, {0.5, 0.5, 1e12, 0.5, 0.5});
    const std::vector<Polyline> p = plot::detail::curvePolylines(s, x, y, 0.1);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_DOUBLE_EQ(p[0].back().y, 1.1);
    EXPECT_DOUBLE_EQ(p[1].front().y, 1.1);
    EXPECT_EQ(p[0].front(), (Vec2d{0.0, 0.5}));
    EXPECT_EQ(p[1].back(), (Vec2d{1.0, 0.5}));
    // Entirely outside: nothing.
    EXPECT_TRUE(plot::detail::curvePolylines(series({0, 1}, {5, 6}), x, y, 0.1).empty());
}

TEST(PlotGeometry, BandPolygons) {
    const plot::Axis x = axis(0, 2, plot::Scale::Linear);
    const plot::Axis y = axis(0.1, 10, plot::Scale::Log);
    plot::Series s = series({0, 1, 2}, {1, 1, 1});
    EXPECT_TRUE(plot::detail::bandPolygons(s, x, y, 0).empty()); // no band
    s.bandLo = {0.5, -1.0, NAN};                                 // log: <= 0 goes to the bottom
    s.bandHi = {2, 2, 2};
    const auto polys = plot::detail::bandPolygons(s, x, y, 0);
    ASSERT_EQ(polys.size(), 1u); // second interval has a NaN end
    double minY = 1;
    for (const Vec2d& v : polys[0])
        minY = std::min(minY, v.y);
    EXPECT_DOUBLE_EQ(minY, 0.0);
    s.bandLo = {0.5, 0.5}; // too short: ignored
    EXPECT_TRUE(plot::detail::bandPolygons(s, x, y, 0).empty());
}

TEST(PlotGeometry, DashPolyline) {
    const Polyline line = {{0, 0}, {10, 0}, {10, 10}};
    const std::vector<Polyline> d = plot::detail::dashPolyline(line, 3, 2);
    // 20 units: on 0-3, 5-8, 10-13 (around the corner), 15-18.
    ASSERT_EQ(d.size(), 4u);
    EXPECT_EQ(d[0].front(), (Vec2d{0, 0}));
    EXPECT_EQ(d[0].back(), (Vec2d{3, 0}));
    ASSERT_EQ(d[2].size(), 2u);
    EXPECT_EQ(d[2].front(), (Vec2d{10, 0}));
    EXPECT_DOUBLE_EQ(d[2].back().y, 3.0);
    EXPECT_DOUBLE_EQ(d[3].back().y, 8.0);
    EXPECT_EQ(plot::detail::dashPolyline(line, 3, 0).size(), 1u);
}

TEST(PlotGeometry, PickNonOverlappingPrefersMajors) {
    using plot::detail::LabelSpan;
    const std::vector<LabelSpan> spans = {{0, 10, 0},  {8, 18, 1},  {20, 30, 0},
                                          {29, 39, 0}, {50, 60, 1}, {59, 70, 1}};
    const std::vector<size_t> kept = plot::detail::pickNonOverlapping(spans, 1.0);
    EXPECT_EQ(kept, (std::vector<size_t>{1, 2, 4}));
}

} // namespace
