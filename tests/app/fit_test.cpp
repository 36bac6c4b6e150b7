// `fit` (pipeline/fitting.h, cli/fit_command.cpp): known parameters recovered from a model's own
// output, a mis-set dipole fitted to the path-traced reference back to its best Multiplier,
// determinism, and the bad inputs: undeclared names, ranges outside the declared ones, bools, a
// model that is NaN for some values (listed, the search goes on), an optimizer out of budget.
#include "../support/cli_fixture.h"
#include "../support/gl_fixture.h"
#include "core/core.h"
#include "pipeline/fit_stage.h"
#include "pipeline/fitting.h"
#include "pipeline/model_stages.h"
#include "pipeline/scoring.h"
#include "pipeline/workbench.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>

namespace {
namespace fs = std::filesystem;

// A normalised Gaussian of width W (mm) and amplitude Amp; NaN where W < Floor.
const char* kGaussian = "analytic radial no_wi no_wo\n"
                        "::begin parameters\n"
                        "float Amp 0.1 3.0 1.0\n"
                        "float W 0.2 5.0 2.0\n"
                        "float Floor 0.0 1.0 0.0\n"
                        "bool Unused true\n"
                        "::end parameters\n"
                        "::begin shader\n"
                        "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                        "    float r = length(Xo - Xi);\n"
                        "    float nan = sqrt(-1.0 - r);\n"
                        "    if (W < Floor) return vec3(nan);\n"
                        "    return vec3(Amp * exp(-r * r / (2.0 * W * W)) / (2.0 * PI * W * W));\n"
                        "}\n"
                        "::end shader\n";

// A target on Marble's red channel whose reference is the model itself at `values` (standard
// errors 0.1 % of each bin: nearly exact).
app::FitTarget ownOutput(app::Workbench& wb, const bssrdf::ModelEntry& e,
                         const bssrdf::ParamValues& values, double sigmaScale = 1) {
    app::MaterialSettings s;
    wb.applyPreset(s, "Marble");
    app::FitTarget t;
    t.preset = "Marble";
    t.channel = 0;
    t.params = app::effectiveParams(e, s);
    t.ldMm = material::diffuseMeanFreePath(t.params)[0];
    const int n = 360;
    for (int i = 0; i <= n; ++i)
        t.edges.push_back(4.5 * t.ldMm * i / n);
    // the bin averages of the model at `values`, exactly as the fit averages it
    std::vector<core::BinNodes> nodes;
    std::vector<double> radii;
    for (int i = 0; i < n; ++i) {
        nodes.push_back(core::areaAverageNodes(t.edges[size_t(i)], t.edges[size_t(i) + 1]));
        radii.insert(radii.end(), nodes.back().r.begin(), nodes.back().r.end());
    }
    material::MaterialParams scaled = t.params; // the medium made with; the target keeps its own
    scaled.sigmaA *= sigmaScale;
    scaled.sigmaS *= sigmaScale;
    const bssrdf::Profile p =
        bssrdf::evaluateProfile(e.programs.at("pencil_profile.comp").id(), *e.model, values,
                                app::builtinsOf(scaled), radii);
    for (int i = 0; i < n; ++i) {
        double v = 0;
        for (size_t k = 0; k < 4; ++k)
            v += nodes[size_t(i)].w[k] * p.value[4 * size_t(i) + k][0];
        t.ref.push_back(v);
        t.refSe.push_back(1e-3 * v);
    }
    return t;
}

} // namespace

