// The artist mappings and the parameterization lab (pipeline/param_mappings.h, params_lab.h,
// cli/params_lab_command.cpp, the Parameters panel's "From albedo and length"):
//   - van de Hulst's albedo inverted by bisection equals the closed-form inverse Blender Cycles
//     prints (constants read from its source), at several g;
//   - the R_dr / l_d mappings give back the asked R_dr (the model's own DiffuseReflectance) and
//     l_d; the mean-free-path mappings give σt = 1/d;
//   - the lab measures what it says: at η = 1, g = 0 its albedo is Chandrasekhar's
//     R(μ0 = 1) = 1 − H(1) √(1 − α) for the α the mapping gave (z-test);
//   - params-lab writes its CSV, report and plots; bad values name their argument;
//   - the panel's section applies σ and measures it without holding the frames.
#include "../pathtrace/stats.h"
#include "../support/cli_fixture.h"
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "core/core.h"
#include "core/statistics.h"
#include "gui/gui.h"
#include "pipeline/model_stages.h"
#include "pipeline/param_mappings.h"
#include "pipeline/params_lab.h"
#include "pipeline/workbench.h"

#include <gtest/gtest.h>
#include <imgui_internal.h>

#include <cmath>
#include <cstdio>

namespace fs = std::filesystem;

TEST(ParamMappings, VanDeHulstEqualsTheClosedFormInverseInCycles) {
    const app::ParamMapping* m = app::findParamMapping("van_de_hulst");
    ASSERT_NE(m, nullptr);
    for (double g : {0.0, 0.5, 0.8})
        for (double A : {0.02, 0.1, 0.3, 0.5, 0.7, 0.9, 0.98}) {
            const material::MaterialParams p =
                app::mapArtistParams(*m, glm::dvec3(A), glm::dvec3(2.0), g, 1.3, nullptr);
            EXPECT_NEAR(p.sigmaS.x + p.sigmaA.x, 0.5, 1e-12); // σt = 1/d
            const double alpha = p.sigmaS.x / 0.5;
            // blender/cycles src/kernel/integrator/subsurface_random_walk.h (d'Eon eq. 53.7)
            const double s =
                4.09712 + 4.20863 * A - std::sqrt(9.59217 + A * (41.6808 + 17.7126 * A));
            const double want = (1 - s * s) / (1 - g * s * s);
            // Cycles prints its constants to 6 digits: s to ~1e-5, α to 1e-5 |dα/ds|
            const double dads = 2 * s * (1 - g) / ((1 - g * s * s) * (1 - g * s * s));
            EXPECT_NEAR(alpha, want, 1e-5 * dads + 1e-7) << "A " << A << " g " << g;
        }
}

// Cycles' anisotropic fit: σt (1 − g) = 1/d, and the single-scattering albedo rises with A from
// near 0 to near 1 at every g (a sign or digit error in its 48 constants would break one of these).
TEST(ParamMappings, CyclesAnisotropicFitIsMonotonicWithTheReducedLength) {
    const app::ParamMapping* m = app::findParamMapping("cycles_anisotropic_fit");
    ASSERT_NE(m, nullptr);
    for (double g : {0.0, 0.3, 0.6, 0.8}) {
        double previous = -1;
        for (int i = 1; i <= 99; ++i) {
            const double A = i / 100.0;
            const material::MaterialParams p =
                app::mapArtistParams(*m, glm::dvec3(A), glm::dvec3(2.0), g, 1.3, nullptr);
            const double alpha = p.sigmaS.x / (p.sigmaA.x + p.sigmaS.x);
            EXPECT_NEAR((p.sigmaA.x + p.sigmaS.x) * (1 - g), 0.5, 1e-12); // σt (1 − g) = 1/d
            // it rises until Cycles' clamp at 0.999999 (the fit passes 1 near A = 0.93)
            if (alpha < 0.999998) {
                EXPECT_GT(alpha, previous) << "A " << A << " g " << g;
            } else {
                EXPECT_GT(A, 0.75) << "clamped already at A " << A << " g " << g;
            }
            previous = alpha;
        }
        const auto at = [&](double A) {
            const material::MaterialParams p =
                app::mapArtistParams(*m, glm::dvec3(A), glm::dvec3(1.0), g, 1.3, nullptr);
            return p.sigmaS.x / (p.sigmaA.x + p.sigmaS.x);
        };
        EXPECT_LT(at(0.01), 0.3) << "g " << g;
        EXPECT_GT(at(0.99), 0.99) << "g " << g;
        // at g = 0 it agrees with van de Hulst's inverse to 1 % in α at mid albedo (two
        // independent fits of the same transport problem)
        if (g == 0) {
            const material::MaterialParams v =
                app::mapArtistParams(*app::findParamMapping("van_de_hulst"), glm::dvec3(0.5),
                                     glm::dvec3(1.0), 0, 1.3, nullptr);
            EXPECT_NEAR(at(0.5), v.sigmaS.x / (v.sigmaA.x + v.sigmaS.x), 0.01);
        }
    }
}

