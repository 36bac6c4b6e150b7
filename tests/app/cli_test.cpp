// End-to-end tests of the bssrdf-workbench command line: each test runs the real executable
// (BW_EXE) with --root BW_SOURCE_ROOT in a fresh temporary working folder, captures stdout and
// stderr together plus the exit status, and checks outputs (CSV, PNG, printed numbers) and
// that every rejected input fails with a message naming the offending argument or file.
#include "../support/cli_fixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {
namespace fs = std::filesystem;
using namespace clitest;

// ---- helpers ------------------------------------------------------------------------------

std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    std::stringstream ss(text);
    std::string line;
    while (std::getline(ss, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        lines.push_back(line);
    }
    return lines;
}

bool contains(const std::string& hay, const std::string& needle) {
    return hay.find(needle) != std::string::npos;
}

std::vector<std::string> splitOn(const std::string& s, char sep) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, sep))
        out.push_back(item);
    return out;
}

double toDouble(const std::string& s, bool& ok) {
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(s.c_str(), &end);
    ok = !s.empty() && end == s.c_str() + s.size();
    return v;
}

// A parsed profile CSV: '#' header lines, the column header row, then r_mm,R,G,B rows.
struct ProfileCsv {
    std::vector<std::string> comments;
    std::string header;
    std::vector<std::array<double, 4>> rows;
    std::vector<std::string> problems; // malformed lines
};

ProfileCsv parseProfile(const std::string& text) {
    ProfileCsv csv;
    bool inData = false;
    for (const auto& line : splitLines(text)) {
        if (!inData) {
            if (!line.empty() && line[0] == '#') {
                csv.comments.push_back(line);
                continue;
            }
            csv.header = line;
            inData = true;
            continue;
        }
        if (line.empty()) continue;
        auto cells = splitOn(line, ',');
        if (cells.size() != 4) {
            csv.problems.push_back("not 4 columns: " + line);
            continue;
        }
        std::array<double, 4> row{};
        for (int i = 0; i < 4; ++i) {
            bool ok = false;
            row[i] = toDouble(cells[i], ok);
            if (!ok) csv.problems.push_back("not a number: " + line);
        }
        csv.rows.push_back(row);
    }
    return csv;
}

std::string findComment(const ProfileCsv& csv, const std::string& prefix) {
    for (const auto& c : csv.comments)
        if (c.rfind(prefix, 0) == 0) return c;
    return {};
}

// "# key a b c ..." -> the numbers after the key.
std::vector<double> commentNumbers(const std::string& line, size_t skipWords) {
    std::stringstream ss(line);
    std::string w;
    for (size_t i = 0; i < skipWords && (ss >> w); ++i) {
    }
    std::vector<double> v;
    while (ss >> w) {
        bool ok = false;
        double d = toDouble(w, ok);
        if (!ok) break;
        v.push_back(d);
    }
    return v;
}

const std::string kDipole = "materials/dipole.bssrdf";
fs::path sourceRoot() {
    return fs::path(BW_SOURCE_ROOT);
}

class Cli : public CliFixture {};

// ---- profile ------------------------------------------------------------------------------

TEST_F(Cli, ProfilePresetWritesCsvWithHeaderAndDefaultSamples) {
    std::vector<std::string> args = {"profile", "--model", kDipole,     "--preset",
                                     "Marble",  "--out",   "marble.csv"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    fs::path csvPath = dir() / "marble.csv";
    ASSERT_TRUE(fs::exists(csvPath)) << describe(args, r);
    ProfileCsv csv = parseProfile(readText(csvPath));

    // Header: model path and the material actually used.
    EXPECT_TRUE(contains(findComment(csv, "# model "), "dipole.bssrdf"));
    std::string sa = findComment(csv, "# sigma_a ");
    std::string ss = findComment(csv, "# sigma_s ");
    ASSERT_FALSE(sa.empty()) << "no '# sigma_a' header line";
    ASSERT_FALSE(ss.empty()) << "no '# sigma_s' header line";
    EXPECT_FALSE(findComment(csv, "# g ").empty()) << "no '# g' header line";
    EXPECT_FALSE(findComment(csv, "# eta ").empty()) << "no '# eta' header line";
    // Marble (Jensen et al. 2001, materials/presets.json) with g = 0: sigma_s = sigma_s'.
    auto saV = commentNumbers(sa, 2), ssV = commentNumbers(ss, 2);
    ASSERT_EQ(saV.size(), 3u) << sa;
    ASSERT_EQ(ssV.size(), 3u) << ss;
    const double kSa[3] = {0.0021, 0.0041, 0.0071}, kSs[3] = {2.19, 2.62, 3.00};
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(saV[c], kSa[c], 1e-9) << sa;
        EXPECT_NEAR(ssV[c], kSs[c], 1e-9) << ss;
    }
    auto eta = commentNumbers(findComment(csv, "# eta "), 2);
    ASSERT_EQ(eta.size(), 1u);
    EXPECT_NEAR(eta[0], 1.3, 1e-12);
    auto g = commentNumbers(findComment(csv, "# g "), 2);
    ASSERT_EQ(g.size(), 1u);
    EXPECT_EQ(g[0], 0.0);

    EXPECT_EQ(csv.header, "r_mm,R,G,B");
    EXPECT_TRUE(csv.problems.empty()) << csv.problems.front();
    ASSERT_EQ(csv.rows.size(), 512u);
    EXPECT_EQ(csv.rows.front()[0], 0.0);
    for (size_t i = 0; i < csv.rows.size(); ++i) {
        const auto& row = csv.rows[i];
        for (int k = 0; k < 4; ++k)
            ASSERT_TRUE(std::isfinite(row[k])) << "row " << i;
        for (int k = 1; k < 4; ++k)
            EXPECT_GT(row[k], 0.0) << "row " << i << " column " << k;
        if (i > 0) {
            EXPECT_GT(row[0], csv.rows[i - 1][0]) << "r not increasing at row " << i;
        }
    }
    // A diffusion profile falls off with distance: the first value exceeds the last.
    for (int k = 1; k < 4; ++k)
        EXPECT_GT(csv.rows.front()[k], csv.rows.back()[k]);
}

