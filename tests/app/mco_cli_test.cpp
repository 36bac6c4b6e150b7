// MCML files on the command line: `slab --out FILE.mco` writes MCML's format (read back by the
// reader that reproduces MCML's own files byte for byte), and `compare --mco` scores the models
// against MCML output, with per-bin standard errors from two independent runs; bad inputs name
// the file or argument.
#include "../support/cli_fixture.h"
#include "../support/gl_fixture.h"
#include "core/core.h"
#include "gl/gl.h"
#include "gui/gui.h"
#include "gui/panels/panels.h"
#include "pathtrace/mco.h"
#include "pipeline/pencil_series.h"
#include "pipeline/workbench.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace {
class McoCli : public clitest::CliFixture {};

// The r_mm,Rd_per_mm2,stderr rows of a slab CSV.
std::vector<std::array<double, 3>> csvRows(const fs::path& file) {
    std::ifstream in(file);
    std::string line;
    std::vector<std::array<double, 3>> out;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line[0] == 'r') continue;
        std::array<double, 3> v{};
        std::sscanf(line.c_str(), "%lf,%lf,%lf", &v[0], &v[1], &v[2]);
        out.push_back(v);
    }
    return out;
}
} // namespace

TEST_F(McoCli, SlabWritesMcmlsFormatWithTheSameNumbersAsItsCsv) {
    const std::vector<std::string> base = {"slab",  "--sigma-a", "0.02",  "--sigma-s", "2",
                                           "--g",   "0.5",       "--eta", "1.4",       "--paths",
                                           "20000", "--bins",    "40",    "--rmax",    "8"};
    auto with = [&](const std::string& out) {
        std::vector<std::string> a = base;
        a.push_back("--out");
        a.push_back(out);
        return a;
    };
    clitest::RunResult r = run(with("run.mco"));
    ASSERT_EQ(r.code, 0) << describe(with("run.mco"), r);
    ASSERT_EQ(run(with("run.csv")).code, 0);
    const std::string text = clitest::readText(dir() / "run.mco");
    EXPECT_EQ(text.rfind("A1 \t# Version number of the file format.\n", 0), 0u);
    const pathtrace::McoFile m = pathtrace::parseMco(text, "run.mco");
    EXPECT_EQ(pathtrace::formatMco(m), text);
    ASSERT_EQ(m.layers.size(), 1u);
    EXPECT_DOUBLE_EQ(m.layers[0].mua, 0.2); // 1/cm
    EXPECT_DOUBLE_EQ(m.layers[0].mus, 20);
    EXPECT_DOUBLE_EQ(m.layers[0].g, 0.5);
    EXPECT_DOUBLE_EQ(m.layers[0].n, 1.4);
    EXPECT_DOUBLE_EQ(m.dr, 0.02); // 8 mm / 40 bins
    const auto rows = csvRows(dir() / "run.csv");
    ASSERT_EQ(rows.size(), size_t(m.nr));
    for (size_t i = 0; i < rows.size(); ++i)
        EXPECT_NEAR(m.rdR[i] / 100, rows[i][1], 1e-4 * rows[i][1] + 1e-15) << "bin " << i;
    // a shard writes its table of raw sums, never an .mco
    std::vector<std::string> shard = with("part.mco");
    shard.insert(shard.end(), {"--shard", "1/2"});
    expectFailure(shard, {"--out", "raw sums"});
}

TEST_F(McoCli, CompareScoresTheModelsAgainstTwoMcmlRuns) {
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    for (const char* seed : {"1", "2"}) {
        const std::vector<std::string> args = {"slab",
                                               "--sigma-a",
                                               "0.01",
                                               "--sigma-s",
                                               "1",
                                               "--eta",
                                               "1.3",
                                               "--paths",
                                               "40000",
                                               "--bins",
                                               "200",
                                               "--rmax",
                                               "80",
                                               "--seed",
                                               seed,
                                               "--out",
                                               std::string("mcml_") + seed + ".mco"};
        ASSERT_EQ(run(args).code, 0);
    }
    const std::string dipole = (fs::path(BW_SOURCE_ROOT) / "materials/dipole.bssrdf").string();
    const std::vector<std::string> args = {"compare",    "--models", dipole,       "--mco",
                                           "mcml_1.mco", "--mco",    "mcml_2.mco", "--no-plots",
                                           "--out",      "scores"};
    clitest::RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const nlohmann::json j = nlohmann::json::parse(clitest::readText(dir() / "scores/scores.json"));
    ASSERT_EQ(j["rows"].size(), 1u) << j.dump(1);
    const auto& row = j["rows"][0];
    EXPECT_EQ(row["preset"], "mcml_1");
    EXPECT_EQ(row["channel"], "R");
    EXPECT_GT(row["rel_err"].get<double>(), 0.0);
    EXPECT_GT(row["rel_err_se"].get<double>(), 0.0); // from the two runs' difference
    // the classical dipole against the path tracer on this medium is within 30 % in total
    EXPECT_NEAR(row["total_ratio"].get<double>(), 1.0, 0.3);

    // the Scoreboard panel, with the two runs opened as the reference, shows the same row
    testsupport::context();
    auto root = testsupport::makeProjectRoot("mcmlscores", {"dipole.bssrdf"});
    {
        app::Workbench wb(root, false);
        wb.openMcmlReference(dir() / "mcml_1.mco", dir() / "mcml_2.mco");
        app::HeadlessGui gui(wb, 1280, 860);
        gui.ui().shared.show(app::PanelId::Scoreboard);
        for (int k = 0; k < 4; ++k)
            gui.frame();
        const auto& rows = wb.scoreboard().mcmlRows();
        ASSERT_EQ(rows.size(), 1u);
        EXPECT_EQ(wb.scoreboard().mcmlName(), "mcml_1.mco");
        EXPECT_EQ(rows[0].score.model, "dipole");
        EXPECT_EQ(rows[0].score.rank, 1);
        EXPECT_DOUBLE_EQ(rows[0].score.relErr, row["rel_err"].get<double>());
        EXPECT_DOUBLE_EQ(rows[0].score.relErrSe, row["rel_err_se"].get<double>());
        EXPECT_DOUBLE_EQ(rows[0].score.totalRatio, row["total_ratio"].get<double>());
        if (const char* png = std::getenv("BW_MCML_SCORES_PNG"))
            gl::writePng(png, gui.width(), gui.height(), gui.pixels());
        // closing the run removes its table
        wb.clearMcmlReference();
        gui.frame();
        EXPECT_TRUE(wb.scoreboard().mcmlRows().empty());
    }
    fs::remove_all(root);
    ::unsetenv("BSSRDF_WORKBENCH_CACHE");
}

