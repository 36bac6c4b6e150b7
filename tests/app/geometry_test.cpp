// The geometry suite's scores (app/pipeline/geometry_scoring.h) and `compare --geometry`
// (app/cli/compare_geometry.h): rel_l2 of synthetic images exactly and, over noisy images, its
// expectation and standard error against the spread; the command end to end (schema, ranks,
// reports, pictures, the reference cache and a damaged entry, the baseline gate, a model that
// cannot be integrated said per case, bad inputs), and shards run through GNU parallel merging
// into the single process's scores.json byte for byte.
#include "../support/cli_fixture.h"
#include "pipeline/geometry_scoring.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

namespace {
namespace fs = std::filesystem;
using namespace clitest;

// A 32 × 32 image of a smooth field over a disc (covered), noise of relative standard error `c`.
app::ChannelImage field(double scale, double c, std::mt19937_64* rng) {
    app::ChannelImage img{32, 32, {}, {}, {}};
    std::normal_distribution<double> n(0.0, 1.0);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const double dx = (x - 15.5) / 16, dy = (y - 15.5) / 16;
            const bool in = dx * dx + dy * dy < 1;
            const double truth = in ? scale * (1.2 + std::sin(3 * dx) * std::cos(2 * dy)) : 0.0;
            const double se = c * truth;
            img.mean.push_back(rng ? truth + se * n(*rng) : truth);
            img.variance.push_back(se * se);
            img.covered.push_back(in);
        }
    return img;
}

} // namespace

TEST(GeometryScores, ExactValuesOfNoiselessImages) {
    const app::ChannelImage ref = field(1.0, 0.0, nullptr);
    const app::ImageScore same = app::imageRelativeL2(ref, ref);
    EXPECT_EQ(same.relL2, 0.0);
    EXPECT_EQ(same.meanRatio, 1.0);
    EXPECT_GT(same.pixels, 700u);
    const app::ImageScore high = app::imageRelativeL2(field(1.1, 0.0, nullptr), ref);
    EXPECT_NEAR(high.relL2, 0.1, 1e-12);
    EXPECT_NEAR(high.meanRatio, 1.1, 1e-12);
    EXPECT_EQ(high.relL2Se, 0.0);
    // pixels that only one image covers are not scored
    app::ChannelImage part = ref;
    for (size_t p = 0; p < part.covered.size() / 2; ++p)
        part.covered[p] = 0;
    EXPECT_LT(app::imageRelativeL2(part, ref).pixels, same.pixels);
    // a dark reference has no relative error
    app::ChannelImage dark = ref;
    std::fill(dark.mean.begin(), dark.mean.end(), 0.0);
    EXPECT_FALSE(app::imageRelativeL2(ref, dark).problem.empty());
}

TEST(GeometryScores, NoiseIsRemovedAndTheStandardErrorIsTheSpread) {
    // model 10 % high with 5 % noise per pixel, reference with 8 %: over 400 pairs the mean of
    // rel_l2 is the noiseless 0.1 and its spread the stated standard error
    std::mt19937_64 rng(7);
    const int n = 400;
    double sum = 0, sumSq = 0, seSum = 0;
    for (int k = 0; k < n; ++k) {
        const app::ImageScore s =
            app::imageRelativeL2(field(1.1, 0.05, &rng), field(1.0, 0.08, &rng));
        sum += s.relL2;
        sumSq += s.relL2 * s.relL2;
        seSum += s.relL2Se;
    }
    const double mean = sum / n, spread = std::sqrt(sumSq / n - mean * mean), se = seSum / n;
    EXPECT_NEAR(mean, 0.1, 4 * spread / std::sqrt(n)) << "the noise is removed";
    EXPECT_NEAR(se / spread, 1.0, 0.15) << "the standard error is the spread";
    // the raw L2 (noise left in) would be far off: √(0.01 + 0.05²·1.21 + 0.08²) ≈ 0.135
    EXPECT_LT(mean, 0.105);
}

