// The BSSRDF slice stage through the Workbench: its reference is exactly the estimate of the
// paths done (and resumes after a cancel to the same table), every model is evaluated on the
// same bins through Bssrdf() on the GPU with the directions it reads, and bad settings or bad
// model values are Errors entries while the last table stays.
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "bssrdf/program.h"
#include "core/statistics.h"
#include "core/text.h"
#include "gui/gui.h"
#include "pathtrace/bssrdf_table.h"
#include "pathtrace/fresnel.h"
#include "pipeline/scoring_oblique.h"
#include "pipeline/slice_model.h"
#include "pipeline/workbench.h"

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <thread>

namespace {

constexpr double kPi = std::numbers::pi;

void smallSlice(app::SliceSettings& s) {
    s.enabled = true;
    s.channel = 1;
    s.thetaIDeg = 45;
    s.rangeLd = 2.0;
    s.rBins = 6;
    s.thetaSBins = 4;
    s.dirCosBins = 2;
    s.dirPhiBins = 3;
    s.paths = 40000;                   // three chunks: the last one partial
    s.device = app::TracerDevice::Cpu; // bitwise the CLI's estimate (the GL walk: its own test)
}

void writeModel(const std::filesystem::path& file, const std::string& body) {
    std::ofstream(file) << "analytic\n::begin shader\nvec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, "
                           "vec3 Wo) {\n"
                        << body << "\n}\n::end shader\n";
}

bool hasError(app::Workbench& wb, const std::string& source, const std::string& text) {
    for (const auto& e : wb.errors())
        if (e.source == source && e.text.find(text) != std::string::npos) return true;
    return false;
}

} // namespace

TEST(SliceStage, ReferenceIsTheEstimateOfThePathsDoneAndEveryModelIsOnItsBins) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice", {"dipole.bssrdf", "better_dipole.bssrdf"});
    app::Workbench wb(root, false);
    smallSlice(wb.sliceSettings());
    const app::SliceSnapshot snap = wb.finishSlice();
    ASSERT_TRUE(snap.problem.empty()) << snap.problem;
    ASSERT_TRUE(snap.slice);
    EXPECT_EQ(snap.pathsDone, 40000u);
    EXPECT_TRUE(snap.energy.empty()) << snap.energy;
    // the medium is the source model's green channel; the table is the CLI's estimate
    const auto p = *wb.view("materials/dipole.bssrdf").effective;
    EXPECT_EQ(snap.medium.sigmaA, p.sigmaA[1]);
    EXPECT_EQ(snap.medium.sigmaS, p.sigmaS[1]);
    const pathtrace::EstimateSettings est = app::estimateSettings(wb.sliceSettings(), snap.medium);
    const double ld = 1 / std::sqrt(3 * p.sigmaA[1] * (p.sigmaA[1] + p.sigmaS[1] * (1 - p.g)));
    EXPECT_NEAR(est.bins.rMaxMm, 2.0 * ld, 1e-12 * ld);
    const pathtrace::BssrdfSlice direct = pathtrace::finalize(
        pathtrace::estimateChunks(snap.medium, est, 0, 0, pathtrace::chunkCount(est)), est.bins,
        45.0, snap.medium);
    EXPECT_EQ(snap.slice->R, direct.R);
    EXPECT_EQ(snap.slice->S, direct.S);
    EXPECT_EQ(snap.slice->SStderr, direct.SStderr);
    // both models, on the same bins
    const auto& models = wb.slice().models();
    ASSERT_EQ(models.size(), 2u);
    for (const auto& [path, r] : models) {
        SCOPED_TRACE(path);
        EXPECT_TRUE(r.problem.empty()) << r.problem;
        ASSERT_TRUE(r.slice);
        EXPECT_EQ(r.slice->R.size(), direct.R.size());
        EXPECT_EQ(r.slice->S.size(), direct.S.size());
    }
    EXPECT_FALSE(hasError(wb, "slice", ""));
}

