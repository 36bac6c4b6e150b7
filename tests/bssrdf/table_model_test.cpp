// Table models (bssrdf/table_model.h): a `.bssrdf` whose `table` section names a CSV radial
// profile or path-traced `.bwtable` files. Checked: the CSV reader and every bad input it lists
// (header, non-numbers, NaN, negative values, radii out of order, too few rows, missing file),
// the section's own errors, truncated tables, and — on real GL —
// that the generated Bssrdf() interpolates the data linearly in r and is 0 beyond it, for a
// CSV and for a table path-traced in the test, which also carries its medium per channel.
#include "../support/gl_fixture.h"
#include "bssrdf/program_library.h"
#include "bssrdf/table_model.h"
#include "core/core.h"
#include "pathtrace/bssrdf_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace {
namespace fs = std::filesystem;

class TableModel : public ::testing::Test {
  protected:
    void SetUp() override {
        m_root = testsupport::makeProjectRoot("tablemodel", {});
        m_dir = m_root / "materials";
    }
    void TearDown() override { fs::remove_all(m_root); }
    void write(const std::string& name, const std::string& text) {
        std::ofstream(m_dir / name, std::ios::binary) << text;
    }
    // A model whose table section holds `directive`.
    std::string model(const std::string& directive) {
        return "analytic radial no_wi no_wo\n# a table model\n::begin table\n" + directive +
               "\n::end table\n";
    }
    bssrdf::Model load(const std::string& name) {
        return bssrdf::loadModel(m_dir / name, "materials/" + name);
    }
    void expectError(const std::string& name, const std::vector<std::string>& fragments) {
        try {
            load(name);
            ADD_FAILURE() << name << " loaded";
        } catch (const core::Error& e) {
            for (const auto& f : fragments)
                EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
                    << "'" << f << "' not in: " << e.what();
        }
    }
    fs::path m_root, m_dir;
};

const char* kProfile = "# measured, per unit power entering\n"
                       "r_mm,R,G,B\n"
                       "0,4,2,1\n"
                       "1,2,1,0.5\n"
                       "3,0,0.5,0.25\n";

