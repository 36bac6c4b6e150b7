// capture CSV tables: bit-exact round trip, errors with file and line, stage files.
#include "capture/capture.h"
#include "core/core.h"
#include "temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>

namespace fs = std::filesystem;
using capture_test::TempDir;

namespace {

uint64_t bits(double v) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

core::Error parseError(const std::string& text) {
    try {
        capture::parseCsv(text, "t.csv");
    } catch (const core::Error& e) {
        return e;
    }
    ADD_FAILURE() << "expected an error for:\n" << text;
    return core::Error("", 0, "");
}

} // namespace

TEST(Table, RoundTripIsBitExactForDoubles) {
    using L = std::numeric_limits<double>;
    std::vector<double> values = {0.1,           1.0 / 3.0,     -0.0,         0.0,
                                  L::max(),      L::lowest(),   L::min(),     L::denorm_min(),
                                  L::epsilon(),  1e300,         -1.2345e-300, 123456789012345678.0,
                                  L::infinity(), -L::infinity()};
    std::mt19937_64 rng(12345);
    while (values.size() < 3000) { // random bit patterns cover every exponent and mantissa
        uint64_t b = rng();
        double v;
        std::memcpy(&v, &b, sizeof v);
        if (!std::isnan(v)) values.push_back(v);
    }
    capture::Table t;
    t.comments = {"pencil-beam profile", " leading space kept", ""};
    t.columns = {"a", "b", "c"};
    for (size_t i = 0; i + 2 < values.size(); i += 3)
        t.rows.push_back({values[i], values[i + 1], values[i + 2]});
    t.rows.push_back({std::nan(""), -std::nan(""), 1.0});

    TempDir tmp;
    capture::writeCsv(tmp.path() / "t.csv", t);
    capture::Table back = capture::readCsv(tmp.path() / "t.csv");
    EXPECT_EQ(back.comments, t.comments);
    EXPECT_EQ(back.columns, t.columns);
    ASSERT_EQ(back.rows.size(), t.rows.size());
    for (size_t r = 0; r + 1 < t.rows.size(); ++r)
        for (size_t c = 0; c < 3; ++c)
            ASSERT_EQ(bits(back.rows[r][c]), bits(t.rows[r][c]))
                << "row " << r << " col " << c << ": " << t.rows[r][c];
    EXPECT_TRUE(std::isnan(back.rows.back()[0]));
    EXPECT_TRUE(std::isnan(back.rows.back()[1]));
    EXPECT_EQ(capture::formatCsv(back), capture::formatCsv(t)); // stable text
}

TEST(Table, FormatIsReadable) {
    capture::Table t{{"note"}, {"r_mm", "R"}, {{0.5, 0.1}, {1, -2.5e-8}}};
    EXPECT_EQ(capture::formatCsv(t), "# note\nr_mm,R\n0.5,0.1\n1,-2.5e-08\n");
    EXPECT_EQ(t.columnIndex("R"), 1);
    EXPECT_EQ(t.columnIndex("G"), -1);
}

TEST(Table, TolerantReading) {
    capture::Table t =
        capture::parseCsv("# c\r\n r_mm , R\r\n+1, 2 \r\n-inf,nan\r\n\r\n\n", "t.csv");
    EXPECT_EQ(t.columns, (std::vector<std::string>{"r_mm", "R"}));
    ASSERT_EQ(t.rows.size(), 2u);
    EXPECT_EQ(t.rows[0], (std::vector<double>{1, 2}));
    EXPECT_TRUE(std::isinf(t.rows[1][0]) && t.rows[1][0] < 0);
    EXPECT_TRUE(std::isnan(t.rows[1][1]));
    EXPECT_TRUE(capture::parseCsv("x\n", "t.csv").rows.empty());
}