TEST(SliceStage, RadialModelIsItsPencilProfileAveragedOverEachBin) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_radial", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    smallSlice(wb.sliceSettings());
    wb.sliceSettings().paths = 16384;
    wb.finishSlice();
    const auto& r = wb.slice().models().at("materials/dipole.bssrdf");
    ASSERT_TRUE(r.slice) << r.problem;
    // the pencil program at the sub-samples' radii, averaged in C++
    bssrdf::ModelEntry* e = wb.library().find("materials/dipole.bssrdf");
    ASSERT_NE(e, nullptr);
    const auto p = *wb.view(e->displayPath).effective;
    const app::SliceSnapshot snap = wb.slice().snapshot();
    const pathtrace::BssrdfBins& b = snap.settings.bins;
    const app::SliceSampling n = app::sliceSampling(b, false);
    const auto q = app::sliceQueries(b, 45, false, n);
    std::vector<double> radii(q.size());
    for (size_t i = 0; i < q.size(); ++i)
        radii[i] = std::hypot(double(q[i].xo.x), double(q[i].xo.y));
    const bssrdf::Profile prof =
        bssrdf::evaluateProfile(e->programs.at("pencil_profile.comp").id(), *e->model, e->values,
                                app::builtinsOf(p), radii);
    const double t12 = 1 - pathtrace::fresnelDielectric(std::cos(kPi / 4), p.eta);
    const size_t per = q.size() / size_t(b.spatialBins());
    for (size_t bin = 0; bin < size_t(b.spatialBins()); ++bin) {
        double avg = 0;
        for (size_t k = 0; k < per; ++k)
            avg += prof.value[bin * per + k][1] / double(per);
        EXPECT_NEAR(r.slice->R[bin], t12 * avg, 1e-6 * t12 * avg) << bin;
    }
}

TEST(SliceStage, ModelThatReadsWoIsEvaluatedWithTheExitDirections) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_wo", {});
    writeModel(root / "materials" / "wo.bssrdf", "return vec3(1.0 + Wo.z);");
    app::Workbench wb(root, false);
    wb.shared().params.eta = 1.0; // T = 1: the cell averages have a closed form
    smallSlice(wb.sliceSettings());
    wb.sliceSettings().paths = 16384;
    wb.finishSlice();
    const auto& r = wb.slice().models().at("materials/wo.bssrdf");
    ASSERT_TRUE(r.slice) << r.problem;
    const app::SliceSnapshot snap = wb.slice().snapshot();
    const pathtrace::BssrdfBins& b = snap.settings.bins;
    const app::SliceSampling n = app::sliceSampling(b, true);
    for (int cell = 0; cell < b.dirBins(); ++cell) {
        const int ring = cell / b.dirPhiBins;
        const double m0 = double(ring) / b.dirCosBins, m1 = double(ring + 1) / b.dirCosBins;
        const double first = (m1 * m1 - m0 * m0) / 2, second = (m1 * m1 * m1 - m0 * m0 * m0) / 3;
        const double exact = (first + second) / (kPi * first);
        const double h = (m1 - m0) / n.mu; // midpoint rule's bound, and float
        const double bound = (m1 - m0) * h * h / 12 / (kPi * first) + 1e-5 * exact;
        for (int bin = 0; bin < b.spatialBins(); ++bin)
            EXPECT_NEAR(r.slice->S[size_t(bin * b.dirBins() + cell)], exact, bound);
    }
    // a model that ignored Wo (evaluated at the normal, 1 + 1) would give 2/π in every cell
    EXPECT_LT(r.slice->S[0], 0.9 * 2 / kPi);
}

TEST(SliceStage, CancelledRunResumesToTheUninterruptedTable) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_resume", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    smallSlice(wb.sliceSettings());
    wb.update();                                                 // starts in the background
    std::this_thread::sleep_for(std::chrono::milliseconds(300)); // some chunks, maybe
    wb.sliceSettings().enabled = false;                          // the panel hidden: cancels
    wb.update();
    EXPECT_FALSE(wb.slice().snapshot().running);
    const app::SliceSnapshot snap = wb.finishSlice(); // shown again: resumes
    ASSERT_TRUE(snap.slice);
    EXPECT_EQ(snap.pathsDone, 40000u);
    const pathtrace::EstimateSettings est = app::estimateSettings(wb.sliceSettings(), snap.medium);
    const pathtrace::BssrdfSlice direct = pathtrace::finalize(
        pathtrace::estimateChunks(snap.medium, est, 0, 0, pathtrace::chunkCount(est)), est.bins,
        45.0, snap.medium);
    EXPECT_EQ(snap.slice->R, direct.R);
    EXPECT_EQ(snap.slice->RStderr, direct.RStderr);
}