TEST(GeometryScores, RanksTieWithinTheNoise) {
    std::vector<app::GeometryRow> rows(4);
    const double e[4] = {0.10, 0.105, 0.30, 0.09};
    for (int k = 0; k < 4; ++k) {
        rows[size_t(k)] = {
            "m" + std::to_string(k), "sphere:r=2", "Marble", "R", 1, 1, {}, 0, false};
        rows[size_t(k)].score.relL2 = e[k];
        rows[size_t(k)].score.relL2Se = 0.01;
    }
    rows.push_back(rows[0]);
    rows.back().model = "broken";
    rows.back().score.problem = "no image";
    app::rankGeometryRows(rows);
    EXPECT_EQ(rows[3].rank, 1); // 0.09
    EXPECT_EQ(rows[0].rank, 1); // 0.10: within 2√2 · 0.01 of 0.09
    EXPECT_TRUE(rows[0].tie);
    EXPECT_EQ(rows[1].rank, 1);
    EXPECT_EQ(rows[2].rank, 4);
    EXPECT_FALSE(rows[2].tie);
    EXPECT_EQ(rows[4].rank, 0); // no score, no rank
}

namespace {

class GeometryCli : public CliFixture {
  protected:
    std::vector<std::string> args(const std::string& out) const {
        return {"compare",
                "--geometry",
                "--models",
                "materials/dipole.bssrdf",
                "materials/better_dipole.bssrdf",
                "--shapes",
                "slab:t=0.5,w=6",
                "corner:s=3",
                "--presets",
                "Skin1",
                "--size",
                "16",
                "--reference-spp",
                "16",
                "--model-spp",
                "16",
                "--out",
                out};
    }
};

} // namespace

namespace {
// The cells of a model's row in report.md's summary ("| dipole | 42.2 % (0) | 34 % (3) |")
// and of its line in what `compare --geometry` printed (columns two spaces or more apart):
// the same, in the same order.
std::vector<std::string> summaryCells(const std::string& text, const std::string& model,
                                      bool markdown) {
    const size_t start = markdown ? text.find("## Summary") : text.find("median rel_l2 over");
    if (start == std::string::npos) return {};
    std::istringstream in(text.substr(start));
    const std::regex sep(markdown ? "\\s*\\|\\s*" : "\\s{2,}");
    for (std::string line; std::getline(in, line);) {
        if (markdown && line.rfind("| " + model + " |", 0) != 0) continue;
        if (!markdown && line.rfind(model + "  ", 0) != 0) continue;
        std::vector<std::string> cells;
        for (std::sregex_token_iterator it(line.begin(), line.end(), sep, -1), end; it != end; ++it)
            if (!it->str().empty()) cells.push_back(*it);
        return cells; // the model's name first
    }
    return {};
}
} // namespace

