// capture comparison: tolerance boundaries (a tolerance must be able to fail), NaN/inf rules,
// shape mismatches and the one-line report.
#include "capture/capture.h"
#include "core/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using capture::compareTables;
using capture::Table;

namespace {

Table profile() {
    return {{}, {"r_mm", "R", "G"}, {{0.0, 0.0, 1.0}, {0.5, 2.0, -3.0}, {1.0, 0.25, 1e-9}}};
}

// `expected` with the value at (row, col) replaced by `v`.
Table with(Table t, size_t row, size_t col, double v) {
    t.rows[row][col] = v;
    return t;
}

} // namespace

TEST(Compare, IdenticalTablesPassExactly) {
    capture::Comparison c = compareTables("pencil_plot", profile(), profile(), 0, 0);
    EXPECT_TRUE(c.pass);
    EXPECT_EQ(c.values, 9u);
    EXPECT_EQ(c.failing, 0u);
    EXPECT_EQ(c.worstExcess, 0);
    EXPECT_EQ(capture::formatComparison(c), "PASS pencil_plot  9 values, exact match");
}

TEST(Compare, ToleranceBoundaries) {
    const double absTol = 1e-6, relTol = 1e-4;
    const double b = 2.0; // profile() row 2, column R
    const double limit = absTol + relTol * b;
    for (double factor : {0.999, 0.5, 1.0 - 1e-9}) {
        for (double sign : {1.0, -1.0}) {
            Table a = with(profile(), 1, 1, b + sign * factor * limit);
            capture::Comparison c = compareTables("s", profile(), a, absTol, relTol, "r_mm");
            EXPECT_TRUE(c.pass) << factor << " " << capture::formatComparison(c);
            EXPECT_LT(c.worstExcess, 1.0);
            EXPECT_EQ(c.where, "row 2 (r_mm=0.5), column R");
        }
    }
    for (double factor : {1.001, 1.0 + 1e-9, 10.0}) {
        for (double sign : {1.0, -1.0}) {
            Table a = with(profile(), 1, 1, b + sign * factor * limit);
            capture::Comparison c = compareTables("s", profile(), a, absTol, relTol, "r_mm");
            EXPECT_FALSE(c.pass) << factor;
            EXPECT_EQ(c.failing, 1u);
            EXPECT_GT(c.worstExcess, 1.0);
            EXPECT_EQ(c.where, "row 2 (r_mm=0.5), column R");
            EXPECT_NEAR(c.worstAbs, factor * limit, 1e-15);
            EXPECT_NEAR(c.worstRel, factor * limit / b, 1e-15);
        }
    }
}

TEST(Compare, AbsoluteToleranceMattersAtZero) {
    // At expected 0 only absTol gives room; a relative tolerance alone cannot excuse any diff.
    Table a = with(profile(), 0, 1, 0.999e-3);
    EXPECT_TRUE(compareTables("s", profile(), a, 1e-3, 0).pass);
    a = with(profile(), 0, 1, 1.001e-3);
    EXPECT_FALSE(compareTables("s", profile(), a, 1e-3, 0).pass);
    a = with(profile(), 0, 1, 1e-300);
    capture::Comparison c = compareTables("s", profile(), a, 0, 0.5);
    EXPECT_FALSE(c.pass);
    EXPECT_TRUE(std::isinf(c.worstRel));
}

TEST(Compare, ExactToleranceFailsOnOneUlp) {
    Table a = with(profile(), 2, 2, std::nextafter(1e-9, 1.0));
    capture::Comparison c = compareTables("s", profile(), a, 0, 0);
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.where, "row 3, column G");
}

TEST(Compare, WorstIsByExcessNotByAbsoluteDifference) {
    Table a = profile();
    a.rows[1][1] = 2.0 + 1e-5; // large abs diff, but relative to 2.0 it is small
    a.rows[2][2] = 1e-9 * 1.5; // tiny abs diff, 50% relative
    capture::Comparison c = compareTables("s", profile(), a, 0, 1e-3, "r_mm");
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.failing, 1u);
    EXPECT_EQ(c.where, "row 3 (r_mm=1), column G");
    EXPECT_NEAR(c.worstAbs, 1e-5, 1e-12);
    std::string line = capture::formatComparison(c);
    EXPECT_EQ(line.rfind("FAIL s  1 of 9 values out of tolerance; worst at row 3 (r_mm=1), "
                         "column G: expected 1.0000000000000001e-09, got ",
                         0),
              0u)
        << line;
    EXPECT_NE(line.find("[absTol 0, relTol 0.001]"), std::string::npos) << line;
}

