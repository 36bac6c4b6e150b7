// End-to-end tests of `estimate` and `merge` (app/cli/estimate_commands.h) on the real executable:
// the table and its CSVs, shards merged into bitwise the file of one run, and every bad input the
// reference issue lists — incidence angles, bin counts, shard specs, unwritable outputs, and
// table files that are truncated, of another version (version 1 still reads), not tables, with a
// NaN in the header or a negative value, or of another medium — each failing with a message naming
// the argument or file.
#include "../support/cli_fixture.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {
namespace fs = std::filesystem;
using namespace clitest;

class Estimate : public CliFixture {
  protected:
    // `estimate` with a small default setup; a flag in `extra` replaces the default's.
    std::vector<std::string> estimate(std::vector<std::string> extra) {
        const std::vector<std::pair<std::string, std::string>> base = {
            {"--theta-i", "0,60"},   {"--r-bins", "5"},    {"--rmax", "3"},
            {"--theta-s-bins", "2"}, {"--paths", "20000"}, {"--sigma-a", "0.2"}};
        std::vector<std::string> a = {"estimate"};
        for (const auto& [flag, value] : base)
            if (std::find(extra.begin(), extra.end(), flag) == extra.end()) {
                a.push_back(flag);
                a.push_back(value);
            }
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    }
    std::string bytes(const std::string& name) { return readText(m_dir.path() / name); }
    void write(const std::string& name, const std::string& data) {
        std::ofstream(m_dir.path() / name, std::ios::binary) << data;
    }
};

TEST_F(Estimate, WritesTableAndCsvAndShardsMergeBitwise) {
    // 40000 paths: three chunks of 16384, one per shard.
    RunResult r = run(estimate({"--paths", "40000", "--dir-bins", "2x3", "--out", "full.bwtable",
                                "--csv", "r.csv", "--csv-dir", "s.csv"}));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("theta_i 60: 40000 paths"), std::string::npos) << r.output;
    const std::string csv = bytes("r.csv");
    EXPECT_EQ(csv.rfind("theta_i_deg,r_lo_mm,r_hi_mm,theta_s_lo_deg,theta_s_hi_deg,R,stderr\n", 0),
              0u);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 2 * 5 * 2);
    const std::string dirCsv = bytes("s.csv");
    EXPECT_EQ(dirCsv.rfind("theta_i_deg,r_lo_mm,r_hi_mm,theta_s_lo_deg,theta_s_hi_deg,theta_o_deg,"
                           "phi_o_deg,solid_angle_sr,S,stderr\n",
                           0),
              0u);
    EXPECT_EQ(std::count(dirCsv.begin(), dirCsv.end(), '\n'), 1 + 2 * 5 * 2 * 6);
    for (int k = 1; k <= 3; ++k) {
        r = run(
            estimate({"--paths", "40000", "--dir-bins", "2x3", "--shard", std::to_string(k) + "/3",
                      "--out", "s" + std::to_string(k) + ".bwtable"}));
        ASSERT_EQ(r.code, 0) << r.output;
    }
    r = run({"merge", "s2.bwtable", "s3.bwtable", "s1.bwtable", "--out", "m.bwtable"});
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(bytes("m.bwtable") == bytes("full.bwtable"));
    // Two of three shards: a partial table, said so.
    r = run({"merge", "s1.bwtable", "s3.bwtable", "--out", "p.bwtable"});
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("covers 2 of the run's 3 chunks"), std::string::npos) << r.output;
    // The same shard twice overlaps.
    expectFailure({"merge", "s1.bwtable", "s1.bwtable", "--out", "x.bwtable"},
                  {"s1.bwtable", "overlap"});
    expectFailure({"merge", "s1.bwtable", "--no-plots", "--out", "x.bwtable"},
                  {"--no-plots: only for folders of `compare --shard`"});
    // Another medium, or other bins, cannot be merged.
    ASSERT_EQ(run(estimate({"--paths", "40000", "--dir-bins", "2x3", "--sigma-a", "0.3", "--shard",
                            "2/3", "--out", "o.bwtable"}))
                  .code,
              0);
    expectFailure({"merge", "s1.bwtable", "o.bwtable", "--out", "x.bwtable"},
                  {"o.bwtable", "medium", "sigma_a"});
    ASSERT_EQ(run(estimate({"--paths", "40000", "--shard", "2/3", "--out", "b.bwtable"})).code, 0);
    expectFailure({"merge", "s1.bwtable", "b.bwtable", "--out", "x.bwtable"},
                  {"b.bwtable", "settings.bins"});
}