TEST_F(TableModel, CsvProfileReadsAndRejectsBadFiles) {
    write("p.csv", kProfile);
    const auto t = bssrdf::readProfileCsv(m_dir / "p.csv", "p.csv");
    ASSERT_EQ(t.r.size(), 3u);
    EXPECT_EQ(t.rgb[1][2], 0.5);
    auto bad = [&](const std::string& text, int line, const std::string& fragment) {
        write("bad.csv", text);
        try {
            bssrdf::readProfileCsv(m_dir / "bad.csv", "materials/bad.csv");
            ADD_FAILURE() << "accepted: " << fragment;
        } catch (const core::Error& e) {
            const std::string where = "materials/bad.csv:" + std::to_string(line);
            if (line > 0) {
                EXPECT_NE(std::string(e.what()).find(where), std::string::npos) << e.what();
            }
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    bad("r,R,G,B\n0,1,1,1\n", 1, "header");
    bad("r_mm,R,G,B\n0,1,1,1\n1,x,1,1\n", 3, "'x' is not a number");
    bad("r_mm,R,G,B\n0,1,1,1\n1,nan,1,1\n", 3, "R must be finite");
    bad("r_mm,R,G,B\n0,1,1,1\n1,1,-2,1\n", 3, "G must be finite and >= 0");
    bad("r_mm,R,G,B\n0,1,1,1\n0,1,1,1\n", 3, "increase");
    bad("r_mm,R,G,B\n-1,1,1,1\n0,1,1,1\n", 2, "r_mm");
    bad("r_mm,R,G,B\n0,1,1\n", 2, "4 numbers");
    bad("r_mm,R,G,B\n0,1,1,1\n", 0, "at least 2 rows");
    bad("", 0, "empty");
    bad("r_mm,R,G,B\n0,1,1,1\n\xff\xfe,1,1,1\n", 3, "UTF-8");
}

TEST_F(TableModel, SectionErrorsNameTheModelLine) {
    write("p.csv", kProfile);
    write("a.bssrdf", model("profile p.csv\nprofile p.csv"));
    expectError("a.bssrdf", {"materials/a.bssrdf:5", "one directive"});
    write("b.bssrdf", model("lookup p.csv"));
    expectError("b.bssrdf", {"materials/b.bssrdf:4", "unknown table directive 'lookup'"});
    write("c.bssrdf", model("# nothing"));
    expectError("c.bssrdf", {"materials/c.bssrdf", "empty table section"});
    write("d.bssrdf", model("profile /etc/p.csv"));
    expectError("d.bssrdf", {"relative to the model file"});
    write("e.bssrdf", model("profile missing.csv"));
    expectError("e.bssrdf", {"materials/missing.csv"});
    write("f.bssrdf", model("profile p.csv") +
                          "::begin shader\nvec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { "
                          "return vec3(0.0); }\n::end shader\n");
    expectError("f.bssrdf", {"materials/f.bssrdf:3", "not both"});
    write("g.bssrdf", model("estimate a.bwtable b.bwtable"));
    expectError("g.bssrdf", {"one table (all channels) or three"});
}

TEST_F(TableModel, CsvModelInterpolatesOnTheGpu) {
    testsupport::context();
    write("p.csv", kProfile);
    write("measured.bssrdf", model("profile p.csv"));
    bssrdf::ModelLibrary lib(m_root, {"pencil_profile.comp"});
    lib.scanAll();
    bssrdf::ModelEntry* e = lib.find("measured");
    ASSERT_NE(e, nullptr);
    ASSERT_FALSE(e->problem) << e->problem->text();
    ASSERT_TRUE(e->usable());
    ASSERT_EQ(e->model->dataFiles.size(), 1u);
    const std::vector<double> radii = {0.0, 0.5, 1.0, 2.0, 2.9, 3.5};
    const auto prof = bssrdf::evaluateProfile(e->programs.at("pencil_profile.comp").id(), *e->model,
                                              e->values, bssrdf::Builtins{}, radii);
    const double expect[6][3] = {{4, 2, 1},        {3, 1.5, 0.75},       {2, 1, 0.5},
                                 {1, 0.75, 0.375}, {0.1, 0.525, 0.2625}, {0, 0, 0}};
    for (size_t i = 0; i < radii.size(); ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(prof.value[i][c], expect[i][c], 1e-5) << "r " << radii[i] << " c " << c;
    // The data file is watched: a new profile reloads the model.
    write("p.csv", "r_mm,R,G,B\n0,8,8,8\n3,8,8,8\n");
    EXPECT_TRUE(lib.onFilesChanged({m_dir / "p.csv"}));
    e = lib.find("measured");
    const auto again = bssrdf::evaluateProfile(e->programs.at("pencil_profile.comp").id(),
                                               *e->model, e->values, bssrdf::Builtins{}, {1.0});
    EXPECT_NEAR(again.value[0][0], 8.0, 1e-5);
    // A broken profile keeps the last good model and names the file and line.
    write("p.csv", "r_mm,R,G,B\n0,8,8,8\n3,-1,8,8\n");
    lib.onFilesChanged({m_dir / "p.csv"});
    e = lib.find("measured");
    ASSERT_TRUE(e->problem);
    EXPECT_NE(e->problem->text().find("materials/p.csv:3"), std::string::npos)
        << e->problem->text();
    EXPECT_TRUE(e->usable());
}

TEST_F(TableModel, EstimateTableModelCarriesItsMedium) {
    testsupport::context();
    const pathtrace::Medium medium{0.1, 1.0, 0.0, 1.3};
    pathtrace::EstimateSettings s;
    s.thetaIDeg = {0.0, 45.0};
    s.bins.rBins = 6;
    s.bins.rMaxMm = 3;
    s.bins.thetaSBins = 2;
    s.paths = 20000;
    const auto table = pathtrace::estimateTable(medium, s, 0, pathtrace::chunkCount(s));
    pathtrace::writeTable(m_dir / "t.bwtable", table);
    write("traced.bssrdf", model("estimate t.bwtable"));
    const bssrdf::Model m = load("traced.bssrdf");
    ASSERT_EQ(m.tableMedia.size(), 3u);
    EXPECT_EQ(m.tableMedia[2].sigmaA, 0.1);
    EXPECT_EQ(m.tableMedia[0].eta, 1.3);

    bssrdf::ModelLibrary lib(m_root, {"pencil_profile.comp"});
    lib.scanAll();
    bssrdf::ModelEntry* e = lib.find("traced");
    ASSERT_NE(e, nullptr);
    ASSERT_TRUE(e->usable());
    // At a bin centre (normal incidence) the model is the θs-averaged R of θi = 0 over 1 − R_sp.
    const auto slice = table.slice(0);
    const double rMid = 0.25 + 0.5 * 2; // bin 2
    const auto prof = bssrdf::evaluateProfile(e->programs.at("pencil_profile.comp").id(), *e->model,
                                              e->values, bssrdf::Builtins{}, {rMid});
    const double expect = 0.5 * (slice.R[4] + slice.R[5]) / (1 - slice.specular);
    EXPECT_NEAR(prof.value[0][1], expect, 1e-6 * expect);

    // Two θs bins and two angles make it an oblique (non-radial) model, whose value in the
    // pencil plot (normal incidence) is still that θs mean (oblique_table_test.cpp).
    EXPECT_FALSE(e->model->attrs.radial);
    // A truncated file: an error naming the table.
    const std::string bytes = core::readFile(m_dir / "t.bwtable");
    write("cut.bwtable", bytes.substr(0, bytes.size() / 2));
    write("cut.bssrdf", model("estimate cut.bwtable"));
    expectError("cut.bssrdf", {"cut.bwtable", "truncated"});
}

} // namespace