TEST(Compare, NanAndInfinity) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    Table e = with(profile(), 1, 2, nan);
    EXPECT_TRUE(compareTables("s", e, e, 0, 0).pass); // NaN in both = equal

    capture::Comparison c = compareTables("s", e, profile(), 1, 1, "r_mm"); // NaN vs number
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.where, "row 2 (r_mm=0.5), column G");
    EXPECT_NE(capture::formatComparison(c).find("expected nan, got -3"), std::string::npos)
        << capture::formatComparison(c);

    c = compareTables("s", profile(), e, 1, 1); // number vs NaN
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.where, "row 2, column G");

    Table i = with(profile(), 0, 2, inf);
    EXPECT_TRUE(compareTables("s", i, i, 0, 0).pass);
    EXPECT_FALSE(compareTables("s", i, with(profile(), 0, 2, -inf), 1e300, 1).pass);
    EXPECT_FALSE(compareTables("s", i, profile(), 1e300, 1).pass);
    EXPECT_FALSE(compareTables("s", profile(), i, 1e300, 1).pass);
}

TEST(Compare, ShapeAndNameMismatches) {
    Table shorter = profile();
    shorter.rows.pop_back();
    capture::Comparison c = compareTables("pencil_plot", profile(), shorter, 1, 1);
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.message, "row count differs: expected 3, got 2");
    EXPECT_EQ(capture::formatComparison(c),
              "FAIL pencil_plot  row count differs: expected 3, got 2");

    Table narrow{{}, {"r_mm", "R"}, {{0, 0}, {0.5, 2}, {1, 0.25}}};
    c = compareTables("s", profile(), narrow, 1, 1);
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.message, "column count differs: expected 3 (r_mm, R, G), got 2 (r_mm, R)");

    Table renamed = profile();
    renamed.columns[2] = "B";
    c = compareTables("s", profile(), renamed, 1, 1);
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.message, "column 3 name differs: expected 'G', got 'B'");

    c = compareTables("s", profile(), profile(), 1, 1, "radius");
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.message, "key column 'radius' not found");

    Table ragged = profile();
    ragged.rows[1].pop_back();
    EXPECT_FALSE(compareTables("s", profile(), ragged, 1, 1).pass);

    c = compareTables("s", profile(), profile(), -1, 0);
    EXPECT_FALSE(c.pass);
    EXPECT_NE(c.message.find("invalid tolerance"), std::string::npos);
    EXPECT_FALSE(compareTables("s", profile(), profile(), 0, std::nan("")).pass);
}

TEST(Compare, PassLineNamesWorstValue) {
    Table a = with(profile(), 1, 1, 2.0 * (1 + 3.1e-7));
    capture::Comparison c = compareTables("pencil_plot", profile(), a, 0, 1e-5, "r_mm");
    EXPECT_TRUE(c.pass);
    EXPECT_EQ(capture::formatComparison(c),
              "PASS pencil_plot  9 values, worst diff 6.2e-07 (limit 2e-05, 3.1% of tolerance) "
              "at row 2 (r_mm=0.5), column R");
}

TEST(Compare, EmptyTables) {
    Table e{{}, {"x"}, {}};
    capture::Comparison c = compareTables("s", e, e, 0, 0);
    EXPECT_TRUE(c.pass);
    EXPECT_EQ(capture::formatComparison(c), "PASS s  no values to compare (empty tables)");
}

// ---- Monte Carlo tables: per-value z-test with a Bonferroni limit -----------------------
namespace {
capture::Table mcTable(double shift, double stderrScale) {
    capture::Table t;
    t.columns = {"r_mm", "Rd", "Rd_stderr"};
    for (int i = 0; i < 50; ++i)
        t.rows.push_back({0.1 * i, 1.0 / (1 + i) + shift, 0.01 * stderrScale});
    return t;
}
} // namespace

