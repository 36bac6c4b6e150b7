// `compare` (app/cli/compare_command.h, app/pipeline/scoring.h): the scores of a model against
// a synthetic reference (exact values, the standard error against the spread of noisy references,
// ties within the noise), and the command end to end: scores.json schema, reports, the
// reference cache, --fail-if-worse and bad inputs.
#include "../support/cli_fixture.h"
#include "cli/compare_command.h"
#include "gui/report_png.h"
#include "pipeline/scoring.h"
#include "pipeline/scoring_oblique.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>

#include <stb_image.h>

namespace {
namespace fs = std::filesystem;
using namespace clitest;

struct Synthetic {
    std::vector<double> r, rd, se, model;
};
// A reference R_d(r) = e^(−r) on 90 bins of 0.05 (l_d = 1), standard error 1 % of each value.
Synthetic synthetic(double modelScale) {
    Synthetic s;
    for (int i = 0; i < 90; ++i) {
        const double r = 0.05 * (i + 0.5);
        s.r.push_back(r);
        s.rd.push_back(std::exp(-r));
        s.se.push_back(0.01 * std::exp(-r));
        s.model.push_back(modelScale * std::exp(-r)); // R_sp = 0 below: R_ref = R_d
    }
    return s;
}

app::ScoreRow score(const Synthetic& s, double modelTotal = 1.0) {
    return app::scoreAgainstReference(app::binEdges(s.r), s.rd, s.se, 0.0, 1.0, 0.01, 1.0, s.model,
                                      modelTotal);
}

} // namespace

TEST(CompareScores, ExactValuesOfAScaledModel) {
    // a model equal to the reference: no error anywhere
    app::ScoreRow same = score(synthetic(1.0));
    EXPECT_DOUBLE_EQ(same.relErr, 0.0);
    EXPECT_DOUBLE_EQ(same.ratio1, 1.0);
    EXPECT_DOUBLE_EQ(same.ratio4, 1.0);
    EXPECT_FALSE(same.rErr5Ld.has_value());
    // R_m = 1.1 R_ref: rel_err² = 0.1² less the reference's noise c²(3x² − 2x) with c = 1 %,
    // x = 1.1; ratios 1.1, the error exceeds 5 % (and 2 se = 2 %) from the first bin inside
    // [0.1, 4] l_d, whose centre is 0.125
    app::ScoreRow high = score(synthetic(1.1), 1.1);
    EXPECT_NEAR(high.relErr, std::sqrt(0.01 - 1e-4 * (3 * 1.21 - 2.2)), 1e-12);
    EXPECT_NEAR(high.ratio1, 1.1, 1e-12);
    EXPECT_NEAR(high.ratio4, 1.1, 1e-12);
    EXPECT_NEAR(high.totalRatio, 1.1, 1e-12);
    ASSERT_TRUE(high.rErr5Ld.has_value());
    EXPECT_NEAR(*high.rErr5Ld, 0.125, 1e-12);
    // R_sp divides the reference: R_ref = R_d/(1 − R_sp)
    Synthetic s = synthetic(1.0 / 0.96);
    app::ScoreRow sp = app::scoreAgainstReference(app::binEdges(s.r), s.rd, s.se, 0.04, 0.96, 0.01,
                                                  1.0, s.model, 1.0);
    EXPECT_NEAR(sp.relErr, 0.0, 1e-12);
    EXPECT_NEAR(sp.totalRatio, 1.0, 1e-12);
}