// `slab --shard K/N` writes tables; `merge --slab-csv` gives the very CSV rows of one `slab` run.
TEST_F(Estimate, SlabShardsMergeIntoTheSlabCsv) {
    const std::vector<std::string> base = {"slab", "--paths",   "40000", "--bins",
                                           "30",   "--sigma-a", "0.1",   "--estimator"};
    for (const char* est : {"implicit", "connections"}) {
        auto args = base;
        args.push_back(est);
        auto with = [&](std::vector<std::string> extra) {
            auto a = args;
            a.insert(a.end(), extra.begin(), extra.end());
            return a;
        };
        RunResult r = run(with({"--out", "one.csv"}));
        ASSERT_EQ(r.code, 0) << r.output;
        for (int k = 1; k <= 3; ++k) {
            r = run(with({"--shard", std::to_string(k) + "/3", "--out",
                          "p" + std::to_string(k) + ".bwtable"}));
            ASSERT_EQ(r.code, 0) << r.output;
        }
        r = run({"merge", "p1.bwtable", "p2.bwtable", "p3.bwtable", "--out", "all.bwtable",
                 "--slab-csv", "merged.csv"});
        ASSERT_EQ(r.code, 0) << r.output;
        auto body = [](const std::string& csv) { return csv.substr(csv.find("r_mm,")); };
        auto line = [](const std::string& csv, const std::string& key) {
            const size_t at = csv.find(key);
            return at == std::string::npos ? std::string()
                                           : csv.substr(at, csv.find('\n', at) - at);
        };
        const std::string one = bytes("one.csv"), merged = bytes("merged.csv");
        EXPECT_EQ(body(merged), body(one)) << est;
        for (const char* key : {"# total_Rd ", "# absorbed ", "# estimator ", "# energy_check "})
            EXPECT_EQ(line(merged, key), line(one, key)) << est;
        EXPECT_FALSE(line(one, "# total_Rd ").empty());
    }
    // A table that is not slab-shaped cannot become the slab CSV.
    ASSERT_EQ(run(estimate({"--out", "wide.bwtable"})).code, 0);
    expectFailure({"merge", "wide.bwtable", "--out", "x.bwtable", "--slab-csv", "x.csv"},
                  {"--slab-csv", "not a slab table"});
    expectFailure({"slab", "--paths", "1000", "--shard", "3/2", "--out", "x.bwtable"}, {"--shard"});
    expectFailure({"slab", "--paths", "1000", "--gpu", "--shard", "1/2", "--out", "x.bwtable"},
                  {"--shard", "CPU"});
}

// Counts take scientific notation; a command line the parser refuses exits 2 with
// `error: <argument>: message` (not the parser's own exit codes).
TEST_F(Estimate, CountsTakeScientificNotationAndUsageErrorsHaveOneForm) {
    RunResult r = run({"slab", "--paths", "2e4", "--bins", "1e1", "--out", "s.csv"});
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(bytes("s.csv").find("# paths 20000"), std::string::npos);
    r = run(estimate({"--paths", "1.5e4", "--out", "t.bwtable"}));
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("theta_i 0: 15000 paths"), std::string::npos) << r.output;
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"slab", "--paths", "1.5", "--out", "x.csv"},
             {"slab", "--paths", "1e30", "--out", "x.csv"},
             {"slab", "--paths", "many", "--out", "x.csv"},
             {"estimate", "--r-bins", "2.5", "--out", "x.bwtable"}}) {
        r = run(args);
        EXPECT_EQ(r.code, 2) << describe(args, r);
        EXPECT_EQ(r.output.rfind("error: " + args[1] + ": ", 0), 0u) << describe(args, r);
    }
    r = run({"estimate", "--out", "x.bwtable", "--no-such-flag"});
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_EQ(r.output.rfind("error: ", 0), 0u) << r.output;
    EXPECT_NE(r.output.find("--no-such-flag"), std::string::npos) << r.output;
    r = run({"slab", "--help"});
    EXPECT_EQ(r.code, 0) << r.output;
}

