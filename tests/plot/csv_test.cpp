// plot: CSV export (wide / long format, exact round trip, errors naming the path).
#include "plot/plot.h"

#include "core/core.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <unistd.h>

namespace {

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);)
        out.push_back(l);
    return out;
}

std::vector<std::string> cells(const std::string& line) {
    std::vector<std::string> out;
    std::string cur;
    for (char c : line) {
        if (c == ',') {
            out.push_back(cur);
            cur.clear();
        } else {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

plot::Series series(std::string label, std::vector<double> x, std::vector<double> y) {
    plot::Series s;
    s.label = std::move(label);
    s.x = std::move(x);
    s.y = std::move(y);
    return s;
}

TEST(PlotCsv, WideFormatRoundTripsExactly) {
    std::vector<double> x, y1, y2;
    for (int i = 0; i < 64; ++i) {
        x.push_back(i * 0.1 + 1.0 / 3.0);
        y1.push_back(std::exp(-i * 0.37) / 7.0);
        y2.push_back(std::nextafter(1.0 / (i + 1.0), 2.0) * 1e-250);
    }
    y1[5] = 1e-320; // subnormal
    y2[7] = -0.0;
    plot::Series b = series("dipole", x, y2);
    b.bandLo = y2;
    b.bandHi = y1;
    const std::vector<plot::Series> s = {series("R(r)", x, y1), b};
    const std::vector<std::string> l = lines(plot::toCsv(s, "r [mm]"));
    ASSERT_EQ(l.size(), 65u);
    EXPECT_EQ(l[0], "r [mm],R(r),dipole,dipole lo,dipole hi");
    for (int i = 0; i < 64; ++i) {
        const std::vector<std::string> c = cells(l[i + 1]);
        ASSERT_EQ(c.size(), 5u);
        EXPECT_EQ(std::strtod(c[0].c_str(), nullptr), x[i]) << c[0];
        EXPECT_EQ(std::strtod(c[1].c_str(), nullptr), y1[i]) << c[1];
        EXPECT_EQ(std::strtod(c[2].c_str(), nullptr), y2[i]) << c[2];
        EXPECT_EQ(std::strtod(c[3].c_str(), nullptr), y2[i]);
        EXPECT_EQ(std::strtod(c[4].c_str(), nullptr), y1[i]);
    }
    EXPECT_EQ(cells(l[8])[2], "-0");
}

TEST(PlotCsv, LongFormatForDifferentGrids) {
    plot::Series a = series("a", {0, 0.5}, {1, 2});
    plot::Series b = series("with, comma \"q\"", {0, 1, 2}, {3, NAN, INFINITY});
    b.bandLo = {2, 2, 2};
    b.bandHi = {4, 4, 4};
    const std::vector<std::string> l = lines(plot::toCsv({a, b}, "r"));
    ASSERT_EQ(l.size(), 6u);
    EXPECT_EQ(l[0], "label,r,y,lo,hi");
    EXPECT_EQ(l[1], "a,0,1,,");
    EXPECT_EQ(l[2], "a,0.5,2,,");
    EXPECT_EQ(l[3], "\"with, comma \"\"q\"\"\",0,3,2,4");
    EXPECT_EQ(l[4], "\"with, comma \"\"q\"\"\",1,nan,2,4");
    EXPECT_EQ(l[5], "\"with, comma \"\"q\"\"\",2,inf,2,4");
}

TEST(PlotCsv, EmptyAndUnlabelled) {
    EXPECT_EQ(plot::toCsv({}, "r"), "r\n");
    EXPECT_EQ(plot::toCsv({series("", {1}, {2})}, "r"), "r,series 1\n1,2\n");
}

TEST(PlotCsv, WriteCsvWritesFile) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("plot_csv_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::filesystem::path p = dir / "profile.csv";
    const std::vector<plot::Series> s = {series("a", {0, 1}, {0.1, 0.2})};
    plot::writeCsv(p, s, "r");
    EXPECT_EQ(core::readFile(p), plot::toCsv(s, "r"));
    std::filesystem::remove_all(dir);
}

TEST(PlotCsv, WriteCsvUnwritableThrowsNamingPath) {
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("plot_csv_file_" + std::to_string(::getpid()));
    core::writeFile(file, "x");
    for (const std::filesystem::path& bad :
         {std::filesystem::path("/proc/nonexistent/x.csv"), file / "under_a_file.csv"}) {
        try {
            plot::writeCsv(bad, {series("a", {0}, {1})}, "r");
            ADD_FAILURE() << "no error for " << bad;
        } catch (const core::Error& e) {
            EXPECT_EQ(e.file(), bad.string());
            EXPECT_NE(std::string(e.what()).find(bad.string()), std::string::npos) << e.what();
            EXPECT_EQ(e.line(), 0);
        }
    }
    std::filesystem::remove(file);
}

} // namespace