TEST(Table, ErrorsNameFileAndLine) {
    core::Error e = parseError("# comment\nr_mm,R,G\n1,2,3\n4,5\n");
    EXPECT_EQ(e.file(), "t.csv");
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.message(), "row has 2 values, header has 3 columns");
    e = parseError("r_mm,R\n1,2\n3,abc\n");
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.message(), "column 'R': 'abc' is not a number");
    e = parseError("r_mm,R\n1,2x\n");
    EXPECT_EQ(e.line(), 2);
    e = parseError("r_mm,R\n1,\n");
    EXPECT_EQ(e.message(), "column 'R': '' is not a number");
    e = parseError("r_mm,R\n1,2\n\n3,4\n");
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.message(), "blank line between rows");
    e = parseError("a,b,a\n");
    EXPECT_EQ(e.line(), 1);
    EXPECT_NE(e.message().find("appears twice"), std::string::npos);
    e = parseError("a,,b\n");
    EXPECT_NE(e.message().find("empty column name"), std::string::npos);
    e = parseError("# only a comment\n");
    EXPECT_NE(e.message().find("no header row"), std::string::npos);
    e = parseError("");
    EXPECT_NE(e.message().find("no header row"), std::string::npos);
    e = parseError("a\n1\n# late comment\n");
    EXPECT_EQ(e.line(), 3);

    TempDir tmp;
    try {
        capture::readCsv(tmp.path() / "missing.csv");
        FAIL();
    } catch (const core::Error& err) {
        EXPECT_EQ(err.file(), (tmp.path() / "missing.csv").string());
    }
}

TEST(Table, MalformedTablesAreNotWritten) {
    TempDir tmp;
    fs::path p = tmp.path() / "bad.csv";
    auto expectWriteError = [&](const capture::Table& t, const std::string& fragment) {
        try {
            capture::writeCsv(p, t);
            ADD_FAILURE() << "expected an error mentioning " << fragment;
        } catch (const core::Error& e) {
            EXPECT_EQ(e.file(), p.string());
            EXPECT_NE(e.message().find(fragment), std::string::npos) << e.what();
        }
        EXPECT_FALSE(fs::exists(p));
    };
    expectWriteError({{}, {}, {}}, "no columns");
    expectWriteError({{}, {"a,b"}, {}}, "contains ','");
    expectWriteError({{}, {"a", "a"}, {}}, "appears twice");
    expectWriteError({{}, {"#a"}, {}}, "starts with '#'");
    expectWriteError({{}, {" a"}, {}}, "blanks");
    expectWriteError({{"two\nlines"}, {"a"}, {}}, "line break");
    expectWriteError({{}, {"a", "b"}, {{1, 2}, {3}}}, "row 2 has 1 values");
}

TEST(Table, UnwritablePathThrowsNamingIt) {
    TempDir tmp;
    std::ofstream(tmp.path() / "plain_file") << "x";
    fs::path p = tmp.path() / "plain_file" / "t.csv";
    try {
        capture::writeCsv(p, {{}, {"a"}, {{1}}});
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), p.string());
    }
    try {
        capture::writeCsvStage(tmp.path() / "plain_file", "s", "t.csv", {{}, {"a"}, {{1}}}, 0, 0,
                               "");
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("plain_file"), std::string::npos) << e.what();
    }
}

TEST(Table, WriteAndCompareStage) {
    TempDir tmp;
    capture::Table t{{"recorded"}, {"r_mm", "R"}, {{0.5, 0.25}, {1.0, 0.125}}};
    capture::StageOutput o =
        capture::writeCsvStage(tmp.path(), "pencil_plot", "sub/pp.csv", t, 0, 1e-6, "CPU double");
    EXPECT_EQ(o.stage, "pencil_plot");
    EXPECT_EQ(o.file, "sub/pp.csv");
    EXPECT_EQ(o.kind, "csv");
    EXPECT_EQ(o.relTol, 1e-6);
    EXPECT_EQ(o.hash, capture::hashFile(tmp.path() / "sub" / "pp.csv"));

    EXPECT_TRUE(capture::compareCsvStage(o, tmp.path(), t).pass);
    capture::Table changed = t;
    changed.rows[1][1] *= 1 + 2e-6;
    capture::Comparison c = capture::compareCsvStage(o, tmp.path(), changed, "r_mm");
    EXPECT_FALSE(c.pass);
    EXPECT_EQ(c.where, "row 2 (r_mm=1), column R");

    o.file = "gone.csv";
    c = capture::compareCsvStage(o, tmp.path(), t);
    EXPECT_FALSE(c.pass);
    EXPECT_NE(c.message.find("cannot read the recorded output"), std::string::npos);
    EXPECT_THROW(capture::writeCsvStage(tmp.path(), "s", "../x.csv", t, 0, 0, ""), core::Error);
    EXPECT_THROW(capture::writeCsvStage(tmp.path(), "s", "x.csv", t, -1, 0, ""), core::Error);
}