TEST(CompareScores, StandardErrorIsTheSpreadOverNoisyReferences) {
    // an uneven 10 % error; 300 references, each the truth with 1 % Gaussian noise per bin: the
    // stated standard error is the spread of rel_err over them, whose mean is the noise-free one
    Synthetic s = synthetic(1.0);
    for (size_t i = 0; i < s.model.size(); ++i)
        s.model[i] *= 1.0 + 0.1 * std::sin(double(i));
    Synthetic exact = s;
    for (double& v : exact.se)
        v = 0;
    const double truth = score(exact).relErr;
    std::mt19937_64 rng(3);
    std::normal_distribution<double> z;
    const int trials = 300;
    double sum = 0, sumSq = 0, seSum = 0;
    for (int t = 0; t < trials; ++t) {
        Synthetic noisy = s;
        for (size_t i = 0; i < noisy.rd.size(); ++i)
            noisy.rd[i] += s.se[i] * z(rng);
        const app::ScoreRow r = score(noisy);
        sum += r.relErr;
        sumSq += r.relErr * r.relErr;
        seSum += r.relErrSe;
    }
    const double mean = sum / trials, sd = std::sqrt(sumSq / trials - mean * mean);
    EXPECT_NEAR(mean, truth, 4 * sd / std::sqrt(double(trials)));
    EXPECT_NEAR(seSum / trials / sd, 1.0, 0.15);
}

TEST(CompareScores, DifferencesWithinTheNoiseAreTies) {
    std::vector<app::ScoreRow> rows;
    auto row = [](const char* model, double rel, double se) {
        app::ScoreRow r;
        r.model = model, r.preset = "P", r.channel = "R", r.relErr = rel, r.relErrSe = se;
        return r;
    };
    rows.push_back(row("c", 0.30, 0.01)); // far from the others
    rows.push_back(row("b", 0.11, 0.01)); // within 2√2 · 0.01 of a
    rows.push_back(row("a", 0.10, 0.01));
    rows.push_back(row("d", 0.135, 0.01)); // beyond the noise from a (0.035 > 0.028): own rank
    app::rankRows(rows);
    ASSERT_EQ(rows.size(), 4u);
    EXPECT_EQ(rows[0].model, "a");
    EXPECT_EQ(rows[0].rank, 1);
    EXPECT_TRUE(rows[0].tie);
    EXPECT_EQ(rows[1].model, "b");
    EXPECT_EQ(rows[1].rank, 1);
    EXPECT_TRUE(rows[1].tie);
    EXPECT_EQ(rows[2].model, "d");
    EXPECT_EQ(rows[2].rank, 3);
    EXPECT_FALSE(rows[2].tie);
    EXPECT_EQ(rows[3].model, "c");
    EXPECT_EQ(rows[3].rank, 4);
    EXPECT_FALSE(rows[3].tie);
}

// Rows come out by preset, then channel in colour order R, G, B (then other names), then rank,
// as the pencil plot and every colour triple list them.
TEST(CompareScores, ChannelsInColourOrder) {
    std::vector<app::ScoreRow> rows;
    for (const char* preset : {"Skin1", "Marble"})
        for (const char* ch : {"B", "lum", "G", "R"})
            for (double rel : {0.2, 0.1}) {
                app::ScoreRow r;
                r.model = rel < 0.15 ? "good" : "poor";
                r.preset = preset, r.channel = ch, r.relErr = rel, r.relErrSe = 0.001;
                rows.push_back(r);
            }
    app::rankRows(rows);
    std::string order;
    for (const app::ScoreRow& r : rows)
        order += r.preset + "/" + r.channel + "/" + r.model + " ";
    EXPECT_EQ(order, "Marble/R/good Marble/R/poor Marble/G/good Marble/G/poor Marble/B/good "
                     "Marble/B/poor Marble/lum/good Marble/lum/poor Skin1/R/good Skin1/R/poor "
                     "Skin1/G/good Skin1/G/poor Skin1/B/good Skin1/B/poor Skin1/lum/good "
                     "Skin1/lum/poor ");
}