TEST(SliceStage, BadSettingsAndBadModelValuesAreErrorsAndTheLastTableStays) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_bad", {"dipole.bssrdf"});
    writeModel(root / "materials" / "negative.bssrdf", "return vec3(-1.0);");
    app::Workbench wb(root, false);
    smallSlice(wb.sliceSettings());
    wb.sliceSettings().paths = 16384;
    const app::SliceSnapshot good = wb.finishSlice();
    ASSERT_TRUE(good.slice);
    EXPECT_TRUE(hasError(wb, "slice", "materials/negative.bssrdf: Bssrdf() is negative"));
    for (double ti : {90.0, -5.0, double(NAN)}) {
        SCOPED_TRACE(ti);
        wb.sliceSettings().thetaIDeg = ti;
        wb.update();
        EXPECT_TRUE(hasError(wb, "slice", "theta_i must lie in [0, 90)"));
        const app::SliceSnapshot kept = wb.slice().snapshot();
        ASSERT_TRUE(kept.slice);
        EXPECT_EQ(kept.slice->R, good.slice->R);
    }
    wb.sliceSettings().thetaIDeg = 45;
    wb.sliceSettings().rBins = 0;
    wb.update();
    EXPECT_TRUE(hasError(wb, "slice", "r_bins"));
    wb.sliceSettings().rBins = 6;
    wb.sliceSettings().channel = 3;
    wb.update();
    EXPECT_TRUE(hasError(wb, "slice", "channel must be 0 (R), 1 (G) or 2 (B)"));
    wb.sliceSettings().channel = 1;
    const app::SliceSnapshot again = wb.finishSlice(); // good settings: the same table again
    EXPECT_FALSE(hasError(wb, "slice", "theta_i"));
    EXPECT_FALSE(hasError(wb, "slice", "channel"));
    ASSERT_TRUE(again.slice);
    EXPECT_EQ(again.slice->R, good.slice->R);
}

TEST(SlicePanel, ClickingABinPicksItForTheExitDirections) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_panel", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    smallSlice(wb.sliceSettings());
    app::HeadlessGui gui(wb, 1600, 1000);
    gui.ui().shared.show(app::PanelId::Slice);
    gui.frame();
    EXPECT_TRUE(wb.sliceSettings().enabled); // runs while its panel shows
    wb.finishSlice();
    gui.frame();
    gui.frame();
    app::SlicePanelState& ps = gui.ui().slice;
    ASSERT_GT(ps.refRect.width(), 100.0f);
    EXPECT_EQ(ps.bin, -1);
    // forward (θs ≈ 0), at 0.55 of r_max: radial bin 3 of 6, θs bin 0
    const float cx = 0.5f * (ps.refRect.x0 + ps.refRect.x1);
    const float cy = 0.5f * (ps.refRect.y0 + ps.refRect.y1);
    testsupport::clickAt(gui, cx + 0.55f * (0.5f * ps.refRect.width() - 2.0f), cy - 2.0f);
    EXPECT_EQ(ps.bin, 3 * wb.sliceSettings().thetaSBins + 0);
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    if (const char* dir = std::getenv("BW_PANEL_PNG_DIR"))
        gl::writePng((std::filesystem::path(dir) / "Slice-clicked-1600x1000.png").string(), 1600,
                     1000, gui.pixels());
}