TEST(Fit, RecoversKnownParametersFromTheModelsOwnOutputAndIsDeterministic) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("fitown", {});
    core::writeFile(root / "materials/gauss.bssrdf", kGaussian);
    app::Workbench wb(root, false);
    wb.update();
    const bssrdf::ModelEntry* e = wb.library().find("materials/gauss.bssrdf");
    ASSERT_TRUE(e && e->usable());
    bssrdf::ParamValues truth = e->values;
    truth["Amp"][0] = 0.7f;
    truth["W"][0] = 1.3f * float(material::diffuseMeanFreePath([&] {
                        app::MaterialSettings s;
                        wb.applyPreset(s, "Marble");
                        return app::effectiveParams(*e, s);
                    }())[0]) /
                    4.0f;
    const std::vector<app::FitTarget> targets{ownOutput(wb, *e, truth)};
    const std::vector<app::FitVariable> vars = app::fitVariables(*e->model, {"Amp", "W"});
    app::FitSettings s;
    s.xtolRel = 1e-7;
    const app::FitResult r = app::fitModel(*e, vars, targets, s);
    EXPECT_TRUE(r.converged) << r.status;
    EXPECT_NEAR(r.best[0], truth["Amp"][0], 1e-4 * truth["Amp"][0]);
    EXPECT_NEAR(r.best[1], truth["W"][0], 1e-4 * truth["W"][0]);
    EXPECT_LT(r.relErrBest[0], 1e-3);
    EXPECT_GT(r.relErrStart[0], 0.1);
    // the same targets and start: the same evaluations and result, bit for bit
    const app::FitResult again = app::fitModel(*e, vars, targets, s);
    EXPECT_EQ(again.best, r.best);
    EXPECT_EQ(again.evaluations, r.evaluations);
    // a budget too small to converge says so
    app::FitSettings tight = s;
    tight.maxEvaluations = 4;
    const app::FitResult cut = app::fitModel(*e, vars, targets, tight);
    EXPECT_FALSE(cut.converged);
    EXPECT_NE(cut.status.find("budget"), std::string::npos) << cut.status;
    fs::remove_all(root);
}

// The medium as a free quantity: the dipole's own output for σ × 1.3 gives back σ scale 1.3
// (the reference keeps the preset's medium; the model is evaluated with the scaled one).
TEST(Fit, RecoversTheSigmaScaleOfTheMediumTheModelNeeds) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("fitmedium", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.update();
    const bssrdf::ModelEntry* e = wb.library().find("materials/dipole.bssrdf");
    ASSERT_TRUE(e && e->usable());
    const std::vector<app::FitTarget> targets{ownOutput(wb, *e, e->values, 1.3)};
    app::FitSettings s;
    s.xtolRel = 1e-7;
    const app::FitResult r =
        app::fitModel(*e, app::fitVariables(*e->model, {"medium.sigma_scale"}), targets, s);
    EXPECT_TRUE(r.converged) << r.status;
    EXPECT_EQ(r.start[0], 1.0);
    EXPECT_NEAR(r.best[0], 1.3, 1e-4);
    EXPECT_LT(r.relErrBest[0], 1e-3);
    fs::remove_all(root);
}

TEST(Fit, NanForSomeValuesIsListedAndTheSearchGoesOn) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("fitnan", {});
    // NaN wherever W < 1 mm: the fit must stay where the model is finite
    core::writeFile(root / "materials/gauss.bssrdf",
                    std::string(kGaussian).replace(std::string(kGaussian).find("Floor 0.0 1.0 0.0"),
                                                   17, "Floor 0.0 1.0 1.0"));
    app::Workbench wb(root, false);
    wb.update();
    const bssrdf::ModelEntry* e = wb.library().find("materials/gauss.bssrdf");
    ASSERT_TRUE(e && e->usable());
    bssrdf::ParamValues truth = e->values;
    truth["W"][0] = 1.5f;
    const std::vector<app::FitTarget> targets{ownOutput(wb, *e, truth)};
    // from W = 0.9, where the model is NaN: the first steps find where it is finite
    wb.library().find("materials/gauss.bssrdf")->values["W"][0] = 0.9f;
    const app::FitResult r =
        app::fitModel(*e, app::fitVariables(*e->model, {"W"}), targets, app::FitSettings{});
    ASSERT_FALSE(r.problems.empty());
    EXPECT_NE(r.problems[0].find("W = "), std::string::npos) << r.problems[0];
    EXPECT_NE(r.problems[0].find("NaN"), std::string::npos) << r.problems[0];
    EXPECT_NEAR(r.best[0], 1.5, 1e-3);
    fs::remove_all(root);
}