// Each model over every row: rows where it ranks 1 (ties at rank 1 included, a tie at a lower
// rank not), the median rel_err (the mean of the middle two for an even count), the row of the
// largest rel_err; models in order of their median.
TEST(CompareScores, ModelSummariesCountFirstsAndTakeTheMedian) {
    std::vector<app::ScoreRow> rows;
    auto add = [&](const char* model, const char* preset, const char* ch, double rel) {
        app::ScoreRow r;
        r.model = model, r.preset = preset, r.channel = ch, r.relErr = rel, r.relErrSe = 0.001;
        rows.push_back(r);
    };
    // Marble R: a 0.10 and b 0.1005 tie at rank 1, c 0.40 rank 3
    add("a", "Marble", "R", 0.10), add("b", "Marble", "R", 0.1005), add("c", "Marble", "R", 0.40);
    // Marble G: c best; a and b tie at rank 2
    add("a", "Marble", "G", 0.30), add("b", "Marble", "G", 0.3005), add("c", "Marble", "G", 0.05);
    // Skin1 R: b best by far
    add("a", "Skin1", "R", 0.50), add("b", "Skin1", "R", 0.02), add("c", "Skin1", "R", 0.20);
    // Skin1 G: only a and c
    add("a", "Skin1", "G", 0.12), add("c", "Skin1", "G", 0.60);
    app::rankRows(rows);
    const std::vector<app::ModelSummary> m = app::summarizeModels(rows);
    ASSERT_EQ(m.size(), 3u);
    // medians: a {0.10, 0.12, 0.30, 0.50} → 0.21; b {0.02, 0.1005, 0.3005} → 0.1005;
    // c {0.05, 0.20, 0.40, 0.60} → 0.30
    EXPECT_EQ(m[0].model, "b");
    EXPECT_EQ(m[1].model, "a");
    EXPECT_EQ(m[2].model, "c");
    EXPECT_DOUBLE_EQ(m[0].medianRelErr, 0.1005);
    EXPECT_DOUBLE_EQ(m[1].medianRelErr, 0.21);
    EXPECT_DOUBLE_EQ(m[2].medianRelErr, 0.30);
    EXPECT_EQ(m[0].rows, 3u);
    EXPECT_EQ(m[1].rows, 4u);
    EXPECT_EQ(m[0].first, 2u); // Marble R (tie), Skin1 R; its Marble G tie is at rank 2
    EXPECT_EQ(m[1].first, 2u); // Marble R (tie), Skin1 G
    EXPECT_EQ(m[2].first, 1u); // Marble G
    EXPECT_EQ(m[1].worst.preset, "Skin1");
    EXPECT_EQ(m[1].worst.channel, "R");
    EXPECT_EQ(m[2].worst.preset, "Skin1");
    EXPECT_EQ(m[2].worst.channel, "G");
    EXPECT_DOUBLE_EQ(m[2].worst.relErr, 0.60);
    const std::string text = app::modelSummaryText(rows);
    EXPECT_NE(text.find("b      2 / 3      " + app::formatScore(100 * 0.1005, 3) + " %"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("60 % (Skin1 G, theta_i 0)"), std::string::npos) << text;
}

namespace {

// A synthetic slice on the scoreboard's oblique bins: R = e^(−r) · (1 + θs/π), S spread over the
// cells by cos θo (so Σ_c S Ω_c = R), standard errors 1 % of each value.
struct SyntheticSlice {
    pathtrace::BssrdfBins bins;
    pathtrace::BssrdfSlice ref;
    app::ModelSlice model;
};
SyntheticSlice syntheticSlice(double scale) {
    SyntheticSlice s;
    s.bins = app::obliqueSettings(1.0, 45.0, 1000).bins;
    s.ref.thetaIDeg = 45;
    const std::vector<double> e = s.bins.rEdges();
    double omega = 0;
    for (int c = 0; c < s.bins.dirBins(); ++c)
        omega += pathtrace::cellProjectedSolidAngle(s.bins, c);
    for (int b = 0; b < s.bins.spatialBins(); ++b) {
        const int ir = b / s.bins.thetaSBins, it = b % s.bins.thetaSBins;
        const double r = 0.5 * (e[size_t(ir)] + e[size_t(ir) + 1]);
        const double v = std::exp(-r) * (1 + (it + 0.5) / s.bins.thetaSBins);
        s.ref.R.push_back(v);
        s.ref.RStderr.push_back(0.01 * v);
        s.model.R.push_back(scale * v);
        for (int c = 0; c < s.bins.dirBins(); ++c) {
            s.ref.S.push_back(v / omega);
            s.ref.SStderr.push_back(0.01 * v / omega);
            s.model.S.push_back(scale * v / omega);
        }
    }
    return s;
}

} // namespace

TEST(CompareScores, ObliqueScoresOfAScaledModelAreExact) {
    const SyntheticSlice same = syntheticSlice(1.0);
    const app::ScoreRow a = app::scoreSlice(same.bins, same.ref, same.model, 1.0);
    EXPECT_DOUBLE_EQ(a.relErr, 0.0);
    ASSERT_TRUE(a.relErrDir.has_value());
    EXPECT_DOUBLE_EQ(*a.relErrDir, 0.0);
    EXPECT_DOUBLE_EQ(a.totalRatio, 1.0);
    EXPECT_FALSE(a.rErr5Ld.has_value());
    EXPECT_EQ(a.thetaI, 45.0);
    // 1.1 × the reference: the ratios are 1.1 exactly, rel_err² is 0.1² less the noise term
    // c²(3x² − 2x) (c = 1 %, x = 1.1); the error exceeds 5 % (and 2 se, about 1 % of a ring)
    // from the first ring, [0.1, 0.1 · 40^(1/16)] l_d (rings of equal steps in ln r)
    const SyntheticSlice high = syntheticSlice(1.1);
    const app::ScoreRow b = app::scoreSlice(high.bins, high.ref, high.model, 1.0);
    const double expected = std::sqrt(0.01 - 1e-4 * (3 * 1.21 - 2.2));
    EXPECT_NEAR(b.relErr, expected, 1e-12);
    EXPECT_NEAR(*b.relErrDir, expected, 1e-12);
    EXPECT_NEAR(b.ratio1, 1.1, 1e-12);
    EXPECT_NEAR(b.ratio4, 1.1, 1e-12);
    EXPECT_NEAR(b.totalRatio, 1.1, 1e-12);
    ASSERT_TRUE(b.rErr5Ld.has_value());
    EXPECT_NEAR(*b.rErr5Ld, 0.05 * (1 + std::pow(40.0, 1.0 / 16)), 1e-12);
}

TEST(CompareScores, ObliqueStandardErrorIsTheSpreadOverNoisyReferences) {
    // an uneven 10 % error on the plane; 200 references with 1 % Gaussian noise per bin
    SyntheticSlice s = syntheticSlice(1.0);
    for (size_t i = 0; i < s.model.R.size(); ++i)
        s.model.R[i] *= 1.0 + 0.1 * std::sin(double(i));
    std::mt19937_64 rng(5);
    std::normal_distribution<double> z;
    const int trials = 200;
    double sum = 0, sumSq = 0, seSum = 0;
    for (int t = 0; t < trials; ++t) {
        SyntheticSlice noisy = s;
        for (size_t i = 0; i < noisy.ref.R.size(); ++i)
            noisy.ref.R[i] += s.ref.RStderr[i] * z(rng);
        const app::ScoreRow r = app::scoreSlice(s.bins, noisy.ref, s.model, 1.0);
        sum += r.relErr;
        sumSq += r.relErr * r.relErr;
        seSum += r.relErrSe;
    }
    const double mean = sum / trials, sd = std::sqrt(sumSq / trials - mean * mean);
    SyntheticSlice exact = s;
    for (double& v : exact.ref.RStderr)
        v = 0;
    const double truth = app::scoreSlice(s.bins, exact.ref, s.model, 1.0).relErr;
    EXPECT_NEAR(mean, truth, 4 * sd / std::sqrt(double(trials)));
    EXPECT_NEAR(seSum / trials / sd, 1.0, 0.15);
}

TEST(ReportPng, Base64OfKnownStrings) { // RFC 4648 §10 test vectors
    EXPECT_EQ(app::base64(""), "");
    EXPECT_EQ(app::base64("f"), "Zg==");
    EXPECT_EQ(app::base64("fo"), "Zm8=");
    EXPECT_EQ(app::base64("foo"), "Zm9v");
    EXPECT_EQ(app::base64("foob"), "Zm9vYg==");
    EXPECT_EQ(app::base64("fooba"), "Zm9vYmE=");
    EXPECT_EQ(app::base64("foobar"), "Zm9vYmFy");
}

class CompareCli : public CliFixture {};

TEST_F(CompareCli, WritesScoresAndReportsCachesTheReferenceAndFailsIfWorse) {
    // a cache of its own, so the first run traces (the commands inherit the environment)
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    const std::vector<std::string> args = {"compare",
                                           "--models",
                                           "materials/dipole.bssrdf",
                                           "materials/better_dipole.bssrdf",
                                           "--presets",
                                           "Marble",
                                           "Skin1",
                                           "--paths",
                                           "20000",
                                           "--out",
                                           "cmp"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const nlohmann::json j = nlohmann::json::parse(readText(dir() / "cmp/scores.json"));
    EXPECT_EQ(j["schema"], "bssrdf-workbench-scores");
    EXPECT_EQ(j["version"], 2);
    ASSERT_EQ(j["rows"].size(), 12u); // 2 models × 2 presets × 3 channels
    for (const auto& row : j["rows"]) {
        for (const char* k : {"model", "preset", "channel"})
            EXPECT_TRUE(row[k].is_string()) << k;
        for (const char* k :
             {"theta_i", "ld_mm", "rel_err", "rel_err_se", "ratio_1ld", "ratio_1ld_se", "ratio_4ld",
              "ratio_4ld_se", "total_ratio", "total_ratio_se", "rank"})
            EXPECT_TRUE(row[k].is_number()) << k << " " << row.dump();
        EXPECT_TRUE(row["r_err5_ld"].is_number() || row["r_err5_ld"].is_null());
        EXPECT_TRUE(row["tie"].is_boolean());
        EXPECT_GE(row["rel_err"].get<double>(), 0.0);
        EXPECT_GT(row["rel_err_se"].get<double>(), 0.0);
        EXPECT_GE(row["rank"].get<int>(), 1);
    }
    EXPECT_NE(readText(dir() / "cmp/report.html").find("<table>"), std::string::npos);
    EXPECT_NE(readText(dir() / "cmp/report.md").find("| Marble | R | "), std::string::npos);
    EXPECT_NE(r.output.find("6 references traced"), std::string::npos) << r.output;
    // each model over the run, as scores.json has it: rows where it ranks 1 and its median
    for (const char* model : {"dipole", "better_dipole"}) {
        std::vector<double> rel;
        int first = 0;
        for (const auto& row : j["rows"])
            if (row["model"] == model) {
                rel.push_back(row["rel_err"].get<double>());
                first += row["rank"].get<int>() == 1;
            }
        ASSERT_EQ(rel.size(), 6u);
        std::sort(rel.begin(), rel.end());
        const std::string line = std::string(model) + std::string(15 - strlen(model), ' ') +
                                 std::to_string(first) + " / 6      " +
                                 app::formatScore(100 * 0.5 * (rel[2] + rel[3]), 3) + " %";
        EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
        EXPECT_NE(readText(dir() / "cmp/report.md")
                      .find("| " + std::string(model) + " | " + std::to_string(first) + " / 6 | "),
                  std::string::npos);
    }
    EXPECT_NE(r.output.find("12 rows: cmp/scores.json; reports: cmp/report.md, cmp/report.html"),
              std::string::npos)
        << r.output;

    // the second run takes the references from the cache; the same models are not worse
    std::vector<std::string> again = args;
    again.back() = "cmp2";
    again.insert(again.end(), {"--baseline", "cmp/scores.json", "--fail-if-worse", "5"});
    r = run(again);
    EXPECT_EQ(r.code, 0) << describe(again, r);
    EXPECT_NE(r.output.find("0 references traced, 6 from the cache"), std::string::npos)
        << r.output;
    EXPECT_EQ(readText(dir() / "cmp2/scores.json"), readText(dir() / "cmp/scores.json"));

    // a baseline where the row farthest from the reference (in standard errors) was exact:
    // that row is worse now beyond the noise, exit 1 naming it
    size_t far = 0;
    auto zOf = [&](size_t i) {
        return j["rows"][i]["rel_err"].get<double>() / j["rows"][i]["rel_err_se"].get<double>();
    };
    for (size_t i = 1; i < j["rows"].size(); ++i)
        if (zOf(i) > zOf(far)) far = i;
    ASSERT_GT(zOf(far), 3.0);
    nlohmann::json better = j;
    better["rows"][far]["rel_err"] = 0.0;
    better["rows"][far]["rel_err_se"] = 0.0;
    std::ofstream(dir() / "better.json") << better.dump();
    again[again.size() - 3] = "better.json";
    r = run(again);
    EXPECT_EQ(r.code, 1) << describe(again, r);
    EXPECT_NE(r.output.find("worse: " + j["rows"][far]["model"].get<std::string>()),
              std::string::npos)
        << r.output;
}

// Every preset is scored by default; a channel without absorption (Spectralon) has no l_d, so it
// is listed as skipped with the reason instead of failing the run.
TEST_F(CompareCli, ChannelsWithoutAbsorptionAreSkippedWithTheReason) {
    const std::vector<std::string> args = {"compare",   "--models",   "materials/dipole.bssrdf",
                                           "--presets", "Spectralon", "Marble",
                                           "--paths",   "2000",       "--out",
                                           "sp"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const nlohmann::json j = nlohmann::json::parse(readText(dir() / "sp/scores.json"));
    EXPECT_EQ(j["rows"].size(), 3u); // Marble's three channels
    ASSERT_EQ(j["skipped"].size(), 3u);
    EXPECT_EQ(j["skipped"][0]["preset"], "Spectralon");
    EXPECT_NE(j["skipped"][0]["reason"].get<std::string>().find("sigma_a = 0"), std::string::npos);
    EXPECT_NE(r.output.find("Spectralon R not scored"), std::string::npos) << r.output;
}

TEST_F(CompareCli, BadInputsNameTheirArgumentAndWriteNothing) {
    expectFailure({"compare", "--presets", "Marble", "Nonsense", "--paths", "2000", "--out", "o1"},
                  {"--presets", "unknown preset 'Nonsense'"});
    EXPECT_FALSE(fs::exists(dir() / "o1/scores.json"));
    std::ofstream(dir() / "other.json") << R"({"schema": "something-else", "rows": []})";
    expectFailure({"compare", "--presets", "Marble", "--paths", "2000", "--baseline", "other.json",
                   "--fail-if-worse", "5", "--out", "o2"},
                  {"other.json", "not a scores file"});
    std::ofstream(dir() / "v3.json")
        << R"({"schema": "bssrdf-workbench-scores", "version": 3, "rows": []})";
    expectFailure({"compare", "--presets", "Marble", "--paths", "2000", "--baseline", "v3.json",
                   "--fail-if-worse", "5", "--out", "o3"},
                  {"v3.json", "schema version 3"});
    // a baseline from before rel_err (version 1 ranked by rel_l2) is refused, saying why
    std::ofstream(dir() / "v1.json") << R"({"schema": "bssrdf-workbench-scores", "version": 1,
        "rows": [{"model": "dipole", "preset": "Marble", "channel": "R", "theta_i": 0,
                  "rel_l2": 0.1, "rel_l2_se": 0.01}]})";
    expectFailure({"compare", "--presets", "Marble", "--paths", "2000", "--baseline", "v1.json",
                   "--fail-if-worse", "5", "--out", "o6"},
                  {"v1.json", "version 1", "rel_l2", "rel_err", "run `compare` again"});
    EXPECT_FALSE(fs::exists(dir() / "o6"));
    EXPECT_FALSE(fs::exists(dir() / "o2"));
    expectFailure({"compare", "--presets", "Marble", "--paths", "2000", "--out", "/proc/no/dir"},
                  {"--out", "/proc/no/dir"});
    expectFailure({"compare", "--fail-if-worse", "5", "--out", "o4"},
                  {"--fail-if-worse", "--baseline"});
    expectFailure({"compare", "--paths", "nan", "--out", "o5"}, {"--paths"});
}

// θi > 0 rows against the connections estimate, with rel_err_dir; the report embeds its plots
// (pencil plot and ratio per preset and channel, slice heatmaps at θi > 0) as PNG drawn by the
// workbench's plot code, and writes them to plots/ too.
TEST_F(CompareCli, ObliqueAnglesAreScoredOverThePlaneAndTheReportHasItsPlots) {
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    const std::vector<std::string> args = {"compare",
                                           "--models",
                                           "materials/dipole.bssrdf",
                                           "materials/directional_dipole.bssrdf",
                                           "--presets",
                                           "Skin1",
                                           "--theta-i",
                                           "0,60",
                                           "--paths",
                                           "3000",
                                           "--out",
                                           "ob"};
    RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const nlohmann::json j = nlohmann::json::parse(readText(dir() / "ob/scores.json"));
    EXPECT_EQ(j["theta_i"], nlohmann::json::array({0.0, 60.0}));
    ASSERT_EQ(j["rows"].size(), 12u); // 2 models × 3 channels × 2 angles
    int oblique = 0;
    for (const auto& row : j["rows"]) {
        if (row["theta_i"].get<double>() == 0) {
            EXPECT_TRUE(row["rel_err_dir"].is_null()) << row.dump();
            continue;
        }
        ++oblique;
        EXPECT_EQ(row["theta_i"].get<double>(), 60.0);
        for (const char* k : {"rel_err", "rel_err_se", "rel_err_dir", "rel_err_dir_se", "ratio_1ld",
                              "total_ratio", "rank"})
            EXPECT_TRUE(row[k].is_number()) << k << " " << row.dump();
        EXPECT_GT(row["rel_err_se"].get<double>(), 0.0);
        EXPECT_GT(row["rel_err_dir"].get<double>(), 0.0);
    }
    EXPECT_EQ(oblique, 6);
    EXPECT_NE(r.output.find("6 references traced"), std::string::npos) << r.output;

    // the pictures: 2 per channel at θi = 0, 1 per channel at 60°, decoded and not blank
    const std::string html = readText(dir() / "ob/report.html");
    size_t embedded = 0;
    for (size_t at = html.find("data:image/png;base64,"); at != std::string::npos;
         at = html.find("data:image/png;base64,", at + 1))
        ++embedded;
    EXPECT_EQ(embedded, 9u);
    for (const char* name :
         {"Skin1_R_profile.png", "Skin1_G_ratio.png", "Skin1_B_theta60_slice.png"}) {
        const std::string png = readText(dir() / "ob/plots" / name);
        int w = 0, h = 0, n = 0;
        unsigned char* px = stbi_load_from_memory(
            reinterpret_cast<const unsigned char*>(png.data()), int(png.size()), &w, &h, &n, 3);
        ASSERT_NE(px, nullptr) << name;
        EXPECT_GE(w, 400) << name;
        EXPECT_GE(h, 200) << name;
        size_t differ = 0; // pixels unlike the top-left one: axes, curves, bins, labels
        for (int i = 0; i < w * h; ++i)
            differ += px[3 * i] != px[0] || px[3 * i + 1] != px[1] || px[3 * i + 2] != px[2];
        stbi_image_free(px);
        EXPECT_GT(differ, size_t(w * h / 50)) << name;
    }
    EXPECT_NE(readText(dir() / "ob/report.md").find("](plots/Skin1_R_profile.png)"),
              std::string::npos);

    // --no-plots: the same table without pictures
    std::vector<std::string> plain = args;
    plain.back() = "ob2";
    plain.push_back("--no-plots");
    r = run(plain);
    ASSERT_EQ(r.code, 0) << describe(plain, r);
    EXPECT_NE(r.output.find("0 references traced, 6 from the cache"), std::string::npos)
        << r.output;
    EXPECT_EQ(readText(dir() / "ob2/report.html").find("data:image/png"), std::string::npos);
    EXPECT_EQ(readText(dir() / "ob2/scores.json"), readText(dir() / "ob/scores.json"));
}

TEST_F(CompareCli, IncidenceAnglesOutsideTheRangeAreRefused) {
    expectFailure({"compare", "--presets", "Marble", "--theta-i", "0,90", "--out", "a1"},
                  {"--theta-i", "[0, 90)"});
    expectFailure({"compare", "--presets", "Marble", "--theta-i", "-5", "--out", "a2"},
                  {"--theta-i"});
    expectFailure({"compare", "--presets", "Marble", "--theta-i", "nan", "--out", "a3"},
                  {"--theta-i"});
    EXPECT_FALSE(fs::exists(dir() / "a1/scores.json"));
}

// `compare --shard K/N` run by GNU parallel, as a user would, merges into the single process's
// scores.json and reports byte for byte (every medium and angle is a unit; units go round-robin
// to the shards); a missing or repeated shard is refused.
TEST_F(CompareCli, ShardsRunByGnuParallelMergeIntoTheSameScoresAndReports) {
    ASSERT_EQ(std::system("command -v parallel >/dev/null"), 0)
        << "GNU parallel (Debian package parallel) is needed: ./run installs it";
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    const std::vector<std::string> args = {"compare",
                                           "--models",
                                           "materials/dipole.bssrdf",
                                           "materials/directional_dipole.bssrdf",
                                           "--presets",
                                           "Skin1",
                                           "Marble",
                                           "--theta-i",
                                           "0,60",
                                           "--paths",
                                           "3000",
                                           "--out"};
    std::vector<std::string> one = args;
    one.push_back("one");
    RunResult r = run(one);
    ASSERT_EQ(r.code, 0) << describe(one, r);
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache-shards").c_str(), 1);
    std::string shardArgs;
    for (const std::string& s : args)
        shardArgs += " '" + s + "'";
    const std::string cmd = "cd '" + dir().string() + "' && parallel -j 2 --halt now,fail=1 '" +
                            BW_EXE + "' --root '" + BW_SOURCE_ROOT + "'" + shardArgs +
                            " s{} --shard {}/5 ::: 1 2 3 4 5 >parallel.log 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << readText(dir() / "parallel.log");
    const std::vector<std::string> merge = {"merge", "s1", "s2", "s3", "s4", "s5", "--out", "m"};
    r = run(merge);
    ASSERT_EQ(r.code, 0) << describe(merge, r);
    EXPECT_EQ(readText(dir() / "m/scores.json"), readText(dir() / "one/scores.json"));
    EXPECT_EQ(readText(dir() / "m/report.md"), readText(dir() / "one/report.md"));
    EXPECT_EQ(readText(dir() / "m/report.html"), readText(dir() / "one/report.html"));
    expectFailure({"merge", "s1", "s2", "s4", "s5", "--out", "m2"}, {"missing shards of 5: 3"});
    expectFailure({"merge", "s1", "s2", "s3", "s4", "s5", "s2", "--out", "m3"},
                  {"shard 2/5 is also in s2"});
    expectFailure(
        {"compare", "--models", "materials/dipole.bssrdf", "--shard", "6/5", "--out", "bad"},
        {"--shard", "6/5"});
    ::unsetenv("BSSRDF_WORKBENCH_CACHE");
}