// Every command checks its outputs before any work: the folder must take a file, and binary
// formats need their extension (an EXR named .png was written before).
using CliOutputs = Estimate;
TEST_F(CliOutputs, CheckedBeforeAnyWork) {
    const std::string bunny = std::string(BW_SOURCE_ROOT) + "/third_party/bunny/bunny.obj";
    const std::string dipole = std::string(BW_SOURCE_ROOT) + "/materials/dipole.bssrdf";
    expectFailure({"sphere", "--size", "8x8", "--spp", "1", "--out", "s.png"}, {"--out", ".exr"});
    expectFailure({"mesh", "--mesh", bunny, "--out", "m.EXRX"}, {"--out", ".exr"});
    expectFailure({"sphere", "--out", "/proc/nope/s.exr"}, {"--out", "/proc/nope/s.exr"});
    expectFailure({"pointcloud", "--mesh", bunny, "--points", "100", "--out", "p.txt"},
                  {"--out", ".ply"});
    expectFailure({"render", "--mesh", bunny, "--model", dipole, "--preset", "Marble", "--out",
                   "r.exr", "--png", "r.jpg"},
                  {"--png", ".png"});
    expectFailure(
        {"render", "--mesh", bunny, "--model", dipole, "--preset", "Marble", "--out", "r.png"},
        {"--out", ".exr"});
    expectFailure({"profile", "--model", dipole, "--preset", "Marble", "--out", "/proc/nope/p.csv"},
                  {"--out", "/proc/nope/p.csv"});
    EXPECT_FALSE(fs::exists(m_dir.path() / "s.png"));
    RunResult r = run({"sphere", "--size", "8x8", "--spp", "1", "--out", "S.EXR"});
    EXPECT_EQ(r.code, 0) << r.output; // the extension is case-insensitive
}

// `record` refuses to replace a capture without --force, and a failed record leaves nothing.
TEST_F(CliOutputs, RecordNeverOverwritesSilentlyNorLeavesHalfACapture) {
    const std::string dipole = std::string(BW_SOURCE_ROOT) + "/materials/dipole.bssrdf";
    const std::vector<std::string> rec = {"record", "--name", "c",     "--model",
                                          dipole,   "--out",  "caps/c"};
    RunResult r = run(rec);
    ASSERT_EQ(r.code, 0) << r.output;
    ASSERT_TRUE(fs::exists(m_dir.path() / "caps/c/manifest.json"));
    const std::string manifest = bytes("caps/c/manifest.json");
    expectFailure(rec, {"--out", "caps/c", "--force"});
    EXPECT_EQ(bytes("caps/c/manifest.json"), manifest);
    auto forced = rec;
    forced.push_back("--force");
    r = run(forced);
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(m_dir.path() / "caps/c/manifest.json"));
    // A record that fails (an open mesh for the lit spheres) leaves no folder of any name.
    std::ofstream(m_dir.path() / "open.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    expectFailure({"record", "--name", "bad", "--model", dipole, "--out", "caps/bad",
                   "--lit-spheres", "8", "--lit-mesh", (m_dir.path() / "open.obj").string()},
                  {"open"});
    size_t entries = 0;
    for (const auto& e : fs::directory_iterator(m_dir.path() / "caps")) {
        ++entries;
        EXPECT_EQ(e.path().filename(), "c") << "left behind: " << e.path();
    }
    EXPECT_EQ(entries, 1u);
}

// `record --from-request` (the GUI's recordings): a missing or malformed request is an error
// naming the file, and nothing is written.
TEST_F(CliOutputs, RecordFromABadRequestNamesItAndWritesNothing) {
    expectFailure({"record", "--name", "r", "--out", "caps/r", "--from-request",
                   (m_dir.path() / "missing.json").string()},
                  {"missing.json", "cannot open"});
    std::ofstream(m_dir.path() / "bad.json") << R"({"formatVersion": 1})";
    expectFailure({"record", "--name", "r", "--out", "caps/r", "--from-request",
                   (m_dir.path() / "bad.json").string()},
                  {"bad.json", "missing key 'name'"});
    EXPECT_FALSE(fs::exists(m_dir.path() / "caps/r"));
}

// `record --slice-*`: a bad incidence angle is refused naming the flag, and nothing is left.
TEST_F(CliOutputs, RecordRefusesABadSliceAngle) {
    const std::string dipole = std::string(BW_SOURCE_ROOT) + "/materials/dipole.bssrdf";
    for (const char* angle : {"90", "-1"})
        expectFailure({"record", "--name", "s", "--model", dipole, "--out", "caps/s",
                       "--slice-paths", "100", "--slice-theta-i", angle},
                      {"--slice-theta-i", "[0, 90)"});
    expectFailure({"record", "--name", "s", "--model", dipole, "--out", "caps/s", "--slice-paths",
                   "100", "--slice-theta-i", "nan"},
                  {"--slice-theta-i", "finite"});
    EXPECT_FALSE(fs::exists(m_dir.path() / "caps/s"));
}

