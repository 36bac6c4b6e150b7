// capture comparison: per-value tolerance test |a-b| <= absTol + relTol*|b| (b = expected), plus
// a per-value conditioning term where the replaying program supplies one, reporting the worst value
// (by excess over its limit) with its location.
#include "capture.h"
#include "core/statistics.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>

namespace capture {

namespace {

std::string columnList(const std::vector<std::string>& columns) {
    std::string out;
    for (const std::string& c : columns)
        out += (out.empty() ? "" : ", ") + c;
    return out;
}

// Empty when every row has one value per column.
std::string raggedProblem(const char* which, const Table& t) {
    for (size_t r = 0; r < t.rows.size(); ++r)
        if (t.rows[r].size() != t.columns.size())
            return std::string(which) + " row " + std::to_string(r + 1) + " has " +
                   std::to_string(t.rows[r].size()) + " values for " +
                   std::to_string(t.columns.size()) + " columns";
    return "";
}

// Shape, names and tolerance problems that make a value-by-value comparison meaningless.
std::string structuralProblem(const Table& expected, const Table& actual, double absTol,
                              double relTol, const std::string& keyColumn) {
    if (!(absTol >= 0) || !(relTol >= 0) || !std::isfinite(absTol) || !std::isfinite(relTol))
        return "invalid tolerance: absTol " + core::formatNumber(absTol, 6) + ", relTol " +
               core::formatNumber(relTol, 6);
    if (expected.columns.size() != actual.columns.size())
        return "column count differs: expected " + std::to_string(expected.columns.size()) + " (" +
               columnList(expected.columns) + "), got " + std::to_string(actual.columns.size()) +
               " (" + columnList(actual.columns) + ")";
    for (size_t c = 0; c < expected.columns.size(); ++c)
        if (expected.columns[c] != actual.columns[c])
            return "column " + std::to_string(c + 1) + " name differs: expected '" +
                   expected.columns[c] + "', got '" + actual.columns[c] + "'";
    if (expected.rows.size() != actual.rows.size())
        return "row count differs: expected " + std::to_string(expected.rows.size()) + ", got " +
               std::to_string(actual.rows.size());
    if (!keyColumn.empty() && expected.columnIndex(keyColumn) < 0)
        return "key column '" + keyColumn + "' not found";
    std::string ragged = raggedProblem("expected", expected);
    return ragged.empty() ? raggedProblem("actual", actual) : ragged;
}

} // namespace

Comparison compareTables(const std::string& stage, const Table& expected, const Table& actual,
                         double absTol, double relTol, const std::string& keyColumn,
                         const Table* conditioning, const std::string& conditioningNote) {
    Comparison c;
    c.stage = stage;
    c.absTol = absTol;
    c.relTol = relTol;
    c.message = structuralProblem(expected, actual, absTol, relTol, keyColumn);
    if (!c.message.empty()) return c;
    if (conditioning) {
        c.conditioningNote = conditioningNote;
        const std::string shape = structuralProblem(actual, *conditioning, 0, 0, "");
        if (!shape.empty()) {
            c.message = "the per-value tolerances do not fit the table: " + shape;
            return c;
        }
        for (const auto& row : conditioning->rows)
            for (double t : row)
                if (!(t >= 0) || !std::isfinite(t)) {
                    c.message = "invalid per-value tolerance " + core::formatNumber(t, 6);
                    return c;
                }
    }

    const int key = keyColumn.empty() ? -1 : expected.columnIndex(keyColumn);
    bool worstFails = false;
    for (size_t r = 0; r < expected.rows.size(); ++r) {
        for (size_t col = 0; col < expected.columns.size(); ++col) {
            const double b = expected.rows[r][col];
            const double a = actual.rows[r][col];
            const double limit = std::isfinite(b)
                                     ? absTol + relTol * std::fabs(b) +
                                           (conditioning ? conditioning->rows[r][col] : 0)
                                     : 0.0;
            double diff = 0, excess = 0;
            bool ok = true;
            if ((std::isnan(a) && std::isnan(b)) || a == b) {
                ok = true; // includes NaN == NaN and equal infinities
            } else if (!std::isfinite(a) || !std::isfinite(b)) {
                ok = false;
                diff = std::fabs(a - b);
                excess = INFINITY;
            } else {
                diff = std::fabs(a - b);
                ok = diff <= limit;
                excess = limit > 0 ? diff / limit : INFINITY;
                c.worstAbs = std::max(c.worstAbs, diff);
                c.worstRel = std::max(c.worstRel, b != 0 ? diff / std::fabs(b) : INFINITY);
            }
            ++c.values;
            if (!ok) ++c.failing;
            const bool worse =
                (!ok && !worstFails) || ((!ok) == worstFails && excess > c.worstExcess);
            if (!worse) continue;
            worstFails = !ok;
            c.worstExcess = excess;
            c.expected = b;
            c.actual = a;
            c.diff = diff;
            c.limit = limit;
            c.where = "row " + std::to_string(r + 1);
            if (key >= 0)
                c.where +=
                    " (" + keyColumn + "=" + core::formatNumber(expected.rows[r][key], 6) + ")";
            c.where += ", column " + expected.columns[col];
        }
    }
    c.pass = c.failing == 0;
    return c;
}

Comparison compareStatTables(const std::string& stage, const Table& expected, const Table& actual,
                             double alpha, const std::string& keyColumn) {
    Comparison c;
    c.stage = stage;
    c.statistical = true;
    c.alpha = alpha;
    if (!(alpha > 0 && alpha < 1)) {
        c.message = "invalid alpha " + core::formatNumber(alpha, 6) + " (must lie in (0, 1))";
        return c;
    }
    c.message = structuralProblem(expected, actual, 0, 0, keyColumn);
    if (!c.message.empty()) return c;
    const size_t ncol = expected.columns.size();
    std::vector<int> companion(ncol, -1);
    std::vector<bool> isStderr(ncol, false);
    size_t m = 0;
    for (size_t col = 0; col < ncol; ++col) {
        int se = expected.columnIndex(expected.columns[col] + "_stderr");
        if (se >= 0) {
            companion[col] = se;
            isStderr[size_t(se)] = true;
            m += expected.rows.size();
        }
    }
    const double zLimit = core::normalUpperQuantile(alpha / (2.0 * double(std::max<size_t>(m, 1))));
    c.limit = zLimit;
    const int key = keyColumn.empty() ? -1 : expected.columnIndex(keyColumn);
    bool worstFails = false;
    for (size_t r = 0; r < expected.rows.size(); ++r) {
        for (size_t col = 0; col < ncol; ++col) {
            if (isStderr[col]) continue; // judged with its value column
            const double b = expected.rows[r][col], a = actual.rows[r][col];
            double z = 0;
            bool ok = (std::isnan(a) && std::isnan(b)) || a == b;
            if (!ok && companion[col] >= 0) {
                const double sb = expected.rows[r][size_t(companion[col])];
                const double sa = actual.rows[r][size_t(companion[col])];
                const double se = std::sqrt(sa * sa + sb * sb);
                z = se > 0 && std::isfinite(se) ? std::fabs(a - b) / se : INFINITY;
                ok = z <= zLimit;
            } else if (!ok) {
                z = INFINITY; // deterministic column: must match exactly
            }
            ++c.values;
            if (!ok) ++c.failing;
            const double excess = z / zLimit;
            const bool worse =
                (!ok && !worstFails) || ((!ok) == worstFails && excess > c.worstExcess);
            if (!worse || (ok && z == 0)) continue;
            worstFails = !ok;
            c.worstExcess = excess;
            c.expected = b;
            c.actual = a;
            c.diff = z;
            c.where = "row " + std::to_string(r + 1);
            if (key >= 0)
                c.where +=
                    " (" + keyColumn + "=" + core::formatNumber(expected.rows[r][key], 6) + ")";
            c.where += ", column " + expected.columns[col];
        }
    }
    c.pass = c.failing == 0;
    return c;
}

namespace {
std::string formatComparisonBody(const Comparison& c);
} // namespace

std::string formatComparison(const Comparison& c) {
    std::string out = formatComparisonBody(c);
    if (!c.artifacts.empty()) out += "\n     " + c.artifacts;
    return out;
}

namespace {
std::string formatComparisonBody(const Comparison& c) {
    std::string out = std::string(c.pass ? "PASS " : "FAIL ") + c.stage + "  ";
    if (!c.message.empty()) return out + c.message;
    if (c.statistical) {
        const std::string values = std::to_string(c.values) + " values";
        const std::string rule = "z-test, Bonferroni |z| <= " + core::formatNumber(c.limit, 3) +
                                 " for family alpha " + core::formatNumber(c.alpha, 6);
        if (c.where.empty()) return out + values + ", identical [" + rule + "]";
        if (c.pass)
            return out + values + ", worst |z| " + core::formatNumber(c.diff, 3) + " at " +
                   c.where + " [" + rule + "]";
        return out + std::to_string(c.failing) + " of " + values + " fail; worst |z| " +
               core::formatNumber(c.diff, 3) + " at " + c.where + ": expected " +
               core::formatNumber(c.expected, 9) + ", got " + core::formatNumber(c.actual, 9) +
               " [" + rule + "]";
    }
    const std::string values = std::to_string(c.values) + (c.values == 1 ? " value" : " values");
    if (c.values == 0) return out + "no values to compare (empty tables)";
    if (c.where.empty()) return out + values + ", exact match";
    std::string tol =
        "absTol " + core::formatNumber(c.absTol, 6) + ", relTol " + core::formatNumber(c.relTol, 6);
    if (!c.conditioningNote.empty()) tol += ", plus " + c.conditioningNote;
    if (c.pass)
        return out + values + ", worst diff " + core::formatNumber(c.diff, 3) + " (limit " +
               core::formatNumber(c.limit, 3) + ", " + core::formatNumber(100 * c.worstExcess, 3) +
               "% of tolerance) at " + c.where +
               (c.conditioningNote.empty() ? "" : " [" + tol + "]");
    out += std::to_string(c.failing) + " of " + values + " out of tolerance; worst at " + c.where +
           ": expected " + core::formatNumber(c.expected, 17) + ", got " +
           core::formatNumber(c.actual, 17);
    if (std::isfinite(c.expected) && std::isfinite(c.actual))
        out += ", diff " + core::formatNumber(c.diff, 3) + " > limit " +
               core::formatNumber(c.limit, 3) + " (" + core::formatNumber(c.worstExcess, 3) +
               "x tolerance)";
    return out + " [" + tol + "]";
}
} // namespace

} // namespace capture