// With no model visible the panel says there is none to trace. (That it no longer says so on
// a frame drawn before the stage's first run, with models loaded, was seen in the window only:
// headless frames run the stage before the panel's first draw.)
TEST(SlicePanel, SaysSoWhenNoModelIsVisible) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_no_model", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    smallSlice(wb.sliceSettings());
    wb.view("materials/dipole.bssrdf").visible = false;
    app::HeadlessGui gui(wb, 1280, 720);
    gui.ui().shared.show(app::PanelId::Slice);
    gui.frame();
    const std::string text = testsupport::panelText(gui, app::PanelId::Slice);
    EXPECT_NE(text.find("No usable model"), std::string::npos) << text;
}

// The panel states the model's rel_err over the plane as `compare` computes it, and at 1280×720
// the three maps, the difference map included, are on screen.
TEST(SlicePanel, StatesRelErrAndShowsTheDifferenceMapAt1280x720) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_summary", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    smallSlice(wb.sliceSettings());
    app::HeadlessGui gui(wb, 1280, 720);
    gui.ui().shared.show(app::PanelId::Slice);
    gui.frame();
    wb.finishSlice();
    gui.frame();
    gui.frame();
    const app::SlicePanelState& ps = gui.ui().slice;
    const app::SliceSnapshot snap = wb.slice().snapshot();
    ASSERT_TRUE(snap.slice.has_value());
    const auto& models = wb.slice().models();
    ASSERT_EQ(models.count(ps.model), 1u);
    const app::ModelSliceResult& mr = models.at(ps.model);
    ASSERT_TRUE(mr.slice.has_value());
    const pathtrace::Medium& m = snap.medium;
    const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
    const capture::ScoreRow want = app::scoreSlice(snap.settings.bins, *snap.slice, *mr.slice, ld);
    ASSERT_TRUE(std::isfinite(want.relErr));
    EXPECT_NE(ps.summary.find("rel_err over the plane " + core::formatNumber(100 * want.relErr, 3) +
                              " % +- "),
              std::string::npos)
        << ps.summary;
    const ImGuiWindow* panel = testsupport::panelWindow(app::PanelId::Slice);
    ASSERT_NE(panel, nullptr);
    ASSERT_GT(ps.diffRect.width(), 100.0f);
    EXPECT_LE(ps.diffRect.y1, panel->InnerClipRect.Max.y) << "the difference map is below the fold";
    EXPECT_LE(ps.diffRect.x1, panel->InnerClipRect.Max.x);
    if (const char* dir = std::getenv("BW_PANEL_PNG_DIR"))
        gl::writePng((std::filesystem::path(dir) / "Slice-1280x720.png").string(), 1280, 720,
                     gui.pixels());
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
}

// A path-traced oblique table loaded as a model (table models, pathtrace/bssrdf_table.h) is a
// model like any other in the slice: evaluated on the bins through its generated Bssrdf().
TEST(SliceStage, ObliqueTableModelIsEvaluatedLikeAnyModel) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_table", {"dipole.bssrdf"});
    app::SliceSettings settings;
    smallSlice(settings);
    settings.paths = 16384;
    pathtrace::Medium m; // one medium for all channels: the table's
    m.sigmaA = 0.01;
    m.sigmaS = 1.0;
    m.g = 0.0;
    m.eta = 1.3;
    const pathtrace::EstimateSettings est = app::estimateSettings(settings, m);
    pathtrace::writeTable(root / "materials" / "t.bwtable",
                          pathtrace::estimateTable(m, est, 0, pathtrace::chunkCount(est)));
    std::ofstream(root / "materials" / "table.bssrdf")
        << "analytic\n::begin table\nestimate t.bwtable\n::end table\n";
    app::Workbench wb(root, false);
    wb.shared().params.sigmaA = glm::dvec3(m.sigmaA);
    wb.shared().params.sigmaS = glm::dvec3(m.sigmaS);
    wb.shared().params.eta = m.eta;
    wb.sliceSettings() = settings;
    const app::SliceSnapshot snap = wb.finishSlice();
    ASSERT_TRUE(snap.slice);
    const auto& r = wb.slice().models().at("materials/table.bssrdf");
    ASSERT_TRUE(r.slice) << r.problem;
    EXPECT_TRUE(r.problem.empty()) << r.problem;
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    const int inner = 3 * wb.sliceSettings().thetaSBins; // the first three rings
    for (int bin = 0; bin < inner; ++bin) {
        EXPECT_TRUE(std::isfinite(r.slice->R[size_t(bin)]));
        EXPECT_GT(r.slice->R[size_t(bin)], 0.0) << bin;
    }
}