// `record`'s stage options need what they build on: each refusal names its flag, a missing lit
// mesh is named under its own flag, and nothing is left.
TEST_F(CliOutputs, RecordRefusesStageOptionsWithoutWhatTheyNeed) {
    const std::string dipole = std::string(BW_SOURCE_ROOT) + "/materials/dipole.bssrdf";
    const std::vector<std::string> rec = {"record", "--name", "t",     "--model",
                                          dipole,   "--out",  "caps/t"};
    auto with = [&](std::vector<std::string> extra) {
        extra.insert(extra.begin(), rec.begin(), rec.end());
        return extra;
    };
    expectFailure(with({"--hybrid"}), {"--hybrid", "needs --texture-space"});
    expectFailure(with({"--texture-space", "64"}), {"--texture-space", "needs --scene-points"});
    expectFailure(with({"--scene-points", "500", "--texture-space", "100"}),
                  {"--texture-space", "power of two"});
    // Each option of a stage another option turns on is refused without it (a --lit-mesh
    // without --lit-spheres was ignored, and the capture recorded without what was asked for).
    const std::vector<std::array<const char*, 3>> needs = {
        {"--lit-mesh", "third_party/bunny/bunny.obj", "--lit-spheres"},
        {"--lit-sampling", "disk", "--lit-spheres"},
        {"--lit-axes", "pbrt", "--lit-spheres"},
        {"--reference-bins", "50", "--reference-paths"},
        {"--slice-theta-i", "30", "--slice-paths"},
        {"--scene-mesh", "third_party/bunny/bunny.obj", "--scene-points"},
        {"--scene-width", "64", "--scene-points"},
        {"--scene-height", "64", "--scene-points"},
        {"--trace-x", "3", "--scene-points"},
        {"--trace-y", "3", "--scene-points"},
        {"--texture-samples", "64", "--texture-space"},
        {"--texture-sets", "4", "--texture-space"}};
    for (const auto& [flag, value, stage] : needs)
        expectFailure(with({flag, value}), {std::string(flag) + " requires " + stage});
    expectFailure(with({"--lit-spheres", "8", "--lit-mesh", "no/such.obj"}),
                  {"no/such.obj", "--lit-mesh: no such file"});
    EXPECT_FALSE(fs::exists(m_dir.path() / "caps/t"));
}

TEST_F(Estimate, RejectsBadArguments) {
    const std::vector<std::string> out = {"--out", "t.bwtable"};
    auto with = [&](std::vector<std::string> extra) {
        extra.insert(extra.end(), out.begin(), out.end());
        return estimate(extra);
    };
    expectFailure(with({"--theta-i", "90"}), {"--theta-i", "[0, 90)"});
    expectFailure(with({"--theta-i", "-5"}), {"--theta-i", "[0, 90)"});
    expectFailure(with({"--theta-i", "10,abc"}), {"--theta-i"});
    expectFailure(with({"--theta-i", "nan"}), {"--theta-i"});
    expectFailure(with({"--r-bins", "0"}), {"--r-bins", "between 1 and"});
    expectFailure(with({"--theta-s-bins", "100000"}), {"--theta-s-bins", "between 1 and 10000"});
    expectFailure(with({"--dir-bins", "0"}), {"--dir-bins"});
    expectFailure(with({"--dir-bins", "3x"}), {"--dir-bins"});
    expectFailure(with({"--dir-bins", "2000"}), {"--dir-bins"});
    expectFailure(with({"--rmax", "-1"}), {"--rmax", "got -1"});
    expectFailure(with({"--shard", "0/3"}), {"--shard"});
    expectFailure(with({"--shard", "4/3"}), {"--shard"});
    expectFailure(with({"--shard", "two"}), {"--shard"});
    expectFailure(with({"--single-only", "--multiple-only"}), {"--single-only"});
    expectFailure(with({"--gpu", "--shard", "1/2"}), {"--shard", "CPU"});
    expectFailure(with({"--gpu", "--split-levels", "2"}), {"--split-levels: the GL tracer"});
    expectFailure(with({"--gpu", "--exit-samples", "4"}), {"--exit-samples: the GL tracer"});
    // An unwritable output fails at once, before any path is traced.
    RunResult r = run(estimate({"--paths", "100000000", "--out", "/proc/nope/t.bwtable"}));
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("/proc/nope"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("paths/s"), std::string::npos) << "it traced before failing";
    expectFailure(estimate({"--out", "t.bwtable", "--csv", "/proc/nope/r.csv"}), {"--csv"});
}