TEST(ParamMappings, RdrLdGivesBackTheAskedReflectanceAndLength) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot(
        "mappings", {"dipole.bssrdf", "better_dipole.bssrdf", "photon_beam_diffusion.bssrdf"});
    app::Workbench wb(root, false);
    const glm::dvec3 A{0.8, 0.5, 0.2}, d{3.0, 1.0, 0.5};
    for (const char* id : {"rdr_ld_dipole", "rdr_ld_better_dipole"}) {
        const app::ParamMapping* m = app::findParamMapping(id);
        const bssrdf::ModelEntry* e = wb.library().find(m->model);
        ASSERT_NE(e, nullptr) << m->model;
        const material::MaterialParams p = app::mapArtistParams(*m, A, d, 0.3, 1.3, e);
        const glm::dvec3 ld = material::diffuseMeanFreePath(p);
        const glm::dvec3 a = material::reducedAlbedo(p);
        const auto rdr = bssrdf::evaluateDiffuseReflectance(
            e->programs.at("invert_rdr.comp").id(), *e->model, e->values, app::builtinsOf(p), {a});
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(ld[c], d[c], 1e-6 * d[c]) << id << " channel " << c;
            EXPECT_NEAR(rdr[0][c], A[c], 1e-4) << id << " channel " << c;
        }
        EXPECT_EQ(p.g, 0.3);
    }
    for (const char* id : {"pbd_mfp", "rdr_mfp_better_dipole"}) {
        const app::ParamMapping* m = app::findParamMapping(id);
        const material::MaterialParams p =
            app::mapArtistParams(*m, A, d, 0.0, 1.3, wb.library().find(m->model));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(p.sigmaA[c] + p.sigmaS[c], 1 / d[c], 1e-9) << id;
        EXPECT_GT(p.sigmaS.x / (p.sigmaA.x + p.sigmaS.x), p.sigmaS.z / (p.sigmaA.z + p.sigmaS.z));
    }
    // out of range: named with the mapping and channel
    try {
        app::mapArtistParams(*app::findParamMapping("van_de_hulst"), {0.5, 1.0, 0.5},
                             glm::dvec3(1.0), 0, 1.3, nullptr);
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("mapping van_de_hulst: albedo channel G"),
                  std::string::npos)
            << e.what();
    }
    try {
        app::mapArtistParams(*app::findParamMapping("exp_albedo_fit"), glm::dvec3(0.5),
                             {1.0, 1.0, 0.0}, 0, 1.3, nullptr);
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("length channel B"), std::string::npos) << e.what();
    }
    fs::remove_all(root);
}