TEST(SliceStage, GlWalkIsSlicedPerFrameAndEstimatesTheSameTable) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slice_gpu", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::SliceSettings& s = wb.sliceSettings();
    smallSlice(s);
    s.paths = 20000;
    s.device = app::TracerDevice::Gpu;
    // one update = one frame: a slice of the run, not all of it
    wb.update();
    const app::SliceSnapshot first = wb.slice().snapshot();
    EXPECT_TRUE(first.problem.empty()) << first.problem;
    EXPECT_EQ(first.device, "GPU");
    EXPECT_LT(first.pathsDone, 20000u);
    const app::SliceSnapshot gpu = wb.finishSlice();
    ASSERT_TRUE(gpu.problem.empty()) << gpu.problem;
    ASSERT_TRUE(gpu.slice);
    EXPECT_EQ(gpu.pathsDone, 20000u);
    EXPECT_TRUE(gpu.energy.empty()) << gpu.energy;
    EXPECT_EQ(gpu.settings.splitting.levels, 0); // the table says what the GL walk traced
    bool listed = false;
    for (const auto& [k, v] : wb.slice().status().stats)
        listed |= k == "device" && v == "GPU";
    EXPECT_TRUE(listed);

    // the same slice on the CPU: every bin and exit cell agrees within the errors
    s.device = app::TracerDevice::Cpu;
    const app::SliceSnapshot cpu = wb.finishSlice();
    ASSERT_TRUE(cpu.slice);
    EXPECT_EQ(cpu.device, "CPU");
    ASSERT_EQ(cpu.slice->R.size(), gpu.slice->R.size());
    ASSERT_EQ(cpu.slice->S.size(), gpu.slice->S.size());
    const size_t n = cpu.slice->R.size() + cpu.slice->S.size();
    const double zMax = core::normalUpperQuantile(0.001 / (2.0 * double(n)));
    double worst = 0;
    size_t compared = 0;
    auto check = [&](const std::vector<double>& a, const std::vector<double>& ae,
                     const std::vector<double>& b, const std::vector<double>& be) {
        for (size_t i = 0; i < a.size(); ++i) {
            const double se = std::hypot(ae[i], be[i]);
            if (se <= 0) continue;
            worst = std::max(worst, std::abs(a[i] - b[i]) / se);
            ++compared;
        }
    };
    check(gpu.slice->R, gpu.slice->RStderr, cpu.slice->R, cpu.slice->RStderr);
    check(gpu.slice->S, gpu.slice->SStderr, cpu.slice->S, cpu.slice->SStderr);
    EXPECT_LT(worst, zMax);
    EXPECT_GT(compared, n / 2);
    const double seTotal = std::hypot(gpu.slice->totalRdStderr, cpu.slice->totalRdStderr);
    EXPECT_LT(std::abs(gpu.slice->totalRd - cpu.slice->totalRd) / seTotal, 3.29);

    // a broken edit of the walk keeps the last program and names file:line
    s.device = app::TracerDevice::Gpu;
    wb.update();
    const auto file = root / "shaders/bssrdf_walk.comp";
    const std::string good = testsupport::readText(file);
    const int line = testsupport::lineOf(good, "void main()");
    core::writeFile(file, testsupport::replaced(good, "void main()",
                                                "void main() { brokenCall(); }\nvoid main2()"));
    EXPECT_TRUE(wb.slice().reloadShaders({file}));
    EXPECT_NE(wb.slice().snapshot().problem.find("bssrdf_walk.comp:" + std::to_string(line)),
              std::string::npos)
        << wb.slice().snapshot().problem;
    core::writeFile(file, good);
    EXPECT_TRUE(wb.slice().reloadShaders({file}));
    EXPECT_TRUE(wb.slice().snapshot().problem.empty()) << wb.slice().snapshot().problem;
    std::filesystem::remove_all(root);
}