TEST_F(Estimate, RejectsBadTableFiles) {
    // (expected-value exits switched on, so that an older table's reading as `samples 0` shows)
    ASSERT_EQ(
        run(estimate({"--out", "good.bwtable", "--estimator", "implicit", "--exit-samples", "3"}))
            .code,
        0);
    const std::string good = bytes("good.bwtable");
    const size_t headerEnd = good.find('\n', good.find('\n') + 1);
    ASSERT_NE(headerEnd, std::string::npos);
    auto merge = [&](const std::string& name) {
        return std::vector<std::string>{"merge", name, "--out", "x.bwtable"};
    };
    write("trunc.bwtable", good.substr(0, good.size() - 100));
    expectFailure(merge("trunc.bwtable"), {"trunc.bwtable", "truncated"});
    write("header.bwtable", good.substr(0, headerEnd - 5));
    expectFailure(merge("header.bwtable"), {"header.bwtable"});
    write("long.bwtable", good + "extra");
    expectFailure(merge("long.bwtable"), {"long.bwtable", "after the payload"});
    // Older tables read, and merge, as what their walks did: a version-1 table (before radial
    // splitting) has no `splitting` and no `exits`, a version-2 one no `exits` (before
    // expected-value exits): walks without splitting / tallying their actual exits.
    auto erase = [](std::string& t, const std::string& key) {
        const size_t at = t.find(",\"" + key + "\":{");
        ASSERT_NE(at, std::string::npos) << key;
        t.erase(at, t.find('}', at) + 1 - at);
    };
    auto header = [](const std::string& t) { return t.substr(0, t.find('\n', t.find('\n') + 1)); };
    // The table as version 3 wrote it: no "batches", no paths per batch, no batch sums.
    auto version3 = [&](const std::string& t) {
        const size_t l1 = t.find('\n'), l2 = t.find('\n', l1 + 1);
        nlohmann::json h = nlohmann::json::parse(t.substr(l1 + 1, l2 - l1 - 1));
        EXPECT_EQ(h["version"], 4);
        EXPECT_EQ(h["batches"], 32);
        const size_t nS = 5 * 2, batchSums = 32 * nS, k = h["values"].get<size_t>();
        std::string payload;
        for (size_t a = 0, at = l2 + 1; a < 2; ++a) {
            payload += t.substr(at, 16);
            payload += t.substr(at + 16 + 8 * 32, 32 * (k - batchSums));
            at += 16 + 8 * 32 + 32 * k;
        }
        h.erase("batches");
        h["version"] = 3;
        h["values"] = k - batchSums;
        h["payload_bytes"] = payload.size();
        return t.substr(0, l1 + 1) + h.dump() + "\n" + payload;
    };
    const std::string v3 = version3(good);
    write("v3.bwtable", v3);
    ASSERT_EQ(run(merge("v3.bwtable")).code, 0) << "a table before batch sums reads";
    EXPECT_NE(bytes("x.bwtable").find("\"batches\":0"), std::string::npos)
        << header(bytes("x.bwtable"));
    std::string v1 = v3, v2 = v3;
    erase(v1, "splitting");
    erase(v1, "exits");
    v1.replace(v1.find("\"version\":3"), 11, "\"version\":1");
    write("v1.bwtable", v1);
    ASSERT_EQ(run(merge("v1.bwtable")).code, 0);
    std::string merged = bytes("x.bwtable");
    EXPECT_NE(merged.find("\"splitting\":{\"depth\":3.0,\"levels\":0"), std::string::npos)
        << header(merged);
    EXPECT_NE(merged.find("\"exits\":{\"depth_mfp\":2.0,\"samples\":0}"), std::string::npos)
        << header(merged);
    erase(v2, "exits");
    v2.replace(v2.find("\"version\":3"), 11, "\"version\":2");
    write("v2.bwtable", v2);
    ASSERT_EQ(run(merge("v2.bwtable")).code, 0);
    merged = bytes("x.bwtable");
    EXPECT_NE(merged.find("\"exits\":{\"depth_mfp\":2.0,\"samples\":0}"), std::string::npos)
        << header(merged);
    EXPECT_NE(merged.find("\"splitting\":{\"depth\":3.0,\"levels\":5"), std::string::npos)
        << header(merged);
    std::string v5 = good;
    v5.replace(v5.find("\"version\":4"), 11, "\"version\":5");
    write("v5.bwtable", v5);
    expectFailure(merge("v5.bwtable"), {"v5.bwtable", "version 5", "reads versions 1 to 4"});
    std::string batches = good;
    batches.replace(batches.find("\"batches\":32"), 12, "\"batches\":16");
    write("batches.bwtable", batches);
    expectFailure(merge("batches.bwtable"), {"batches.bwtable", "'batches' must be 32 or 0"});
    // the paths of the batches must add up to the angle's paths: batch 0's count + 1
    std::string batchPaths = good;
    batchPaths[headerEnd + 1 + 16] = char(batchPaths[headerEnd + 1 + 16] + 1);
    write("batchpaths.bwtable", batchPaths);
    expectFailure(merge("batchpaths.bwtable"), {"batchpaths.bwtable", "paths in the batches"});
    std::string nan = good;
    nan.replace(nan.find("\"sigma_a\":0.2"), 13, "\"sigma_a\":NaN");
    write("nan.bwtable", nan);
    expectFailure(merge("nan.bwtable"), {"nan.bwtable", "header"});
    std::string badMedium = good;
    badMedium.replace(badMedium.find("\"eta\":1.3"), 9, "\"eta\":-13");
    write("eta.bwtable", badMedium);
    expectFailure(merge("eta.bwtable"), {"eta.bwtable", "eta"});
    // A negative bin sum of squares: the first squared sum of the first angle (after the two
    // counts, the 32 batch counts and the 10 bin sums), its top byte set.
    std::string neg = good;
    neg[headerEnd + 1 + 16 + 32 * 8 + 10 * 32 + 15] = char(0xff);
    write("neg.bwtable", neg);
    expectFailure(merge("neg.bwtable"), {"neg.bwtable", "negative"});
    std::string paths = good;
    paths[headerEnd + 1] = char(paths[headerEnd + 1] + 1);
    write("paths.bwtable", paths);
    expectFailure(merge("paths.bwtable"), {"paths.bwtable", "paths"});
    write("text.bwtable", "r_mm,R,G,B\n1,2,3,4\n");
    expectFailure(merge("text.bwtable"), {"text.bwtable", "not a BSSRDF table"});
    expectFailure(merge("missing.bwtable"), {"missing.bwtable"});
}

} // namespace