TEST(CompareStat, IdenticalPassesAndShiftsAreJudgedByZ) {
    auto a = mcTable(0, 1);
    auto same = capture::compareStatTables("ref", a, a, 1e-3, "r_mm");
    EXPECT_TRUE(same.pass) << capture::formatComparison(same);
    EXPECT_EQ(same.values, 100u); // 50 r_mm (exact) + 50 Rd (z-test)
    // limit for m = 50 values at family alpha 1e-3: Φ⁻¹(1 − 1e-5) = 4.2649
    const double zLim = core::normalUpperQuantile(1e-3 / 100);
    const double se = 0.01 * std::sqrt(2.0);
    auto below = capture::compareStatTables("ref", a, mcTable(0.99 * zLim * se, 1), 1e-3);
    EXPECT_TRUE(below.pass) << capture::formatComparison(below);
    auto above = capture::compareStatTables("ref", a, mcTable(1.01 * zLim * se, 1), 1e-3, "r_mm");
    EXPECT_FALSE(above.pass);
    EXPECT_EQ(above.failing, 50u);
    EXPECT_NE(capture::formatComparison(above).find("FAIL ref"), std::string::npos);
    EXPECT_NE(capture::formatComparison(above).find("column Rd"), std::string::npos);
}

TEST(CompareStat, DeterministicColumnsMustMatchExactly) {
    auto a = mcTable(0, 1), b = mcTable(0, 1);
    b.rows[3][0] += 1e-12; // r_mm has no stderr companion
    auto c = capture::compareStatTables("ref", a, b, 1e-3);
    EXPECT_FALSE(c.pass);
    EXPECT_NE(c.where.find("column r_mm"), std::string::npos);
    auto bad = capture::compareStatTables("ref", a, a, 1.5);
    EXPECT_FALSE(bad.pass);
    EXPECT_NE(bad.message.find("alpha"), std::string::npos);
}

// Per-value conditioning (the replaying driver's allowance for a model that cancels): each value
// gets its own extra room, which can still fail; a table of another shape or a negative or
// non-finite allowance is refused, and the report says the allowance was there.
TEST(Compare, ConditioningAddsItsOwnRoomPerValue) {
    const double relTol = 1e-5;
    Table cond{{}, profile().columns, {{0, 0, 0}, {0, 1e-3, 0}, {0, 0, 0}}};
    const double limit = relTol * 2.0 + 1e-3; // row 2, column R (b = 2)
    Table a = with(profile(), 1, 1, 2.0 + 0.99 * limit);
    capture::Comparison c = compareTables("s", profile(), a, 0, relTol, "r_mm", &cond, "spread");
    EXPECT_TRUE(c.pass) << capture::formatComparison(c);
    EXPECT_NEAR(c.limit, limit, 1e-15);
    EXPECT_NE(capture::formatComparison(c).find("plus spread"), std::string::npos)
        << capture::formatComparison(c);
    // beyond it, and the same difference on a value without room
    a = with(profile(), 1, 1, 2.0 + 1.01 * limit);
    EXPECT_FALSE(compareTables("s", profile(), a, 0, relTol, "r_mm", &cond, "spread").pass);
    a = with(profile(), 1, 2, -3.0 + 0.5 * limit);
    c = compareTables("s", profile(), a, 0, relTol, "r_mm", &cond, "spread");
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.where, "row 2 (r_mm=0.5), column G");

    Table shorter = cond;
    shorter.rows.pop_back();
    c = compareTables("s", profile(), profile(), 0, relTol, "", &shorter, "spread");
    EXPECT_FALSE(c.pass);
    EXPECT_NE(c.message.find("per-value tolerances do not fit"), std::string::npos) << c.message;
    for (double bad : {-1e-9, std::numeric_limits<double>::quiet_NaN(), double(INFINITY)}) {
        Table b = cond;
        b.rows[2][2] = bad;
        c = compareTables("s", profile(), profile(), 0, relTol, "", &b, "spread");
        EXPECT_FALSE(c.pass) << bad;
        EXPECT_NE(c.message.find("invalid per-value tolerance"), std::string::npos) << c.message;
    }
}