TEST_F(GeometryCli, WritesScoresReportsAndPicturesCachesReferencesAndFailsIfWorse) {
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    RunResult r = run(args("g1"));
    ASSERT_EQ(r.code, 0) << describe(args("g1"), r);
    EXPECT_NE(r.output.find("6 references traced, 0 from the cache"), std::string::npos)
        << r.output;
    const nlohmann::json j = nlohmann::json::parse(readText(dir() / "g1/scores.json"));
    EXPECT_EQ(j["schema"], "bssrdf-workbench-geometry-scores");
    EXPECT_EQ(j["version"], 1);
    EXPECT_EQ(j["settings"]["size"], 16);
    ASSERT_EQ(j["shapes"].size(), 2u);
    EXPECT_EQ(j["shapes"][0]["spec"], "slab:t=0.5,w=6,view=front");
    ASSERT_EQ(j["rows"].size(), 12u); // 2 shapes × 3 channels × 2 models
    for (const auto& row : j["rows"]) {
        for (const char* k : {"rel_l2", "rel_l2_se", "mean_ratio", "mean_ratio_se", "ld_mm",
                              "radius_mm", "pixels", "rank", "case"})
            EXPECT_TRUE(row[k].is_number()) << k << " " << row.dump();
        EXPECT_TRUE(row["problem"].is_null());
        EXPECT_GE(row["rank"].get<int>(), 1);
        EXPECT_GT(row["pixels"].get<int>(), 20);
        // the models are off (Skin1's blue, albedo 0.68, loses half of it at the corner's
        // oblique faces), but by factors, not orders of magnitude
        EXPECT_GT(row["mean_ratio"].get<double>(), 0.3) << row.dump();
        EXPECT_LT(row["mean_ratio"].get<double>(), 3.0) << row.dump();
    }
    // rows are in case order, models in the library's (name) order; the first case is the slab's
    // red channel
    EXPECT_EQ(j["rows"][0]["model"], "better_dipole");
    EXPECT_EQ(j["rows"][1]["model"], "dipole");
    EXPECT_EQ(j["rows"][0]["channel"], "R");
    const double ldR = j["rows"][0]["ld_mm"].get<double>();
    EXPECT_NEAR(j["rows"][0]["radius_mm"].get<double>(), 3 * ldR, 1e-9 * ldR); // w = 6 l_d
    const std::string md = readText(dir() / "g1/report.md");
    EXPECT_NE(md.find("| dipole |"), std::string::npos);
    EXPECT_NE(md.find("## corner:s=3"), std::string::npos);
    EXPECT_NE(md.find("images/corner_s-3__Skin1_G.png"), std::string::npos);
    EXPECT_TRUE(fs::exists(dir() / "g1/images/slab_t-0.5_w-6_view-front__Skin1_R.png"));
    EXPECT_NE(readText(dir() / "g1/report.html").find("<table>"), std::string::npos);
    // the summary is printed as the report has it
    for (const char* model : {"better_dipole", "dipole"}) {
        const std::vector<std::string> cells = summaryCells(md, model, true);
        ASSERT_EQ(cells.size(), 3u) << md; // the model, two shapes
        EXPECT_EQ(summaryCells(r.output, model, false), cells) << r.output;
    }
    EXPECT_NE(r.output.find("reports: g1/report.md, g1/report.html"), std::string::npos);

    // again: every reference from the cache, the same scores, not worse than itself
    std::vector<std::string> again = args("g2");
    again.insert(again.end(), {"--baseline", "g1/scores.json", "--fail-if-worse", "5"});
    r = run(again);
    EXPECT_EQ(r.code, 0) << describe(again, r);
    EXPECT_NE(r.output.find("0 references traced, 6 from the cache"), std::string::npos)
        << r.output;
    EXPECT_EQ(readText(dir() / "g2/scores.json"), readText(dir() / "g1/scores.json"));

    // a damaged cache entry (or one from an older version, which is another key) is traced again
    size_t damaged = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir() / "cache"))
        if (e.path().extension() == ".exr" && damaged++ == 0) std::ofstream(e.path()) << "not EXR";
    r = run(args("g3"));
    EXPECT_EQ(r.code, 0) << describe(args("g3"), r);
    EXPECT_NE(r.output.find("1 references traced, 5 from the cache"), std::string::npos)
        << r.output;
    EXPECT_EQ(readText(dir() / "g3/scores.json"), readText(dir() / "g1/scores.json"));

    // a baseline where the row farthest from its reference (in standard errors) was exact
    size_t far = 0;
    auto zOf = [&](size_t i) {
        return j["rows"][i]["rel_l2"].get<double>() / j["rows"][i]["rel_l2_se"].get<double>();
    };
    for (size_t i = 1; i < j["rows"].size(); ++i)
        if (zOf(i) > zOf(far)) far = i;
    ASSERT_GT(zOf(far), 3.0);
    nlohmann::json better = j;
    better["rows"][far]["rel_l2"] = 0.0;
    better["rows"][far]["rel_l2_se"] = 0.0;
    std::ofstream(dir() / "better.json") << better.dump();
    again[again.size() - 3] = "better.json";
    r = run(again);
    EXPECT_EQ(r.code, 1) << describe(again, r);
    EXPECT_NE(r.output.find("worse: " + j["rows"][far]["model"].get<std::string>()),
              std::string::npos)
        << r.output;
}