// Ctrl-C: slab and estimate stop, write what they have — marked partial — and exit 130.
TEST_F(Estimate, InterruptWritesThePartialResult) {
    namespace fs = std::filesystem;
    auto with = [](std::vector<std::string> rest) {
        rest.insert(rest.begin(), {BW_EXE, "--root", BW_SOURCE_ROOT});
        return rest;
    };
    clitest::RunResult r = clitest::runCommand(
        with({"slab", "--sigma-a", "0.01", "--sigma-s", "1", "--paths", "1e10", "--out", "s.csv"}),
        dir(), 1500, SIGINT);
    EXPECT_EQ(r.code, 130) << r.output;
    EXPECT_NE(r.output.find("interrupted"), std::string::npos) << r.output;
    const std::string csv = clitest::readText(dir() / "s.csv");
    EXPECT_NE(csv.find("# partial: interrupted after "), std::string::npos) << csv;
    EXPECT_NE(csv.find(" of 10000000000 paths"), std::string::npos) << csv;
    EXPECT_NE(csv.find("r_mm,Rd_per_mm2,stderr"), std::string::npos);

    r = clitest::runCommand(with({"estimate", "--sigma-a", "0.01", "--sigma-s", "1", "--theta-i",
                                  "0", "--paths", "1e10", "--out", "t.bwtable"}),
                            dir(), 1500, SIGINT);
    EXPECT_EQ(r.code, 130) << r.output;
    EXPECT_NE(r.output.find("(partial)"), std::string::npos) << r.output;
    EXPECT_GT(fs::file_size(dir() / "t.bwtable"), 0u);
    // the partial table is a valid table (it merges like a shard)
    r = run({"merge", "t.bwtable", "--out", "m.bwtable", "--csv", "m.csv"});
    EXPECT_EQ(r.code, 0) << r.output;
}