TEST_F(Cli, ProfileExplicitCoefficientsSamplesAndRange) {
    std::vector<std::string> args = {
        "profile",   "--model", kDipole,  "--sigma-a", "0.01,0.02,0.03", "--sigma-s",   "1,1,1",
        "--samples", "600",     "--rmax", "10",        "--out",          "explicit.csv"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    ProfileCsv csv = parseProfile(readText(dir() / "explicit.csv"));
    EXPECT_EQ(csv.header, "r_mm,R,G,B");
    EXPECT_TRUE(csv.problems.empty()) << csv.problems.front();
    ASSERT_EQ(csv.rows.size(), 600u);
    EXPECT_EQ(csv.rows.front()[0], 0.0);
    EXPECT_NEAR(csv.rows.back()[0], 10.0, 1e-6);
    for (size_t i = 0; i < csv.rows.size(); ++i) {
        for (int k = 0; k < 4; ++k)
            ASSERT_TRUE(std::isfinite(csv.rows[i][k])) << "row " << i;
        for (int k = 1; k < 4; ++k)
            EXPECT_GT(csv.rows[i][k], 0.0) << "row " << i;
        if (i > 0) {
            EXPECT_GT(csv.rows[i][0], csv.rows[i - 1][0]) << "row " << i;
        }
    }
    auto saV = commentNumbers(findComment(csv, "# sigma_a "), 2);
    ASSERT_EQ(saV.size(), 3u);
    EXPECT_NEAR(saV[0], 0.01, 1e-12);
    EXPECT_NEAR(saV[1], 0.02, 1e-12);
    EXPECT_NEAR(saV[2], 0.03, 1e-12);
}

TEST_F(Cli, ProfileRejectsBadCoefficients) {
    const std::vector<std::string> base = {"profile", "--model", kDipole, "--out", "bad.csv"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = base;
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    expectFailure(with({"--sigma-a", "-1,0,0", "--sigma-s", "1,1,1"}), {"sigma_a"});
    expectFailure(with({"--sigma-a", "0,0,0", "--sigma-s", "0,1,1"}), {"sigma_s"});
    expectFailure(with({"--sigma-a", "nan,0,0", "--sigma-s", "1,1,1"}), {"sigma_a"});
    expectFailure(with({"--sigma-a", "inf,0,0", "--sigma-s", "1,1,1"}), {"sigma_a"});
    expectFailure(with({"--sigma-a", "0.1,0.1,0.1", "--sigma-s", "1,inf,1"}), {"sigma_s"});
    expectFailure(with({"--sigma-a", "0.1", "--sigma-s", "1", "--eta", "0"}), {"eta"});
    expectFailure(with({"--sigma-a", "0.1", "--sigma-s", "1", "--g", "1"}), {"g (mean cosine)"});
    // A preset gives σ′s, from which σs = σ′s/(1 − g): a bad g is named as such, not as the
    // infinite or negative σs it would make.
    expectFailure(with({"--preset", "Skin1", "--g", "1"}), {"g (mean cosine)", "got 1"});
    expectFailure(with({"--preset", "Skin1", "--g", "2"}), {"g (mean cosine)", "got 2"});
    expectFailure(with({"--sigma-a", "1,2", "--sigma-s", "1,1,1"}), {"--sigma-a"});
    expectFailure(with({"--sigma-a", "abc", "--sigma-s", "1,1,1"}), {"--sigma-a", "abc"});
    expectFailure(with({"--sigma-a", "0.1,0.1,0.1", "--sigma-s", "1,x,1"}), {"--sigma-s"});
    expectFailure(with({"--sigma-a", "0.1,0.1,0.1"}), {"--sigma-s"});
    expectFailure(with({"--preset", "Marble", "--sigma-a", "0.1,0.1,0.1"}), {"--preset"});
    EXPECT_FALSE(fs::exists(dir() / "bad.csv")) << "a rejected profile still wrote its CSV";
}

TEST_F(Cli, ProfileRejectsBadPresetModelAndOutput) {
    expectFailure({"profile", "--model", kDipole, "--preset", "NoSuchMaterial", "--out", "x.csv"},
                  {"preset", "NoSuchMaterial"});
    expectFailure(
        {"profile", "--model", "does/not/exist.bssrdf", "--preset", "Marble", "--out", "x.csv"},
        {"--model", "does/not/exist.bssrdf"});
    expectFailure(
        {"profile", "--model", kDipole, "--preset", "Marble", "--out", "/proc/nope/x.csv"},
        {"/proc/nope/x.csv"});
    expectFailure(
        {"profile", "--model", kDipole, "--preset", "Marble", "--samples", "1", "--out", "x.csv"},
        {"--samples"});
    expectFailure(
        {"profile", "--model", kDipole, "--preset", "Marble", "--rmax", "-2", "--out", "x.csv"},
        {"--rmax"});
    EXPECT_FALSE(fs::exists(dir() / "x.csv"));
}

// `gui --size WxH` chooses the window's size (fitted to the screen); a bad size is refused
// before anything starts.
TEST_F(Cli, GuiSizeIsCheckedBeforeAnythingStarts) {
    for (const char* bad : {"garbage", "100x100", "1600x", "9000x800"}) {
        const RunResult r = run({"gui", "--size", bad});
        EXPECT_EQ(r.code, 1) << bad << "\n" << r.output;
        EXPECT_TRUE(contains(r.output, "error: --size")) << r.output;
        EXPECT_FALSE(contains(r.output, "running the default capture")) << r.output;
    }
}

// A folder given as --model is one error naming its full path (the model library's own message
// came first, shortened, then the same again); a mistyped preset suggests the nearest name.
TEST_F(Cli, AFolderAsModelAndAMistypedPresetAreOneClearError) {
    const std::string folder = (fs::path(BW_SOURCE_ROOT) / "materials").string();
    RunResult r = run({"profile", "--model", folder, "--preset", "Marble", "--out", "x.csv"});
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_EQ(splitLines(r.output).size(), 1u) << r.output;
    EXPECT_TRUE(contains(r.output, "error: " + folder + ": --model: a folder")) << r.output;

    r = run({"profile", "--model", kDipole, "--preset", "Marbel", "--out", "x.csv"});
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_TRUE(
        contains(r.output,
                 "error: --preset: unknown preset 'Marbel' (did you mean 'Marble'? known: "))
        << r.output; // named by its argument
    EXPECT_TRUE(contains(r.output, "Skin1")) << r.output;
    r = run({"profile", "--model", kDipole, "--preset", "Quartz", "--out", "x.csv"});
    EXPECT_TRUE(contains(r.output, "unknown preset 'Quartz' (known: ")) << r.output;
    EXPECT_FALSE(fs::exists(dir() / "x.csv"));
}

// A GLSL error inside the shader section is reported against the user's file and line.
// A model whose profile is NaN near the origin and negative farther out: the CSV is written
// (saying so), the error names the model, the kinds, the radii and the channels, status 3.
TEST_F(Cli, ProfileWithNanOrNegativeValuesIsReportedWithTheRadii) {
    const fs::path bad = dir() / "bad_values.bssrdf";
    writeText(bad, "analytic radial no_wi no_wo\n"
                   "::begin shader\n"
                   "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                   "    float r = length(Xo - Xi);\n"
                   "    float nan = sqrt(-1.0 - r);\n"
                   "    return vec3(r < 1.0 ? nan : 1.0, r > 2.0 ? -1.0 : 1.0, 1.0);\n"
                   "}\n"
                   "::end shader\n");
    const std::vector<std::string> args = {"profile", "--model", bad.string(), "--preset",
                                           "Marble",  "--rmax",  "4",          "--samples",
                                           "401",     "--out",   "bad.csv"};
    RunResult r = run(args);
    EXPECT_EQ(r.code, 3) << describe(args, r);
    EXPECT_TRUE(contains(r.output, "error: ")) << r.output;
    EXPECT_TRUE(contains(r.output, "bad_values.bssrdf: R(r) is NaN at 100 of 401 radii (r 0 to "
                                   "0.99 mm, channel R)"))
        << r.output;
    EXPECT_TRUE(contains(r.output, "negative at 200 of 401 radii (r 2.01 to 4 mm, channel G)"))
        << r.output;
    const std::string csv = readText(dir() / "bad.csv");
    EXPECT_TRUE(contains(csv, "# invalid R(r) is NaN at 100 of 401 radii")) << csv;
}

// A model whose Bssrdf() runs for very long (a loop the driver cuts only after 65 535 heavy
// iterations on llvmpipe, about 5 s; never ending elsewhere): its first evaluation runs in a
// child process with the limit of $BSSRDF_WORKBENCH_PROBE_SECONDS, and the command stops with
// the file and the limit named instead of waiting.
TEST_F(Cli, ProfileOfAModelThatDoesNotFinishFailsWithinTheLimit) {
    const fs::path slow = dir() / "hanging.bssrdf";
    writeText(slow, "analytic radial no_wi no_wo\n"
                    "::begin shader\n"
                    "#define STEP x = sin(x * 1.37 + 0.11) + cos(x * 0.73);\n"
                    "#define STEP4 STEP STEP STEP STEP\n"
                    "#define STEP16 STEP4 STEP4 STEP4 STEP4\n"
                    "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                    "    float x = length(Xo - Xi);\n"
                    "    while (SigmaA.x >= 0.0) { STEP16 STEP16 STEP16 STEP16 }\n"
                    "    return vec3(x);\n"
                    "}\n"
                    "::end shader\n");
    ::setenv("BSSRDF_WORKBENCH_PROBE_SECONDS", "1", 1);
    ::setenv("BSSRDF_WORKBENCH_LOOP_BUDGET", "2147483648", 1); // the time limit acts first
    const std::vector<std::string> args = {"profile", "--model", slow.string(), "--preset",
                                           "Marble",  "--out",   "hang.csv"};
    RunResult r = run(args);
    ::unsetenv("BSSRDF_WORKBENCH_PROBE_SECONDS");
    ::unsetenv("BSSRDF_WORKBENCH_LOOP_BUDGET");
    EXPECT_EQ(r.code, 1) << describe(args, r);
    // at the loop's line (the 8th of the file), which the message names
    EXPECT_TRUE(contains(r.output, "hanging.bssrdf:8: Bssrdf() did not finish within 1 s"))
        << r.output;
    EXPECT_TRUE(contains(r.output, "a loop that does not end? [the loop at line 8 (while)]"))
        << r.output;
    EXPECT_FALSE(fs::exists(dir() / "hang.csv"));
}

// The same loop under the default loop budget (bssrdf/loop_budget.h), on any driver: the loop
// stops after the budget in the first evaluation, and the command fails naming the loop's line
// and the budget (the budget's message, not the time limit's: no waiting for it).
TEST_F(Cli, ProfileOfAModelWhoseLoopRunsAwayFailsAtTheLoopsLine) {
    const fs::path slow = dir() / "runaway.bssrdf";
    writeText(slow, "analytic radial no_wi no_wo\n"
                    "::begin shader\n"
                    "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                    "    float x = length(Xo - Xi);\n"
                    "    for (int i = 0; i < 1000000000; ++i) { x = sin(x * 1.37 + 0.11); }\n"
                    "    return vec3(x);\n"
                    "}\n"
                    "::end shader\n");
    const std::vector<std::string> args = {"profile", "--model", slow.string(), "--preset",
                                           "Marble",  "--out",   "runaway.csv"};
    RunResult r = run(args);
    EXPECT_EQ(r.code, 1) << describe(args, r);
    EXPECT_TRUE(contains(r.output, "runaway.bssrdf:5: the loop at line 5 ran past the loop "
                                   "budget of 16384 iterations per Bssrdf() call"))
        << r.output;
    EXPECT_FALSE(contains(r.output, "did not finish within")) << r.output;
    EXPECT_FALSE(fs::exists(dir() / "runaway.csv"));
}

TEST_F(Cli, ProfileReportsShaderErrorAtModelFileLine) {
    auto lines = splitLines(readText(sourceRoot() / kDipole));
    int begin = -1, end = -1;
    for (int i = 0; i < static_cast<int>(lines.size()); ++i) {
        if (lines[i].rfind("::begin shader", 0) == 0) begin = i;
        if (lines[i].rfind("::end shader", 0) == 0) end = i;
    }
    ASSERT_GE(begin, 0);
    ASSERT_GT(end, begin);
    // A statement line inside the function body: indented, a declaration ending with ';'.
    int target = -1;
    for (int i = begin + 1; i < end; ++i) {
        const auto& l = lines[i];
        if (l.size() > 4 && (l[0] == ' ' || l[0] == '\t') && contains(l, "vec3 ") &&
            l.back() == ';' && !contains(l, "return")) {
            target = i;
            break;
        }
    }
    ASSERT_GE(target, 0) << "no statement line found in the shader section of " << kDipole;
    lines[target] = "    vec3 Broken = ;";
    std::string text;
    for (const auto& l : lines)
        text += l + "\n";
    const fs::path broken = dir() / "broken.bssrdf";
    writeText(broken, text);
    const std::string where = broken.string() + ":" + std::to_string(target + 1);

    expectFailure({"profile", "--model", broken.string(), "--preset", "Marble", "--out", "x.csv"},
                  {where});
    expectFailure({"invert", "--model", broken.string(), "--rdr", "0.5,0.5,0.5", "--ld", "1,1,1"},
                  {where});
    EXPECT_FALSE(fs::exists(dir() / "x.csv"));
}

// ---- invert -------------------------------------------------------------------------------

// Classical dipole (materials/dipole.bssrdf): R_dr(alpha') of its diffuseReflectance section
// and l_d = 1/sigma_tr, evaluated in double precision to check the printed inversion.
struct Forward {
    double rdr, ld;
};
Forward dipoleForward(double sigmaA, double sigmaS, double eta) {
    double fdr = -1.44 / (eta * eta) + 0.71 / eta + 0.668 + 0.0636 * eta;
    double A = (1 + fdr) / (1 - fdr);
    double sigmaT = sigmaA + sigmaS; // g = 0
    double alpha = sigmaS / sigmaT;
    double T = std::sqrt(3 * (1 - alpha));
    double rdr = alpha * 0.5 * (1 + std::exp(-4.0 / 3.0 * A * T)) * std::exp(-T);
    double sigmaTr = std::sqrt(3 * sigmaA * sigmaT);
    return {rdr, 1 / sigmaTr};
}

TEST_F(Cli, InvertPrintsCoefficientsThatReproduceTheInputs) {
    std::vector<std::string> args = {"invert",      "--model", kDipole, "--rdr",
                                     "0.5,0.6,0.7", "--ld",    "1,2,3"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    auto lines = splitLines(r.output);
    lines.erase(std::remove(lines.begin(), lines.end(), std::string()), lines.end());
    ASSERT_EQ(lines.size(), 2u) << describe(args, r);
    double values[2][3];
    const char* names[2] = {"sigma_a", "sigma_s"};
    for (int k = 0; k < 2; ++k) {
        std::stringstream ss(lines[k]);
        std::string name;
        ss >> name;
        ASSERT_EQ(name, names[k]) << describe(args, r);
        for (int c = 0; c < 3; ++c) {
            std::string w;
            ASSERT_TRUE(static_cast<bool>(ss >> w)) << describe(args, r);
            bool ok = false;
            values[k][c] = toDouble(w, ok);
            ASSERT_TRUE(ok) << "not a number: " << w;
            ASSERT_TRUE(std::isfinite(values[k][c])) << lines[k];
        }
        std::string extra;
        EXPECT_FALSE(static_cast<bool>(ss >> extra)) << "trailing text: " << lines[k];
    }
    const double rdr[3] = {0.5, 0.6, 0.7}, ld[3] = {1, 2, 3};
    for (int c = 0; c < 3; ++c) {
        EXPECT_GE(values[0][c], 0.0) << lines[0];
        EXPECT_GT(values[1][c], 0.0) << lines[1];
        Forward f = dipoleForward(values[0][c], values[1][c], 1.3);
        EXPECT_NEAR(f.rdr, rdr[c], 1e-3 * rdr[c]) << "channel " << c;
        EXPECT_NEAR(f.ld, ld[c], 1e-3 * ld[c]) << "channel " << c;
    }
}

TEST_F(Cli, InvertRejectsBadInputs) {
    expectFailure({"invert", "--model", kDipole, "--rdr", "1.5,0.5,0.5", "--ld", "1,1,1"},
                  {"R_dr"});
    expectFailure({"invert", "--model", kDipole, "--rdr", "-0.1,0.5,0.5", "--ld", "1,1,1"},
                  {"R_dr"});
    expectFailure({"invert", "--model", kDipole, "--rdr", "0.5,0.5,0.5", "--ld", "0,1,1"}, {"l_d"});
    expectFailure({"invert", "--model", kDipole, "--rdr", "0.5,0.5", "--ld", "1,1,1"}, {"--rdr"});
    expectFailure({"invert", "--model", kDipole, "--rdr", "0.5,0.5,0.5", "--ld", "1,x,1"},
                  {"--ld"});
    expectFailure({"invert", "--model", "does/not/exist.bssrdf", "--rdr", "0.5", "--ld", "1"},
                  {"--model", "does/not/exist.bssrdf"});
}

// Without a diffuseReflectance section, invert integrates the model's profile numerically:
// for the dipole the σ agree with those of its closed-form section.
TEST_F(Cli, InvertWithoutDiffuseReflectanceIntegratesTheProfile) {
    std::string text = readText(sourceRoot() / kDipole);
    size_t b = text.find("::begin diffuseReflectance");
    size_t e = text.find("::end diffuseReflectance");
    ASSERT_NE(b, std::string::npos);
    ASSERT_NE(e, std::string::npos);
    e = text.find('\n', e);
    ASSERT_NE(e, std::string::npos);
    text.erase(b, e + 1 - b);
    const fs::path model = dir() / "no_rdr.bssrdf";
    writeText(model, text);
    auto sigmas = [&](const std::string& m) {
        std::vector<std::string> args = {"invert",      "--model", m,      "--rdr",
                                         "0.5,0.6,0.7", "--ld",    "1,2,3"};
        RunResult r = run(args);
        EXPECT_EQ(r.code, 0) << describe(args, r);
        std::vector<double> v;
        std::stringstream ss(r.output);
        std::string w;
        while (ss >> w) {
            bool ok = false;
            const double x = toDouble(w, ok);
            if (ok) v.push_back(x);
        }
        EXPECT_EQ(v.size(), 6u) << r.output;
        return v;
    };
    const auto closed = sigmas(kDipole), numeric = sigmas(model.string());
    ASSERT_EQ(closed.size(), 6u);
    ASSERT_EQ(numeric.size(), 6u);
    for (size_t i = 0; i < 6; ++i)
        EXPECT_NEAR(numeric[i], closed[i], 1e-3 * closed[i]) << i;
}

// ---- screenshot ---------------------------------------------------------------------------

namespace {
// The width and height in a PNG's header ({0, 0} where it is not a PNG).
std::pair<uint32_t, uint32_t> pngSize(const fs::path& png) {
    const std::string bytes = readText(png);
    const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (bytes.size() < 24 || bytes.substr(12, 4) != "IHDR") return {0, 0};
    for (int i = 0; i < 8; ++i)
        if (static_cast<unsigned char>(bytes[size_t(i)]) != sig[i]) return {0, 0};
    // IHDR: big-endian width and height at bytes 16..23.
    auto be32 = [&](size_t o) {
        uint32_t v = 0;
        for (size_t i = 0; i < 4; ++i)
            v = (v << 8) | static_cast<unsigned char>(bytes[o + i]);
        return v;
    };
    return {be32(16), be32(20)};
}
} // namespace

TEST_F(Cli, ScreenshotWritesPngOfRequestedSize) {
    std::vector<std::string> args = {"screenshot", "--out",    "shot.png", "--size",
                                     "640x400",    "--frames", "2"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    EXPECT_EQ(pngSize(dir() / "shot.png"), std::make_pair(640u, 400u)) << describe(args, r);
}

// --ui-scale 1.5: the same UI in 1.5 times the pixels (a screen at 150 %).
TEST_F(Cli, ScreenshotAtAUiScaleIsThatManyTimesTheSize) {
    std::vector<std::string> args = {"screenshot", "--out", "shot.png",   "--size", "640x400",
                                     "--frames",   "2",     "--ui-scale", "1.5"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    EXPECT_EQ(pngSize(dir() / "shot.png"), std::make_pair(960u, 600u)) << describe(args, r);
}

TEST_F(Cli, ScreenshotRejectsBadSizeAndOutput) {
    expectFailure({"screenshot", "--out", "tiny.png", "--size", "10x10"}, {"--size"});
    expectFailure({"screenshot", "--out", "tiny.png", "--size", "big"}, {"--size"});
    for (const char* scale : {"0.25", "5", "big", "1.5x", "nan", ""})
        expectFailure({"screenshot", "--out", "tiny.png", "--ui-scale", scale},
                      {"error: --ui-scale: expected auto or a number from 0.5 to 4, got '" +
                       std::string(scale) + "'"});
    expectFailure({"screenshot", "--out", "tiny.png", "--size", "4000x3000", "--ui-scale", "3"},
                  {"error: --ui-scale: the image would be over 8192 pixels wide or high: "
                   "4000x3000 at 3"});
    expectFailure({"--headless", "gui", "--ui-scale", "0"}, {"error: --ui-scale: expected auto"});
    EXPECT_FALSE(fs::exists(dir() / "tiny.png"));
    // the file is a PNG, and an unwritable place is refused before the GUI runs
    expectFailure({"screenshot", "--out", "shot.jpg"}, {"--out", "'shot.jpg' must end in .png"});
    EXPECT_FALSE(fs::exists(dir() / "shot.jpg"));
    expectFailure({"screenshot", "--out", "no/such/folder/shot.png"},
                  {"error: --out: cannot write", "no/such/folder"});
}

// ---- the headless default run (README: `./run` without a display) --------------------------

// It records the default capture (the dipole, its pencil plot and the bunny through the mesh
// pipeline) and replays it: every stage must agree with what the same run recorded. The manifest
// once held the camera from before the mesh framed it, and the replay traced the recorded
// G-buffer through another camera (2332 of 2336 pixels off centre).
// --size is the screenshot's size there (else 1600x1000).
TEST_F(Cli, HeadlessDefaultRecordsACaptureThatReplaysAndExitsZero) {
    const std::vector<std::string> args = {"--headless", "--out-dir", "default",
                                           "gui",        "--size",    "800x600"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    EXPECT_FALSE(contains(r.output, "FAIL")) << describe(args, r);
    EXPECT_TRUE(contains(r.output, "PASS scene.gbuffer_rule")) << describe(args, r);
    EXPECT_TRUE(contains(r.output, "PASS scene.render")) << describe(args, r);
    EXPECT_TRUE(fs::exists(dir() / "default" / "capture" / "manifest.json"));
    EXPECT_EQ(pngSize(dir() / "default" / "workbench.png"), std::make_pair(800u, 600u));
}

// The program's --headless and --out-dir belong to the GUI: given with another command (which
// would ignore them) they are refused by name, before it runs.
TEST_F(Cli, HeadlessAndOutDirWithAnotherCommandAreRefused) {
    const std::vector<std::vector<std::string>> cases = {
        {"--out-dir", "x", "profile", "--model", "materials/dipole.bssrdf", "--preset", "Skin1",
         "--out", "p.csv"},
        {"--headless", "profile", "--model", "materials/dipole.bssrdf", "--preset", "Skin1",
         "--out", "p.csv"},
        {"--headless", "bench", "reload"}};
    for (const auto& args : cases) {
        const RunResult r = run(args);
        EXPECT_EQ(r.code, 2) << describe(args, r);
        EXPECT_TRUE(contains(r.output, std::string("error: ") + args[0] +
                                           ": belongs to the GUI (the default command); "))
            << describe(args, r);
    }
    EXPECT_FALSE(fs::exists(dir() / "p.csv"));
    EXPECT_FALSE(fs::exists(dir() / "x"));
}

// What only the window uses, given to the headless run (which records the default capture), is
// refused by name, before anything runs.
TEST_F(Cli, WindowOnlyArgumentsWithHeadlessAreRefused) {
    expectFailure({"--headless", "--out-dir", "out", "gui", "materials/dipole.bssrdf"},
                  {"error: a model file: belongs to the window; the headless run records the "
                   "default capture (leave it out)"});
    expectFailure({"--headless", "--out-dir", "out", "gui", "--fresh"},
                  {"error: --fresh: belongs to the window"});
    EXPECT_FALSE(fs::exists(dir() / "out"));
}

// ---- help, replay -------------------------------------------------------------------------

TEST_F(Cli, HelpListsSubcommands) {
    RunResult r = run({"--help"});
    ASSERT_EQ(r.code, 0) << describe({"--help"}, r);
    for (const char* sub : {"gui", "screenshot", "profile", "invert", "record", "replay"})
        EXPECT_TRUE(contains(r.output, sub)) << sub << "\n" << r.output;
}

TEST_F(Cli, ProfileHelpDocumentsOptions) {
    RunResult r = run({"profile", "--help"});
    ASSERT_EQ(r.code, 0) << describe({"profile", "--help"}, r);
    for (const char* opt : {"--model", "--preset", "--sigma-a", "--sigma-s", "--out"})
        EXPECT_TRUE(contains(r.output, opt)) << opt << "\n" << r.output;
}

// A word that is no command, and a group without one of its commands, are usage errors that
// say what to type instead: every command (hidden ones left out), or the group's. (The runner
// puts --root before the word, as a user may.)
TEST_F(Cli, UnknownSubcommandFails) {
    RunResult r = run({"no-such-command"});
    EXPECT_EQ(r.code, 2) << describe({"no-such-command"}, r);
    EXPECT_TRUE(contains(r.output, "no-such-command: not a command; the commands are gui, "))
        << r.output;
    EXPECT_TRUE(contains(r.output, ", bench\n")) << r.output;
    EXPECT_FALSE(contains(r.output, "probe")) << "a hidden command is offered\n" << r.output;
    r = run({"bench"});
    EXPECT_EQ(r.code, 2) << describe({"bench"}, r);
    EXPECT_TRUE(contains(r.output, "bench: give one of reload, pathtrace, ")) << r.output;
    r = run({"bench", "speed"});
    EXPECT_EQ(r.code, 2) << describe({"bench", "speed"}, r);
    EXPECT_TRUE(contains(r.output, "bench speed: not a command of bench; give one of reload, "))
        << r.output;
}

TEST_F(Cli, ReplayMissingCaptureNamesManifest) {
    std::vector<std::string> args = {"replay", "/nonexistent/capture"};
    RunResult r = run(args);
    EXPECT_EQ(r.code, 2) << describe(args, r);
    EXPECT_TRUE(contains(r.output, "manifest.json")) << describe(args, r);
}

} // namespace

// ---- path tracer: slab, sphere, mesh ----------------------------------------------------------

TEST_F(Cli, SlabWritesHistogramWithStandardErrors) {
    std::vector<std::string> args = {"slab",    "--sigma-a", "0.1",     "--sigma-s", "1",
                                     "--paths", "20000",     "--bins",  "25",        "--rmax",
                                     "5",       "--out",     "slab.csv"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const std::string text = readText(dir() / "slab.csv");
    for (const char* key : {"# sigma_a 0.1", "# paths 20000", "# total_Rd ", "# specular ",
                            "# absorbed ", "# wall_s ", "# paths_per_s ", "r_mm,Rd_per_mm2,stderr"})
        EXPECT_TRUE(contains(text, key)) << key;
    int rows = 0;
    for (const auto& line : splitLines(text))
        if (!line.empty() && line[0] != '#' && line[0] != 'r') {
            auto v = splitOn(line, ',');
            ASSERT_EQ(v.size(), 3u) << line;
            EXPECT_NEAR(std::stod(v[0]), 0.1 + 0.2 * rows, 1e-9); // bin centres
            EXPECT_GE(std::stod(v[2]), 0.0);
            ++rows;
        }
    EXPECT_EQ(rows, 25);
}

// `estimate --gpu`: the GL compute walk writes the table and CSVs of the CPU walk's shape,
// says which device traced it, passes its energy checks, and its table reads back (`merge` of
// the one file gives the same bytes). A thread count and shards are refused.
TEST_F(Cli, EstimateOnTheGpuWritesTheSameKindOfTable) {
    const std::vector<std::string> args = {
        "estimate", "--sigma-a",   "0.2",   "--sigma-s",  "1",         "--theta-i",
        "0,60",     "--r-bins",    "5",     "--rmax",     "3",         "--theta-s-bins",
        "2",        "--paths",     "20000", "--dir-bins", "2x3",       "--gpu",
        "--out",    "gpu.bwtable", "--csv", "r.csv",      "--csv-dir", "s.csv"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    EXPECT_TRUE(contains(r.output, "traced on GPU (")) << r.output;
    EXPECT_TRUE(contains(r.output, "theta_i 60: 20000 paths")) << r.output;
    EXPECT_FALSE(contains(r.output, "energy check failed")) << r.output;
    const std::string csv = readText(dir() / "r.csv");
    EXPECT_EQ(csv.rfind("theta_i_deg,r_lo_mm,r_hi_mm,theta_s_lo_deg,theta_s_hi_deg,R,stderr\n", 0),
              0u);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 5 * 2);
    const std::string dirCsv = readText(dir() / "s.csv");
    EXPECT_EQ(std::count(dirCsv.begin(), dirCsv.end(), '\n'), 1 + 2 * 5 * 2 * 6);
    r = run({"merge", "gpu.bwtable", "--out", "copy.bwtable"});
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(readText(dir() / "gpu.bwtable"), readText(dir() / "copy.bwtable"));
    expectFailure({"estimate", "--paths", "1000", "--gpu", "--shard", "1/2", "--out", "x.bwtable"},
                  {"--shard", "CPU"});
    expectFailure({"estimate", "--paths", "1000", "--gpu", "--threads", "3", "--out", "x.bwtable"},
                  {"--threads: the GL tracer runs on the GPU"});
}

// Ctrl-C during `estimate --gpu` writes the chunks traced so far as a valid table (it merges
// like a shard) and exits 130, as on the CPU.
TEST_F(Cli, EstimateOnTheGpuInterruptedWritesThePartialTable) {
    const std::vector<std::string> args = {
        BW_EXE,      "--root", BW_SOURCE_ROOT,   "estimate", "--sigma-a", "0.2",
        "--sigma-s", "1",      "--theta-i",      "30",       "--r-bins",  "5",
        "--rmax",    "3",      "--theta-s-bins", "2",        "--paths",   "1e10",
        "--gpu",     "--out",  "t.bwtable"};
    // interrupted once the first chunk is traced (its progress line), however long the GPU
    // tracer's build takes (NVIDIA: over 3 s at 16 test processes)
    RunResult r = runCommand(args, dir(), 60000, SIGINT, " paths/s");
    EXPECT_EQ(r.code, 130) << r.output;
    EXPECT_TRUE(contains(r.output, "(partial)")) << r.output;
    r = run({"merge", "t.bwtable", "--out", "m.bwtable", "--csv", "m.csv"});
    EXPECT_EQ(r.code, 0) << r.output;
}

TEST_F(Cli, SlabRejectsBadInputs) {
    const std::vector<std::string> base = {"slab", "--paths", "1000", "--out", "x.csv"};
    auto with = [&](std::vector<std::string> extra) {
        auto a = base;
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    expectFailure(with({"--sigma-a", "-0.1"}), {"--sigma-a", "must be between 0 and"});
    expectFailure(with({"--sigma-s", "0"}), {"sigma_s"});
    expectFailure(with({"--g", "1"}), {"g"});
    expectFailure(with({"--eta", "0"}), {"eta"});
    expectFailure(with({"--bins", "0"}), {"bins"});
    expectFailure(with({"--rmax", "-1"}), {"rmax"});
    expectFailure({"slab", "--paths", "0", "--out", "x.csv"}, {"path"});
    expectFailure({"slab", "--paths", "1000", "--out", "/proc/nope/x.csv"}, {"/proc/nope/x.csv"});
    expectFailure(with({"--max-events", "0"}), {"--max-events", "between 1 and 4294967295"});
    expectFailure(with({"--exit-samples", "65"}), {"--exit-samples", "between 0 and 64"});
    expectFailure(with({"--exit-depth", "-1"}), {"--exit-depth"});
    // the GL tracer does not split nor sample exits: asked for with --gpu, refused
    for (const char* flag : {"--split-levels", "--split-start", "--exit-samples", "--exit-depth"})
        expectFailure(with({"--gpu", flag, "1"}), {std::string(flag) + ": the GL tracer", "--gpu"});
    expectFailure(with({"--gpu", "--threads", "2"}), {"--threads: the GL tracer runs on the GPU"});
    // sigma_a = 0 (no absorption) is valid and terminates; the few paths of the heavy tail of
    // return times that reach the event limit are truncated, and since their weight exceeds the
    // standard error the CSV is written but the energy check fails: exit status 3, saying so
    RunResult r = run({"slab", "--sigma-a", "0", "--paths", "2000", "--out", "ok.csv"});
    EXPECT_EQ(r.code, 3) << r.output;
    EXPECT_NE(r.output.find("error: slab: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("truncated at the event limit"), std::string::npos) << r.output;
    const std::string csv = readText(dir() / "ok.csv");
    EXPECT_NE(csv.find("# energy_check FAILED: "), std::string::npos);
    EXPECT_NE(csv.find("# truncated "), std::string::npos);
    // with absorption nothing is truncated and the check passes
    r = run({"slab", "--sigma-a", "0.05", "--paths", "2000", "--out", "ok2.csv"});
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(readText(dir() / "ok2.csv").find("# energy_check ok"), std::string::npos);
    // the default: expected-value exits, 2 samples
    EXPECT_NE(readText(dir() / "ok2.csv").find("# exits expected, 2 samples within 2 mfp\n"),
              std::string::npos);
    r = run(
        {"slab", "--sigma-a", "0.05", "--paths", "2000", "--exit-samples", "3", "--out", "ev.csv"});
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(readText(dir() / "ev.csv").find("# exits expected, 3 samples within 2 mfp\n"),
              std::string::npos);
    r = run(
        {"slab", "--sigma-a", "0.05", "--paths", "2000", "--exit-samples", "0", "--out", "an.csv"});
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(readText(dir() / "an.csv").find("# exits actual\n"), std::string::npos);
}

// Numbers on the command line are refused when not finite, negative where a count is meant or
// outside the setting's range, naming the flag, never replaced by a default; no output written.
TEST_F(Cli, NumericArgumentsAreRefusedNeverReplacedByDefaults) {
    const std::string mesh = (sourceRoot() / "tests/fuzz/corpus/obj/box.obj").string();
    const std::string model = (sourceRoot() / "materials/dipole.bssrdf").string();
    expectFailure({"slab", "--rmax", "nan", "--paths", "100", "--out", "a.csv"},
                  {"--rmax", "finite"});
    expectFailure({"slab", "--g", "inf", "--paths", "100", "--out", "a.csv"}, {"--g", "finite"});
    expectFailure({"slab", "--threads", "-3", "--paths", "100", "--out", "a.csv"},
                  {"--threads", "between 0 and 1024"});
    expectFailure({"pointcloud", "--mesh", mesh, "--iterations", "-1", "--out", "a.ply"},
                  {"--iterations", "between 0 and 100000, got -1"});
    for (const char* method : {"elimination", "uniform"}) // no relaxation to iterate
        expectFailure({"pointcloud", "--mesh", mesh, "--method", method, "--iterations", "5",
                       "--out", "a.ply"},
                      {"--iterations: only with --method stratified-repulsion or repulsion"});
    expectFailure({"pointcloud", "--mesh", mesh, "--threads", "-3", "--out", "a.ply"},
                  {"--threads"});
    expectFailure({"pointcloud", "--mesh", mesh, "--points", "1e9", "--out", "a.ply"},
                  {"--points", "16777216"});
    expectFailure(
        {"profile", "--model", model, "--preset", "Marble", "--rmax", "1e300", "--out", "a.csv"},
        {"--rmax", "between 0.01 and 1000"});
    expectFailure({"profile", "--model", model, "--preset", "Marble", "--samples", "2000000000",
                   "--out", "a.csv"},
                  {"--samples", "between 2 and 16384"});
    expectFailure(
        {"profile", "--model", model, "--preset", "Marble", "--eta", "nan", "--out", "a.csv"},
        {"--eta", "finite"});
    expectFailure({"render", "--mesh", mesh, "--model", model, "--preset", "Marble", "--yaw", "nan",
                   "--out", "a.exr"},
                  {"--yaw", "finite"});
    expectFailure({"render", "--mesh", mesh, "--model", model, "--preset", "Marble", "--width",
                   "-5", "--out", "a.exr"},
                  {"--width"});
    expectFailure({"sphere", "--threads", "-1", "--out", "a.exr"}, {"--threads"});
    expectFailure({"estimate", "--paths", "1000", "--threads", "5000", "--out", "a.bwtable"},
                  {"--threads", "1024"});
    for (const char* f : {"a.csv", "a.ply", "a.exr", "a.bwtable"})
        EXPECT_FALSE(fs::exists(dir() / f)) << f;
}

// A write that fails part-way (the file-size limit makes the disk "full" after 1 KiB: the
// first buffer is written, a later one fails) gives a clear message and a non-zero exit, and
// leaves neither the output nor its temporary behind; a device is never replaced.
TEST_F(Cli, FailedWritesLeaveNoPartialOutput) {
    auto limited = [&](const std::vector<std::string>& args) {
        std::vector<std::string> full = {
            "/bin/bash", "-c",     "ulimit -f 1; trap '' XFSZ; exec \"$0\" \"$@\"",
            BW_EXE,      "--root", BW_SOURCE_ROOT};
        full.insert(full.end(), args.begin(), args.end());
        return runCommand(full, dir());
    };
    RunResult r = limited({"profile", "--model", kDipole, "--preset", "Marble", "--samples", "4000",
                           "--out", "big.csv"});
    EXPECT_NE(r.code, 0) << r.output;
    EXPECT_LT(r.code, 128) << r.output;
    EXPECT_TRUE(contains(r.output, "big.csv")) << r.output;
    EXPECT_TRUE(contains(r.output, "write failed")) << r.output;
    EXPECT_FALSE(fs::exists(dir() / "big.csv"));
    EXPECT_FALSE(fs::exists(dir() / "big.csv.tmp"));
    r = limited({"screenshot", "--out", "big.png", "--size", "640x480", "--frames", "1"});
    EXPECT_NE(r.code, 0) << r.output;
    EXPECT_FALSE(fs::exists(dir() / "big.png"));
    EXPECT_FALSE(fs::exists(dir() / "big.png.tmp"));
    // the same commands without the limit work
    r = run({"profile", "--model", kDipole, "--preset", "Marble", "--samples", "4000", "--out",
             "big.csv"});
    EXPECT_EQ(r.code, 0) << r.output;
    // a device is refused, not replaced
    expectFailure({"profile", "--model", kDipole, "--preset", "Marble", "--out", "/dev/full"},
                  {"/dev/full", "not a regular file"});
    EXPECT_TRUE(fs::is_character_file("/dev/full"));
}

TEST_F(Cli, SphereAndMeshWriteExrAndRejectBadMeshes) {
    RunResult r = run({"sphere", "--size", "16x16", "--spp", "2", "--out", "s.exr"});
    ASSERT_EQ(r.code, 0) << r.output;
    const std::string exr = readText(dir() / "s.exr");
    ASSERT_GE(exr.size(), 4u);
    EXPECT_EQ(static_cast<unsigned char>(exr[0]), 0x76); // OpenEXR magic 76 2f 31 01
    EXPECT_EQ(static_cast<unsigned char>(exr[1]), 0x2f);
    expectFailure({"mesh", "--mesh", "missing.obj", "--out", "m.exr"}, {"missing.obj"});
    {
        std::ofstream bad(dir() / "open.obj");
        bad << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"; // one triangle: open
    }
    expectFailure({"mesh", "--mesh", "open.obj", "--size", "8x8", "--out", "m.exr"}, {"open"});
    {
        std::ofstream bad(dir() / "garbage.obj");
        bad << "v 0 zero 0\nf 1 2\n";
    }
    expectFailure({"mesh", "--mesh", "garbage.obj", "--out", "m.exr"}, {"garbage.obj"});
    expectFailure({"sphere", "--light", "0,0,0", "--out", "s.exr"}, {"light"});
    expectFailure({"sphere", "--spp", "0", "--out", "s.exr"}, {"--spp"});
}

// Resources come from --root, or from beside the executable (an installed or in-tree layout),
// or the current folder; a copied executable with none of them says so and exits non-zero
// instead of reading the tree it was built in.
TEST_F(Cli, ResourcesAreFoundBesideTheExecutableNeverFromTheBuildTree) {
    namespace fs = std::filesystem;
    const fs::path lone = dir() / "lone", tree = dir() / "tree", elsewhere = dir() / "elsewhere";
    fs::create_directories(lone);
    fs::create_directories(tree / "bin");
    fs::create_directories(elsewhere);
    fs::copy_file(BW_EXE, lone / "bssrdf-workbench");
    fs::copy_file(BW_EXE, tree / "bin" / "bssrdf-workbench");
    fs::copy(fs::path(BW_SOURCE_ROOT) / "shaders", tree / "shaders", fs::copy_options::recursive);
    fs::create_directories(tree / "materials");
    fs::copy_file(fs::path(BW_SOURCE_ROOT) / "materials/presets.json",
                  tree / "materials/presets.json");
    fs::copy_file(fs::path(BW_SOURCE_ROOT) / "materials/dipole.bssrdf",
                  tree / "materials/only_here.bssrdf");
    const std::vector<std::string> args = {
        "profile", "--preset", "Marble", "--model", "materials/only_here.bssrdf", "--out", "p.csv"};

    auto with = [](std::string exe, std::vector<std::string> rest) {
        rest.insert(rest.begin(), std::move(exe));
        return rest;
    };
    clitest::RunResult r =
        clitest::runCommand(with((lone / "bssrdf-workbench").string(), args), elsewhere);
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("pass --root"), std::string::npos) << r.output;
    // the copy inside a tree finds that tree's materials/ from anywhere
    r = clitest::runCommand(with((tree / "bin" / "bssrdf-workbench").string(), args), elsewhere);
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(elsewhere / "p.csv"));
    // --root wins
    auto rooted = args;
    rooted.insert(rooted.begin(), {"--root", tree.string()});
    r = clitest::runCommand(with((lone / "bssrdf-workbench").string(), rooted), elsewhere);
    EXPECT_EQ(r.code, 0) << r.output;
    r = clitest::runCommand(
        with((lone / "bssrdf-workbench").string(), {"--root", elsewhere.string(), "defaults"}),
        elsewhere);
    EXPECT_EQ(r.code, 0) << r.output; // a command that reads no project file runs anywhere
}