TEST_F(GeometryCli, AModelThatCannotBeIntegratedIsSaidPerCase) {
    // a model negative everywhere: no radial distribution to sample, said in its rows
    std::string text = readText(fs::path(BW_SOURCE_ROOT) / "materials/dipole.bssrdf");
    const size_t body = text.find("vec3 Bssrdf(");
    ASSERT_NE(body, std::string::npos);
    const size_t open = text.find('{', body);
    text.insert(open + 1, "\n    return vec3(-1.0);\n");
    std::ofstream(dir() / "negative.bssrdf") << text;
    const std::vector<std::string> a = {"compare",
                                        "--geometry",
                                        "--models",
                                        "materials/dipole.bssrdf",
                                        "negative.bssrdf",
                                        "--shapes",
                                        "sphere:r=1",
                                        "--presets",
                                        "Skin1",
                                        "--size",
                                        "12",
                                        "--reference-spp",
                                        "4",
                                        "--model-spp",
                                        "4",
                                        "--out",
                                        "neg"};
    RunResult r = run(a);
    ASSERT_EQ(r.code, 0) << describe(a, r);
    const nlohmann::json j = nlohmann::json::parse(readText(dir() / "neg/scores.json"));
    ASSERT_EQ(j["rows"].size(), 6u);
    for (const auto& row : j["rows"]) {
        const bool bad = row["model"] == "negative";
        EXPECT_EQ(row["problem"].is_string(), bad) << row.dump();
        EXPECT_EQ(row["rel_l2"].is_null(), bad) << row.dump();
        EXPECT_EQ(row["rank"].get<int>(), bad ? 0 : 1) << row.dump();
    }
    EXPECT_NE(r.output.find("negative"), std::string::npos);
    EXPECT_NE(readText(dir() / "neg/report.md").find("no image"), std::string::npos);
    // no score on the shape: "—" in the report's summary and in the printed one
    const std::vector<std::string> cells =
        summaryCells(readText(dir() / "neg/report.md"), "negative", true);
    EXPECT_EQ(cells, (std::vector<std::string>{"negative", "—"}));
    EXPECT_EQ(summaryCells(r.output, "negative", false), cells) << r.output;
}

TEST_F(GeometryCli, BadInputsNameTheirArgument) {
    const auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = args("bad");
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    expectFailure(with({"--shapes", "slab:t=50"}),
                  {"--shapes", "slab: t = 50 is out of range [0.05, 20] (thickness, in l_d)"});
    expectFailure(with({"--shapes", "teapot"}), {"--shapes", "unknown shape 'teapot'"});
    expectFailure(with({"--presets", "Marbel"}), {"--presets", "Marbel"});
    expectFailure(with({"--theta-i", "30"}), {"--theta-i"});
    expectFailure(with({"--sampling", "magic"}), {"--sampling", "magic"});
    expectFailure(with({"--pictures", "X"}), {"--pictures", "'X'"});
    expectFailure(with({"--shard", "3/2"}), {"--shard", "3/2"});
    expectFailure(with({"--size", "4"}), {"--size"});
    expectFailure(with({"--fail-if-worse", "5"}), {"--fail-if-worse", "needs --baseline"});
    expectFailure({"merge", "--geometry", "nowhere", "--out", "m"}, {"nowhere/shard.json"});
    expectFailure(with({"--paths", "100000"}), {"--paths", "leave out --paths"});
    // a baseline that cannot be read is refused before any image is traced
    std::ofstream(dir() / "radial.json") << R"({"schema": "bssrdf-workbench-scores", "rows": []})";
    std::ofstream(dir() / "broken.json")
        << R"({"schema": "bssrdf-workbench-geometry-scores", "rows": [{"model": "x"}]})";
    for (const auto& [file, says] : std::vector<std::pair<std::string, std::string>>{
             {"missing.json", "cannot open"},
             {"radial.json", "--baseline: not a bssrdf-workbench-geometry-scores file"},
             {"broken.json", "--baseline: row 1: "}}) {
        const std::vector<std::string> a = with({"--baseline", (dir() / file).string()});
        const RunResult r = run(a);
        EXPECT_NE(r.code, 0) << describe(a, r);
        EXPECT_NE(r.output.find(file), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(says), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("reference"), std::string::npos) << "traced first\n" << r.output;
    }
    // the suite's options without --geometry are refused, not ignored by the radial scoreboard
    for (const auto& [flag, value] :
         std::vector<std::pair<std::string, std::string>>{{"--shapes", "sphere"},
                                                          {"--size", "16"},
                                                          {"--reference-spp", "4"},
                                                          {"--model-spp", "4"},
                                                          {"--sampling", "uniform"},
                                                          {"--pictures", "G"}})
        expectFailure({"compare", "--presets", "Marble", flag, value, "--out", "radial"},
                      {flag + " requires --geometry"});
    EXPECT_FALSE(fs::exists(dir() / "bad/scores.json"));
    EXPECT_FALSE(fs::exists(dir() / "radial"));
}