TEST_F(McoCli, BadMcmlInputsNameTheFile) {
    const fs::path samples = fs::path(BW_SOURCE_ROOT) / "tests/data/mcml";
    const std::string dipole = (fs::path(BW_SOURCE_ROOT) / "materials/dipole.bssrdf").string();
    auto cmp = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = {"compare", "--models", dipole, "--out", "o"};
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    expectFailure(cmp({"--mco", (samples / "sample_lhvwang.mco").string()}),
                  {"sample_lhvwang.mco", "needs one layer", "has 3"});
    expectFailure(cmp({"--mco", (samples / "mc-lost-v1-0.mco").string()}), {"mc-lost-v1-0.mco"});
    std::string text = clitest::readText(samples / "sample_kaseykwong.mco");
    text.replace(text.find("RAT #"), 3, "RAX");
    core::writeFile(dir() / "corrupt.mco", text);
    expectFailure(cmp({"--mco", "corrupt.mco"}), {"corrupt.mco", "no section 'RAT'"});
    expectFailure(cmp({"--mco", "missing.mco"}), {"missing.mco", "cannot read"});
    expectFailure(cmp({"--mco", (samples / "sample_lhvwang.mco").string(), "--presets", "Marble"}),
                  {"--mco", "--presets"});
    expectFailure(cmp({"--mco", (samples / "sample_lhvwang.mco").string(), "--theta-i", "45"}),
                  {"--mco", "normal incidence"});
    EXPECT_FALSE(fs::exists(dir() / "o/scores.json"));
}

// File → Open MCML reference: the run's R_d(r) per unit power entering is a pencil-plot series
// (with its ±2σ band when two runs are given); a file that cannot be a reference is an Errors
// entry naming it, and the reference already shown stays.
TEST_F(McoCli, APencilPlotSeriesFromAnMcmlRun) {
    for (const char* seed : {"1", "2"})
        ASSERT_EQ(run({"slab", "--paths", "20000", "--seed", seed, "--out",
                       std::string("run") + seed + ".mco"})
                      .code,
                  0);
    testsupport::context();
    auto root = testsupport::makeProjectRoot("mcmlplot", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.openMcmlReference(dir() / "run1.mco");
    auto mcml = [&]() -> const plot::Series* {
        static std::vector<plot::Series> keep;
        keep = app::plotSeries(wb);
        for (const plot::Series& s : keep)
            if (s.label == "MCML run1.mco") return &s;
        return nullptr;
    };
    const plot::Series* s = mcml();
    ASSERT_NE(s, nullptr);
    const pathtrace::McoFile m = pathtrace::readMco(dir() / "run1.mco");
    EXPECT_EQ(s->x.size(), size_t(m.nr - 1)); // without MCML's overflow bin
    EXPECT_NEAR(s->y[3], m.rdR[3] / 100 / (1 - m.specular), 1e-12);
    EXPECT_TRUE(s->bandLo.empty()); // one run: no standard errors
    wb.openMcmlReference(dir() / "run1.mco", dir() / "run2.mco");
    s = mcml();
    ASSERT_NE(s, nullptr);
    ASSERT_EQ(s->bandLo.size(), s->x.size());
    EXPECT_LT(s->bandLo[3], s->y[3]);
    // a multi-layer MCML file: refused, named, and the reference shown stays
    app::UiShared ui;
    app::openMcmlFile(wb, ui, fs::path(BW_SOURCE_ROOT) / "tests/data/mcml/sample_lhvwang.mco");
    bool named = false;
    for (const auto& e : wb.errors())
        named |= e.text.find("sample_lhvwang.mco") != std::string::npos &&
                 e.text.find("needs one layer") != std::string::npos;
    EXPECT_TRUE(named);
    EXPECT_NE(mcml(), nullptr);
    wb.clearMcmlReference();
    EXPECT_EQ(mcml(), nullptr);
    fs::remove_all(root);
}