// The lab's albedo is the total diffuse reflectance at normal incidence: with an index-matched
// boundary and isotropic scattering it is Chandrasekhar's 1 − H(1)√(1 − α), H solved here.
TEST(ParamsLab, MeasuresChandrasekharsAlbedoAtAnIndexMatchedBoundary) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("paramslab", {"dipole.bssrdf"});
    ::setenv("BSSRDF_WORKBENCH_CACHE", (root / "cache").c_str(), 1);
    app::Workbench wb(root, false);
    app::LabSettings s;
    s.mappings = {"van_de_hulst", "exp_albedo_fit"};
    s.albedos = {0.3, 0.7};
    s.etas = {1.0};
    s.gs = {0.0};
    s.paths = 40000;
    s.diffuse = false;
    const std::vector<app::LabCase> cases = app::runParamsLab(wb, s);
    ASSERT_EQ(cases.size(), 4u);
    const double zMax = core::bonferroniZ(1e-3, 4);
    for (const app::LabCase& c : cases) {
        ASSERT_TRUE(c.problem.empty()) << c.problem;
        const double alpha = c.sigmaS / (c.sigmaS + c.sigmaA);
        const double want = 1 - pttest::hByIntegral(alpha, 1.0) * std::sqrt(1 - alpha);
        EXPECT_LT(std::abs(c.measured - want), zMax * c.measuredSe)
            << c.mapping << " A " << c.albedo << ": " << c.measured << " +- " << c.measuredSe
            << " vs " << want;
        EXPECT_GT(c.meanRadiusMm, 0.0);
    }
    ::unsetenv("BSSRDF_WORKBENCH_CACHE");
    fs::remove_all(root);
}

// Under uniform diffuse light the albedo is 2∫R(μ)μ dμ; with an index-matched boundary and
// isotropic scattering R(μ) = 1 − H(μ)√(1 − α), so A_diff = 1 − 2√(1 − α)∫H(μ)μ dμ, the
// integral by a 40-point Gauss–Legendre rule here (the lab uses 8 points).
TEST(ParamsLab, DiffuseAlbedoIsChandrasekharsAtAnIndexMatchedBoundary) {
    const double zMax = core::bonferroniZ(1e-3, 3);
    for (double alpha : {0.5, 0.9, 0.99}) {
        std::vector<double> x, w;
        pttest::gaussLegendre(40, 0.0, 1.0, x, w);
        double h1 = 0;
        for (size_t i = 0; i < x.size(); ++i)
            h1 += w[i] * x[i] * pttest::hByIntegral(alpha, x[i]);
        const double want = 1 - 2 * std::sqrt(1 - alpha) * h1;
        const auto [got, se] = app::diffuseAlbedo({1 - alpha, alpha, 0.0, 1.0}, 40000);
        EXPECT_LT(std::abs(got - want), zMax * se)
            << "alpha " << alpha << ": " << got << " +- " << se << " vs " << want;
    }
}

namespace {
class ParamsLabCli : public clitest::CliFixture {};
} // namespace