TEST(Fit, ParameterNamesAndRangesAreChecked) {
    const bssrdf::Model m = bssrdf::parseModel(kGaussian, "materials/gauss.bssrdf");
    auto fails = [&](const std::vector<std::string>& names, const std::string& part) {
        try {
            app::fitVariables(m, names);
            ADD_FAILURE() << "accepted " << names[0];
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    fails({"Width"}, "'Width' is not a parameter of materials/gauss.bssrdf (it declares Amp, W");
    fails({"Amp=0.05,2"}, "inside the declared [0.1, 3] (line 3)");
    fails({"Amp=2,1"}, "LO < HI");
    fails({"Amp=x,1"}, "not a number");
    fails({"Unused"}, "is a bool");
    fails({"Amp", "Amp"}, "given twice");
    fails({"medium.g=-2,0"}, "inside [-0.95, 0.95]");
    fails({"medium.sigma_scale", "medium.sigma_scale"}, "given twice");
    // the capture's comma-separated list keeps each range's comma
    EXPECT_EQ(app::splitParams("Amp,W=1,2,medium.g"),
              (std::vector<std::string>{"Amp", "W=1,2", "medium.g"}));
    const auto v = app::fitVariables(m, {"Amp=0.5,2", "W"});
    ASSERT_EQ(v.size(), 2u);
    EXPECT_EQ(v[0].lo, 0.5);
    EXPECT_EQ(v[1].hi, 5.0);
}

// `--set`: fixed values before a fit, checked against the declarations like --params.
TEST(Fit, SetParametersChecksNamesValuesAndRanges) {
    const bssrdf::Model m = bssrdf::parseModel(kGaussian, "materials/gauss.bssrdf");
    bssrdf::ParamValues values = bssrdf::defaultValues(m);
    app::setParameters(m, {"Amp=2.5", "Unused=1"}, values);
    EXPECT_EQ(values.at("Amp")[0], 2.5f);
    EXPECT_EQ(values.at("Unused")[0], 1.0f);
    auto fails = [&](const std::string& spec, const std::string& part) {
        bssrdf::ParamValues v = bssrdf::defaultValues(m);
        try {
            app::setParameters(m, {spec}, v);
            ADD_FAILURE() << "accepted " << spec;
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find("--set"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
        }
    };
    fails("Width=1", "'Width' is not a parameter of materials/gauss.bssrdf (it declares Amp, W");
    fails("Amp=9", "outside the declared range [0.1, 3] (materials/gauss.bssrdf line 3)");
    fails("Amp=x", "'x' is not a number");
    fails("Amp=1,2", "takes one value");
    fails("Amp", "expected NAME=VALUE");
    fails("Unused=2", "outside the declared range [0, 1]");
}

namespace {
class FitCli : public clitest::CliFixture {};
} // namespace

// The dipole with its Multiplier mis-set to 1.6 fitted to the path-traced reference of Marble's
// red channel: rel_err falls from 60 % to the dipole's best, at a Multiplier within a few percent
// of 1 (the classical dipole is close to the truth there); fit.json, report.md and a model file
// with the fitted default are written, and that model file loads.
TEST_F(FitCli, AMisSetDipoleIsFittedBackAndTheResultLoads) {
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    std::string text = clitest::readText(fs::path(BW_SOURCE_ROOT) / "materials/dipole.bssrdf");
    text.replace(text.find("float Multiplier 0.0 10.0 1.0"), 29, "float Multiplier 0.0 10.0 1.6");
    core::writeFile(dir() / "off.bssrdf", text);
    const std::vector<std::string> args = {
        "fit",      "--model",    (dir() / "off.bssrdf").string(),
        "--params", "Multiplier", "--channels",
        "R",        "--paths",    "200000",
        "--out",    "fitted"};
    clitest::RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const nlohmann::json j = nlohmann::json::parse(clitest::readText(dir() / "fitted/fit.json"));
    EXPECT_EQ(j["schema"], "bssrdf-workbench-fit");
    EXPECT_TRUE(j["converged"].get<bool>());
    const double m = j["parameters"][0]["fitted"].get<double>();
    const double sigma = j["parameters"][0]["sigma"].get<double>();
    EXPECT_NEAR(m, 1.0, 0.08);
    EXPECT_GT(sigma, 0.0);
    EXPECT_LT(sigma, 0.05);
    const double before = j["targets"][0]["rel_err_start"].get<double>();
    const double after = j["targets"][0]["rel_err_fitted"].get<double>();
    EXPECT_GT(before, 0.5);
    EXPECT_LT(after, 0.1);
    EXPECT_NE(r.output.find("Marble R: rel_err"), std::string::npos) << r.output;
    // the progress line ends where the fit ended (not at the last line drawn, a quarter second
    // apart)
    EXPECT_NE(r.output.find("fit: " + std::to_string(j["evaluations"].get<int>()) +
                            " evaluations, best mean rel_err^2 "),
              std::string::npos)
        << r.output;
    EXPECT_NE(clitest::readText(dir() / "fitted/report.md").find("| Multiplier |"),
              std::string::npos);
    // before and after against the reference, as `compare` draws them
    EXPECT_NE(clitest::readText(dir() / "fitted/report.md").find("](plots/Marble_R_profile.png)"),
              std::string::npos);
    EXPECT_GT(fs::file_size(dir() / "fitted/plots/Marble_R_ratio.png"), 1000u);
    // the written model carries the fitted default and loads
    const bssrdf::Model fitted =
        bssrdf::loadModel(dir() / "fitted/off_fit.bssrdf", "fitted/off_fit.bssrdf");
    EXPECT_NEAR(fitted.findParam("Multiplier")->value[0], m, 1e-5 * m);
    ::unsetenv("BSSRDF_WORKBENCH_CACHE");
}

// At θi > 0 the target is the whole BSSRDF over the plane (compare's oblique bins): a fit to the
// slab's radial profile and to the slice at 45° together lowers rel_err on both.
TEST_F(FitCli, ObliqueIncidenceFitsTheWholeBssrdfOverThePlane) {
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    const std::string dipole = (fs::path(BW_SOURCE_ROOT) / "materials/dipole.bssrdf").string();
    const std::vector<std::string> args = {
        "fit", "--model",   dipole, "--params", "Multiplier", "--presets", "Skin1",  "--channels",
        "G",   "--theta-i", "0,45", "--paths",  "20000",      "--out",     "oblique"};
    clitest::RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const nlohmann::json j = nlohmann::json::parse(clitest::readText(dir() / "oblique/fit.json"));
    ASSERT_EQ(j["targets"].size(), 2u);
    EXPECT_EQ(j["targets"][1]["theta_i"].get<double>(), 45.0);
    for (const auto& t : j["targets"])
        EXPECT_LT(t["rel_err_fitted"].get<double>(), t["rel_err_start"].get<double>()) << t.dump();
    EXPECT_NE(r.output.find("Skin1 G at 45 deg: rel_err"), std::string::npos) << r.output;
    ::unsetenv("BSSRDF_WORKBENCH_CACHE");
}

// A function fit: normalized_diffusion's scaling factor s (configuration 3: s = S, l = the mean
// free path) fitted at each albedo of a sweep. rel_err falls at every albedo; the profile in units
// of the mean free path widens as the albedo rises, so s falls; A, the path-traced total diffuse
// reflectance, rises with the albedo; a published curve given as CSV is drawn beside the result.
TEST_F(FitCli, AnAlbedoSweepFitsAParameterAsATableOverAlbedo) {
    ::setenv("BSSRDF_WORKBENCH_CACHE", (dir() / "cache").c_str(), 1);
    const fs::path root(BW_SOURCE_ROOT);
    const std::vector<std::string> args = {
        "fit",
        "--model",
        (root / "materials/normalized_diffusion.bssrdf").string(),
        "--set",
        "Configuration=3",
        "--params",
        "S",
        "--albedo-sweep",
        "0.7,0.95",
        "--paths",
        "40000",
        "--published",
        (root / "docs/fits/christensen_burley_searchlight_mfp.csv").string(),
        "--out",
        "sweep"};
    clitest::RunResult r = run(args);
    ASSERT_EQ(r.code, 0) << describe(args, r);
    const nlohmann::json j = nlohmann::json::parse(clitest::readText(dir() / "sweep/fit.json"));
    EXPECT_EQ(j["mode"], "albedo_sweep");
    ASSERT_EQ(j["sweep"].size(), 2u);
    for (const auto& row : j["sweep"]) {
        EXPECT_TRUE(row["converged"].get<bool>()) << row.dump();
        EXPECT_LT(row["targets"][0]["rel_err_fitted"].get<double>(),
                  row["targets"][0]["rel_err_start"].get<double>())
            << row.dump();
        EXPECT_GT(row["parameters"][0]["sigma"].get<double>(), 0.0);
    }
    const auto& lo = j["sweep"][0];
    const auto& hi = j["sweep"][1];
    EXPECT_LT(lo["A"].get<double>(), hi["A"].get<double>());
    EXPECT_GT(lo["parameters"][0]["fitted"].get<double>(),
              hi["parameters"][0]["fitted"].get<double>());
    // the second albedo's fit starts where the first ended
    EXPECT_EQ(hi["parameters"][0]["start"].get<double>(),
              double(float(lo["parameters"][0]["fitted"].get<double>())));
    const std::string csv = clitest::readText(dir() / "sweep/sweep.csv");
    EXPECT_NE(csv.find("alpha_prime,ld_over_l,A,A_se,S,S_sigma,rel_err_start,rel_err_fitted"),
              std::string::npos)
        << csv;
    const std::string md = clitest::readText(dir() / "sweep/report.md");
    EXPECT_NE(md.find("`Configuration=3`"), std::string::npos) << md;
    EXPECT_GT(fs::file_size(dir() / "sweep/sweep_S.png"), 1000u);
    EXPECT_GT(fs::file_size(dir() / "sweep/sweep_rel_err.png"), 1000u);
    EXPECT_NE(r.output.find("a' 0.95"), std::string::npos) << r.output;
    ::unsetenv("BSSRDF_WORKBENCH_CACHE");
}

TEST_F(FitCli, AlbedoSweepBadInputsNameTheirArgument) {
    const std::string nd =
        (fs::path(BW_SOURCE_ROOT) / "materials/normalized_diffusion.bssrdf").string();
    const std::vector<std::string> base = {"fit", "--model", nd, "--params", "S", "--out", "o"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = base;
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    expectFailure(with({"--albedo-sweep", "0.5,1"}), {"--albedo-sweep", "(0, 1)"});
    expectFailure(with({"--albedo-sweep", "0.5", "--presets", "Marble"}), {"--presets"});
    expectFailure(with({"--albedo-sweep", "0.5", "--theta-i", "45"}),
                  {"--theta-i", "needs 0 among its angles"});
    expectFailure(with({"--eta", "1.4"}), {"--eta", "--albedo-sweep"});
    expectFailure(with({"--set", "Configuration=7"}),
                  {"--set", "outside the declared range [0, 4]", "line"});
    expectFailure(with({"--set", "Config=1"}), {"--set", "'Config' is not a parameter"});
    core::writeFile(dir() / "bad.csv", "# comment\nA,T\n0.5,1\n");
    expectFailure(with({"--albedo-sweep", "0.5", "--published", (dir() / "bad.csv").string()}),
                  {"bad.csv:2", "'A,PARAM'", "(S)"});
    core::writeFile(dir() / "bad2.csv", "A,S\n0.5,1\n0.4,x\n");
    expectFailure(with({"--albedo-sweep", "0.5", "--published", (dir() / "bad2.csv").string()}),
                  {"bad2.csv:3", "not two numbers"});
    EXPECT_FALSE(fs::exists(dir() / "o/fit.json"));
}

TEST_F(FitCli, BadInputsNameTheirArgument) {
    const std::string dipole = (fs::path(BW_SOURCE_ROOT) / "materials/dipole.bssrdf").string();
    expectFailure({"fit", "--model", dipole, "--params", "Mult", "--out", "o"},
                  {"--params", "'Mult' is not a parameter", "Multiplier"});
    expectFailure({"fit", "--model", dipole, "--params", "Multiplier=-1,2", "--out", "o"},
                  {"--params", "inside the declared [0, 10]"});
    expectFailure(
        {"fit", "--model", dipole, "--params", "Multiplier", "--presets", "Marbel", "--out", "o"},
        {"--presets", "Marble"});
    expectFailure(
        {"fit", "--model", dipole, "--params", "Multiplier", "--channels", "X", "--out", "o"},
        {"--channels", "'X'"});
    expectFailure({"fit", "--model", dipole, "--params", "Multiplier", "--presets", "Spectralon",
                   "--out", "o"},
                  {"--presets", "Spectralon", "sigma_a = 0"});
    expectFailure(
        {"fit", "--model", dipole, "--params", "Multiplier", "--theta-i", "90", "--out", "o"},
        {"--theta-i", "[0, 90)"});
    // a measured medium that does not scatter in a channel (Narasimhan et al. 2006's Coke)
    expectFailure(
        {"fit", "--model", dipole, "--params", "Multiplier", "--presets", "Coke", "--out", "o"},
        {"Coke: sigma_s = 0 in channel B"});
    expectFailure({"compare", "--models", dipole, "--presets", "Coke", "--out", "o"},
                  {"Coke: sigma_s = 0 in channel B"});
    EXPECT_FALSE(fs::exists(dir() / "o/fit.json"));
}