// The shards of a run, run by GNU parallel as a user would, merge into the single process's
// scores.json byte for byte; a missing shard, a repeated one or one of another run is refused.
TEST_F(GeometryCli, ShardsRunByGnuParallelMergeIntoTheSameScores) {
    ASSERT_EQ(std::system("command -v parallel >/dev/null"), 0)
        << "GNU parallel (Debian package parallel) is needed: ./run installs it";
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    RunResult r = run(args("one"));
    ASSERT_EQ(r.code, 0) << describe(args("one"), r);
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache-shards").c_str(), 1);
    std::string shardArgs;
    for (const std::string& s : args("s{}"))
        shardArgs += " '" + s + "'";
    const std::string cmd = "cd '" + dir().string() + "' && parallel -j 3 --halt now,fail=1 '" +
                            BW_EXE + "' --root '" + BW_SOURCE_ROOT + "'" + shardArgs +
                            " --shard {}/3 ::: 1 2 3 >parallel.log 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << readText(dir() / "parallel.log");
    const std::vector<std::string> merge = {"merge", "--geometry", "s1",    "s2",
                                            "s3",    "--out",      "merged"};
    r = run(merge);
    ASSERT_EQ(r.code, 0) << describe(merge, r);
    EXPECT_EQ(readText(dir() / "merged/scores.json"), readText(dir() / "one/scores.json"));
    EXPECT_EQ(readText(dir() / "merged/report.md"), readText(dir() / "one/report.md"));
    EXPECT_TRUE(fs::exists(dir() / "merged/images/corner_s-3__Skin1_B.png"));
    expectFailure({"merge", "--geometry", "s1", "s3", "--out", "m2"}, {"missing shards of 3: 2"});
    // options of other merges are refused, not ignored
    expectFailure({"merge", "s1", "s2", "s3", "--no-plots", "--out", "m5"},
                  {"--no-plots: geometry shards bring their own pictures"});
    expectFailure({"merge", "s1", "s2", "s3", "--csv", "x.csv", "--out", "m5"},
                  {"--csv: compare shards merge into --out only"});
    expectFailure({"merge", "--geometry", "s1", "s1", "s2", "s3", "--out", "m3"},
                  {"shard 1/3 is also in s1"});
    std::vector<std::string> other = args("o2");
    other[other.size() - 9] = "Marble"; // the preset
    other.insert(other.end(), {"--shard", "2/3"});
    r = run(other);
    ASSERT_EQ(r.code, 0) << describe(other, r);
    expectFailure({"merge", "--geometry", "s1", "o2", "s3", "--out", "m4"},
                  {"o2/shard.json", "a shard of another run"});
}