TEST_F(ParamsLabCli, WritesTheTableTheReportAndThePlots) {
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    const std::vector<std::string> args = {"params-lab", "--mappings", "van_de_hulst,rdr_ld_dipole",
                                           "--albedos",  "0.4,0.8",    "--eta",
                                           "1.3",        "--g",        "0",
                                           "--paths",    "20000",      "--out",
                                           "lab"};
    clitest::RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const std::string csv = clitest::readText(dir() / "lab/lab.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5) << csv; // header + 2 × 2
    EXPECT_NE(csv.find("rdr_ld_dipole,1.3,0,0.8,1,"), std::string::npos) << csv;
    const std::string md = clitest::readText(dir() / "lab/report.md");
    EXPECT_NE(md.find("| van_de_hulst | 1.3 | 0 |"), std::string::npos) << md;
    EXPECT_GT(fs::file_size(dir() / "lab/rdr_ld_dipole_albedo.png"), 1000u);
    EXPECT_GT(fs::file_size(dir() / "lab/van_de_hulst_radius.png"), 1000u);
    ::unsetenv("BSSRDF_WORKBENCH_CACHE");
}

TEST_F(ParamsLabCli, BadValuesNameTheirArgument) {
    expectFailure({"params-lab", "--albedos", "0.5,1.5", "--out", "o"}, {"--albedos", "(0, 1)"});
    expectFailure({"params-lab", "--mappings", "pbrt", "--out", "o"},
                  {"--mappings", "unknown mapping 'pbrt'", "pbd_mfp"});
    expectFailure({"params-lab", "--eta", "0.5", "--out", "o"}, {"--eta", "[1, 3]"});
    expectFailure({"params-lab", "--g", "0.99", "--out", "o"}, {"--g"});
    EXPECT_FALSE(fs::exists(dir() / "o/lab.csv"));
}

TEST(ParamsLabPanel, AppliesTheMappingAndMeasuresItWithoutHoldingTheFrames) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("labpanel", {"dipole.bssrdf", "better_dipole.bssrdf"});
    ::setenv("BSSRDF_WORKBENCH_CACHE", (root / "cache").c_str(), 1);
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 900);
    app::UiState& ui = gui.ui();
    ui.shared.show(app::PanelId::Parameters);
    gui.frame();
    gui.frame();
    app::ArtistMappingState& st = ui.parameters.artist;
    EXPECT_EQ(st.measurePaths, app::LabSettings{}.paths); // the CLI's default
    st.measurePaths = 20000;                              // enough for the ±50 % asked below
    ASSERT_GT(st.header.width(), 5.0f);
    testsupport::click(gui, st.header); // open the section
    gui.frame();
    ASSERT_GT(st.applyButton.width(), 5.0f) << st.problem;
    const ImGuiWindow* w = testsupport::panelWindow(app::PanelId::Parameters);
    ASSERT_NE(w, nullptr);
    EXPECT_TRUE(testsupport::rectOf(w).contains(st.measureButton)) << "the buttons are on screen";
    testsupport::click(gui, st.applyButton);
    const material::MaterialParams want = app::mapArtistParams(
        *app::findParamMapping(st.mapping), st.albedo, st.lengthMm, wb.shared().params.g,
        wb.shared().params.eta, wb.library().find("materials/better_dipole.bssrdf"));
    for (int c = 0; c < 3; ++c) {
        EXPECT_DOUBLE_EQ(wb.shared().params.sigmaA[c], want.sigmaA[c]);
        EXPECT_DOUBLE_EQ(wb.shared().params.sigmaS[c], want.sigmaS[c]);
    }
    EXPECT_TRUE(wb.shared().preset.empty());
    gui.frame();
    testsupport::click(gui, st.measureButton);
    ASSERT_TRUE(st.measurement);
    core::Stopwatch clock;
    double longest = 0;
    int framesWhileMeasuring = 0;
    while (!st.measurement->done.load() && clock.ms() < 60000) {
        core::Stopwatch one;
        gui.frame();
        longest = std::max(longest, one.ms());
        framesWhileMeasuring += !st.measurement->done.load();
    }
    std::printf("%d frames while measuring, the longest %.0f ms, in all %.1f s\n",
                framesWhileMeasuring, longest, clock.ms() / 1000.0);
    ASSERT_TRUE(st.measurement->done.load());
    EXPECT_GE(framesWhileMeasuring, 3) << "a frame waited for the measurement";
    for (const app::LabCase& c : st.measurement->cases) {
        EXPECT_TRUE(c.problem.empty()) << c.problem;
        EXPECT_GT(c.measured, 0.5 * c.albedo);
        EXPECT_LT(c.measured, 1.5 * c.albedo);
    }
    gui.frame();
    EXPECT_GE(testsupport::expectTablesShowTheirCells(app::PanelId::Parameters), 1)
        << "the measured table";
    ::unsetenv("BSSRDF_WORKBENCH_CACHE");
    fs::remove_all(root);
}
