// The path-traced reference in the pencil plot: runs in the background, restarts when the
// material changes, appears as a series with a ±2σ band normalised to unit power entering
// (R_d / (1 − R_sp)), and gives every model that shares its σ error figures.
#include "../support/gl_fixture.h"
#include "capture/capture.h"
#include "captures/capture_io.h"
#include "captures/settings_json.h"
#include "core/color.h"
#include "core/statistics.h"
#include "pathtrace/bssrdf_table.h"
#include "pipeline/pencil_series.h"
#include "pipeline/workbench.h"

#include <algorithm>
#include <cmath>
#include <fstream>

namespace {

// Two references of 8 bins per channel: the same profile within the errors (Bonferroni over 8
// bins x 3 channels at 1e-3), and a smaller standard error of `a` in the bin at the source.
void expectSameProfileLessNoisyAtTheSource(const app::ReferenceSnapshot& refA,
                                           const app::ReferenceSnapshot& refB) {
    for (int c = 0; c < 3; ++c) {
        const auto& a = refA.channel[c];
        const auto& b = refB.channel[c];
        ASSERT_EQ(a.rd.size(), 8u);
        for (size_t i = 0; i < a.rd.size(); ++i)
            EXPECT_LT(std::fabs(a.rd[i] - b.rd[i]) / std::hypot(a.rdStderr[i], b.rdStderr[i]),
                      core::bonferroniZ(1e-3, 24))
                << "channel " << c << " bin " << i;
        EXPECT_LT(a.rdStderr[0], b.rdStderr[0]) << "channel " << c;
    }
}

} // namespace

TEST(Reference, SeriesBandAndModelErrors) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("ref", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    wb.plotSettings().fixedRange = true;
    wb.plotSettings().rMaxMm = 8.0;
    auto& rs = wb.referenceSettings();
    rs.enabled = true;
    rs.paths = 20000;
    rs.bins = 40;
    wb.update();
    app::ReferenceSnapshot snap = wb.finishReference();
    ASSERT_TRUE(snap.problem.empty()) << snap.problem;
    EXPECT_EQ(snap.pathsDone, 20000u);
    EXPECT_FALSE(snap.running);
    wb.update();
    auto series = plotSeries(wb);
    ASSERT_EQ(series.size(), 2u);
    const auto& ref = series[1];
    ASSERT_EQ(ref.x.size(), 40u);
    ASSERT_EQ(ref.bandLo.size(), 40u);
    for (size_t i = 0; i < ref.x.size(); ++i) {
        EXPECT_NEAR(ref.x[i], 0.1 + 0.2 * i, 1e-12); // bin centres
        EXPECT_LE(ref.bandLo[i], ref.y[i]);
        EXPECT_GE(ref.bandHi[i], ref.y[i]);
    }
    // luminance of R_d/(1 − R_sp) per channel, band = 2 standard errors
    const auto& w = core::kRec709Luminance;
    double mean = 0, var = 0;
    for (int c = 0; c < 3; ++c) {
        const auto& ch = snap.channel[c];
        mean += w[c] * ch.rd[5] / (1 - ch.specular);
        var += std::pow(w[c] * ch.rdStderr[5] / (1 - ch.specular), 2);
    }
    EXPECT_NEAR(ref.y[5], mean, 1e-12 * mean);
    EXPECT_NEAR(ref.bandHi[5] - ref.y[5], 2 * std::sqrt(var), 1e-9 * mean);
    // the model's legend carries its error figures against the reference: on the luminance
    // plot rel_err of each channel the Scoreboard scores (B's l_d is too short for these bins)
    EXPECT_NE(series[0].label.find("rel_err R "), std::string::npos) << series[0].label;
    EXPECT_NE(series[0].label.find(" G "), std::string::npos) << series[0].label;
    EXPECT_NE(series[0].tooltip.find("channel R"), std::string::npos) << series[0].tooltip;
    {
        // on one channel, the Scoreboard's very row: one definition, one number
        wb.plotSettings().channel = 0;
        const auto one = plotSeries(wb);
        const app::ScoreboardRow* row = app::scoreOf(wb, wb.reference().model(), 0);
        ASSERT_NE(row, nullptr);
        EXPECT_NE(one[0].label.find(app::errorFigures(row->score)), std::string::npos)
            << one[0].label;
        EXPECT_NE(one[0].label.find("ratio@1ld"), std::string::npos) << one[0].label;
        EXPECT_NE(one[0].tooltip.find("ln r in [0.1, "), std::string::npos) << one[0].tooltip;
        // soloed: each channel's curve carries its own channel's number
        wb.plotSettings().solo = wb.reference().model();
        const auto solo = plotSeries(wb);
        ASSERT_GE(solo.size(), 3u);
        for (int c = 0; c < 2; ++c) { // R and G (B's l_d is too short for these bins)
            const app::ScoreboardRow* rc = app::scoreOf(wb, wb.reference().model(), c);
            ASSERT_NE(rc, nullptr);
            EXPECT_NE(solo[size_t(c)].label.find(app::errorFigures(rc->score)), std::string::npos)
                << solo[size_t(c)].label;
            EXPECT_NE(solo[size_t(c)].tooltip.find(std::string("channel ") + "RGB"[c]),
                      std::string::npos);
        }
        wb.plotSettings().solo.clear();
        wb.plotSettings().channel = 3;
    }
    // the model is compared with the reference: as a ratio the reference is 1 with a band of
    // its own relative uncertainty, and the model's ratio at a bin centre is R_model / R_ref
    EXPECT_EQ(series[0].compareTo, 1);
    EXPECT_EQ(series[1].compareTo, 1);
    const auto ratio = plot::relativeTo(series, plot::Relation::Ratio);
    ASSERT_EQ(ratio.size(), 2u);
    for (size_t i = 0; i < ratio[1].x.size(); ++i) {
        EXPECT_DOUBLE_EQ(ratio[1].y[i], 1.0);
        EXPECT_NEAR(ratio[1].bandHi[i] - 1.0, (ref.bandHi[i] - ref.y[i]) / ref.y[i], 1e-12);
    }
    {
        const auto& m = series[0];
        const size_t k = size_t(std::lower_bound(m.x.begin(), m.x.end(), 1.0) - m.x.begin());
        const auto rk = std::find(ratio[0].x.begin(), ratio[0].x.end(), m.x[k]);
        ASSERT_NE(rk, ratio[0].x.end());
        const double refAt = plot::relativeTo(series, plot::Relation::Difference)[0]
                                 .y[size_t(rk - ratio[0].x.begin())]; // R_model − R_ref
        EXPECT_NEAR(ratio[0].y[size_t(rk - ratio[0].x.begin())], m.y[k] / (m.y[k] - refAt), 1e-9);
    }

    // a material change restarts the run
    wb.applyPreset(wb.shared(), "Marble");
    wb.update();
    snap = wb.finishReference();
    EXPECT_EQ(snap.pathsDone, 20000u);
    EXPECT_NEAR(snap.channel[0].rMid.back(), 8.0 - 0.1, 1e-12);
    std::filesystem::remove_all(root);
}

// A ratio or difference to a model's curve (plot.compare_with): every other curve, and the
// path-traced reference with its band, relative to that model; the model itself 1. Hidden,
// soloed or not loaded, the plot compares with the path-traced reference again.
TEST(Reference, CurvesRelativeToAModelsCurve) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refmodel", {"dipole.bssrdf", "better_dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    auto& ps = wb.plotSettings();
    ps.fixedRange = true;
    ps.rMaxMm = 8.0;
    auto& rs = wb.referenceSettings();
    rs.enabled = true;
    rs.paths = 20000;
    rs.bins = 40;
    wb.update();
    ASSERT_TRUE(wb.finishReference().problem.empty());
    wb.update();
    const std::string dipole = "materials/dipole.bssrdf";
    ASSERT_NE(wb.library().find(dipole), nullptr);
    const auto values = plotSeries(wb);
    ASSERT_EQ(values.size(), 3u); // better_dipole, dipole, the reference
    EXPECT_FALSE(app::comparesWithModel(wb));
    const auto index = [&](const std::vector<plot::Series>& all, const std::string& label) {
        for (size_t i = 0; i < all.size(); ++i)
            if (all[i].label.rfind(label, 0) == 0) return int(i);
        return -1;
    };
    const int better = index(values, "better_dipole"), base = index(values, "dipole");
    ASSERT_GE(better, 0);
    ASSERT_GE(base, 0);

    ps.compareWith = dipole;
    ASSERT_TRUE(app::comparesWithModel(wb));
    const auto series = plotSeries(wb);
    ASSERT_EQ(series.size(), 3u);
    for (const auto& s : series)
        EXPECT_EQ(s.compareTo, base) << s.label;
    const auto ratio = plot::relativeTo(series, plot::Relation::Ratio);
    ASSERT_EQ(ratio.size(), 3u);
    const plot::Series &one = ratio[size_t(base)], &b = ratio[size_t(better)], &ref = ratio[2];
    for (double y : one.y)
        EXPECT_DOUBLE_EQ(y, 1.0);
    ASSERT_EQ(b.x, values[size_t(better)].x); // the same radii: no interpolation
    for (size_t i = 0; i < b.y.size(); ++i)
        EXPECT_DOUBLE_EQ(b.y[i], values[size_t(better)].y[i] / values[size_t(base)].y[i]);
    ASSERT_FALSE(ref.y.empty());
    ASSERT_EQ(ref.bandHi.size(), ref.y.size());
    for (size_t i = 0; i < ref.y.size(); ++i) { // the reference over the dipole, band alike
        EXPECT_LE(ref.bandLo[i], ref.y[i]);
        EXPECT_GE(ref.bandHi[i], ref.y[i]);
    }
    EXPECT_NEAR(ref.y[5] / (values[2].y[5]), ref.bandHi[5] / values[2].bandHi[5], 1e-12);

    // hidden, soloed, or gone: the path-traced reference again
    wb.view(dipole).visible = false;
    EXPECT_FALSE(app::comparesWithModel(wb));
    for (const auto& s : plotSeries(wb))
        EXPECT_EQ(s.compareTo, 1) << s.label; // better_dipole, then the reference
    wb.view(dipole).visible = true;
    ps.solo = dipole;
    EXPECT_FALSE(app::comparesWithModel(wb));
    ps.solo.clear();
    ps.compareWith = "materials/nope.bssrdf";
    EXPECT_FALSE(app::comparesWithModel(wb));
    EXPECT_EQ(plotSeries(wb).back().compareTo, 2);
    std::filesystem::remove_all(root);
}

TEST(Reference, BadMaterialIsAnErrorNotACrash) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refbad", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.referenceSettings().enabled = true;
    wb.referenceSettings().paths = 1000;
    wb.referenceSettings().bins = 0; // no bins: refused with a message
    wb.update();
    auto snap = wb.finishReference();
    EXPECT_NE(snap.problem.find("bins"), std::string::npos) << snap.problem;
    bool listed = false;
    for (const auto& e : wb.errors())
        listed |= e.source == "reference";
    EXPECT_TRUE(listed);
    std::filesystem::remove_all(root);
}

// The connections estimator (seed 001) as the pencil plot's reference on the CPU: a band
// whose error per path is below the implicit histogram's of the actual exits near the source; on
// the GL tracer, which has no connections, a message in Errors instead of a band.
TEST(Reference, ConnectionsEstimatorOnCpuAndRefusedOnGpu) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refconn", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    wb.plotSettings().fixedRange = true;
    wb.plotSettings().rMaxMm = 4.0;
    auto& rs = wb.referenceSettings();
    rs.enabled = true;
    rs.paths = 4000;
    rs.bins = 8;
    rs.estimator = pathtrace::Estimator::Connections;
    wb.update();
    const app::ReferenceSnapshot conn = wb.finishReference();
    ASSERT_TRUE(conn.problem.empty()) << conn.problem;
    EXPECT_TRUE(conn.energy.empty()) << conn.energy;
    EXPECT_EQ(conn.pathsDone, 4000u);
    rs.estimator = pathtrace::Estimator::Implicit;
    rs.exitSamples = 0; // the histogram of the exits themselves (expected-value exits: below)
    wb.update();
    const app::ReferenceSnapshot imp = wb.finishReference();
    expectSameProfileLessNoisyAtTheSource(conn, imp);
    rs.estimator = pathtrace::Estimator::Connections;
    rs.device = app::TracerDevice::Gpu;
    wb.update();
    const app::ReferenceSnapshot gpu = wb.finishReference();
    EXPECT_NE(gpu.problem.find("connections"), std::string::npos) << gpu.problem;
    bool listed = false;
    for (const auto& e : wb.errors())
        listed |= e.source == "reference" && e.text.find("connections") != std::string::npos;
    EXPECT_TRUE(listed);
    std::filesystem::remove_all(root);
}

// A path-traced table as a model (materials/README.md): drawn in the pencil plot; a material
// other than the table's medium is an Errors entry naming both, and matching clears it.
// Expected-value exits are the reference's default (pathtrace.h, ExpectedExits), a setting of
// the reference and of the slice that reaches the CPU walk: the same profile within the errors
// as the actual exits, a smaller error near the source. Captures record it; a capture written
// before the setting existed traced the actual exits and replays them.
TEST(Reference, ExpectedValueExitsAreASettingThatCapturesRecord) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refexits", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    wb.plotSettings().fixedRange = true;
    wb.plotSettings().rMaxMm = 4.0;
    auto& rs = wb.referenceSettings();
    // one default, in the GUI, the CLI (slab, estimate) and captures
    EXPECT_EQ(rs.exitSamples, pathtrace::kExpectedExitSamples);
    EXPECT_EQ(rs.exitSamples, pathtrace::SlabSettings{}.exits.samples);
    EXPECT_EQ(wb.sliceSettings().exitSamples, pathtrace::EstimateSettings{}.exits.samples);
    rs.enabled = true;
    rs.paths = 4000;
    rs.bins = 8;
    rs.device = app::TracerDevice::Cpu;
    wb.update();
    const app::ReferenceSnapshot ev = wb.finishReference();
    ASSERT_TRUE(ev.problem.empty()) << ev.problem;
    EXPECT_TRUE(ev.energy.empty()) << ev.energy;
    rs.exitSamples = 0;
    wb.update();
    const app::ReferenceSnapshot actual = wb.finishReference();
    ASSERT_TRUE(actual.problem.empty()) << actual.problem;
    expectSameProfileLessNoisyAtTheSource(ev, actual);
    // captures: recorded as set; missing (written before the setting) means the actual exits
    rs.exitSamples = 3;
    const capture::Manifest m = app::captureInputs(wb, "exits", -1, -1);
    EXPECT_EQ(m.settings["reference"]["exit_samples"], 3);
    EXPECT_EQ(m.settings["slice"]["exit_samples"], pathtrace::kExpectedExitSamples);
    int x = 0, y = 0;
    app::applySettingsJson(wb, nlohmann::json::parse(R"({"reference": {"paths": 100}})"), "m.json",
                           x, y);
    EXPECT_EQ(wb.referenceSettings().exitSamples, 0);
    app::applySettingsJson(wb, nlohmann::json::parse(R"({"slice": {"paths": 100}})"), "m.json", x,
                           y);
    EXPECT_EQ(wb.sliceSettings().exitSamples, 0);
    app::applySettingsJson(wb, nlohmann::json::parse(R"({"slice": {"exit_samples": 4}})"), "m.json",
                           x, y);
    EXPECT_EQ(wb.sliceSettings().exitSamples, 4);
    try {
        app::applySettingsJson(wb, nlohmann::json::parse(R"({"reference": {"exit_samples": 65}})"),
                               "m.json", x, y);
        ADD_FAILURE() << "65 exit samples were accepted";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("m.json"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("settings.reference.exit_samples"), std::string::npos)
            << e.what();
    }
    std::filesystem::remove_all(root);
}

TEST(Reference, TableModelNamesAMediumMismatch) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("reftable", {});
    const pathtrace::Medium medium{0.1, 1.0, 0.0, 1.3};
    pathtrace::EstimateSettings s;
    s.bins.rBins = 8;
    s.bins.rMaxMm = 4;
    s.bins.thetaSBins = 1;
    s.paths = 5000;
    pathtrace::writeTable(root / "materials/t.bwtable",
                          pathtrace::estimateTable(medium, s, 0, pathtrace::chunkCount(s)));
    std::ofstream(root / "materials/traced.bssrdf")
        << "analytic radial no_wi no_wo\n::begin table\nestimate t.bwtable\n::end table\n";
    app::Workbench wb(root, false);
    wb.update();
    auto mismatch = [&] {
        for (const auto& e : wb.errors())
            if (e.text.find("its table was computed for") != std::string::npos) return true;
        return false;
    };
    EXPECT_TRUE(mismatch()); // the default material is Marble
    EXPECT_EQ(plotSeries(wb).size(), 1u) << "the table model is still drawn";
    auto& p = wb.shared().params;
    p.sigmaA = glm::dvec3(0.1);
    p.sigmaS = glm::dvec3(1.0);
    p.g = 0.0;
    p.eta = 1.3;
    wb.shared().preset.clear();
    wb.update();
    EXPECT_FALSE(mismatch());
    std::filesystem::remove_all(root);
}

// A reference that fails its own energy check says so loudly: σa = 0 (Spectralon) truncates a
// few paths of the heavy tail of return times at the event limit, more weight than the
// error bar; the snapshot names the channel, the Errors panel lists it, the plot draws the
// curve without a band and the model's legend carries no error figures. Absorbing media
// clear it again.
TEST(Reference, FailedEnergyCheckIsAnErrorAndDrawsNoBand) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refenergy", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Spectralon");
    wb.plotSettings().fixedRange = true;
    wb.plotSettings().rMaxMm = 8.0;
    auto& rs = wb.referenceSettings();
    rs.enabled = true;
    rs.paths = 5000;
    rs.bins = 40;
    wb.update();
    app::ReferenceSnapshot snap = wb.finishReference();
    ASSERT_TRUE(snap.problem.empty()) << snap.problem;
    EXPECT_NE(snap.energy.find("truncated at the event limit"), std::string::npos) << snap.energy;
    EXPECT_TRUE(snap.energyFails(3));
    std::string listed;
    for (const auto& e : wb.errors())
        if (e.source == "reference") listed += e.text;
    EXPECT_NE(listed.find("truncated"), std::string::npos) << listed;
    wb.update();
    auto series = plotSeries(wb);
    ASSERT_EQ(series.size(), 2u);
    EXPECT_TRUE(series[1].bandLo.empty());
    EXPECT_NE(series[1].label.find("energy check FAILED"), std::string::npos);
    EXPECT_EQ(series[0].label.find("rel_err"), std::string::npos) << series[0].label;

    wb.applyPreset(wb.shared(), "Marble");
    wb.update();
    snap = wb.finishReference();
    EXPECT_EQ(snap.energy, "");
    for (const auto& e : wb.errors())
        EXPECT_NE(e.source, "reference") << e.text;
    std::filesystem::remove_all(root);
}

TEST(Reference, CaptureRecordsAndReplaysItStatistically) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refcap", {"dipole.bssrdf"});
    const auto dir = root / "captures/ref";
    std::string ranOn;
    {
        app::Workbench wb(root, false);
        wb.applyPreset(wb.shared(), "Skin1");
        wb.referenceSettings() = {true, 5000, 30, 7};
        ASSERT_EQ(wb.referenceSettings().device, app::TracerDevice::Auto);
        app::recordCaptureTo(wb, dir, "ref");
        ranOn = wb.finishReference().device == "GPU" ? "gpu" : "cpu";
    }
    auto m = capture::readManifest(dir);
    ASSERT_EQ(m.outputs.back().stage, "reference");
    EXPECT_EQ(m.outputs.back().kind, "csv_stat");
    // `auto` is recorded as the device that traced: the replay runs the same walk (with the
    // same seed, so the same values) whichever device this machine would pick
    EXPECT_EQ(m.settings["reference"]["device"], ranOn);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("PASS reference  124 values, identical"), std::string::npos) << out;
    // a bin moved by 10 standard errors fails, naming the stage
    auto t = capture::readCsv(dir / "reference.csv");
    t.rows[3][1] += 10 * t.rows[3][2];
    capture::writeCsv(dir / "reference.csv", t);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1);
    EXPECT_NE(out.find("FAIL reference"), std::string::npos) << out;
    std::filesystem::remove_all(root);
}

TEST(Reference, GpuTracerIsSlicedPerFrameAndHotReloads) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refgpu", {"dipole.bssrdf"});
    app::Workbench wb(root, true);
    wb.applyPreset(wb.shared(), "Skin1");
    wb.plotSettings().fixedRange = true;
    wb.plotSettings().rMaxMm = 6.0;
    wb.referenceSettings() = {true, 30000, 30, 3, app::TracerDevice::Gpu};
    // one update = one frame: a slice of the run, not all of it
    wb.update();
    auto first = wb.reference().snapshot();
    EXPECT_TRUE(first.problem.empty()) << first.problem;
    EXPECT_EQ(first.device, "GPU");
    EXPECT_LT(first.pathsDone, 30000u);
    auto snap = wb.finishReference();
    ASSERT_EQ(snap.pathsDone, 30000u);
    EXPECT_FALSE(snap.running);
    EXPECT_EQ(plotSeries(wb).size(), 2u);

    // the same run on the CPU estimates the same profile: z-test per bin, Bonferroni over 30
    wb.referenceSettings().device = app::TracerDevice::Cpu;
    auto cpu = wb.finishReference();
    ASSERT_EQ(cpu.pathsDone, 30000u);
    double worst = 0;
    for (int c = 0; c < 3; ++c)
        for (size_t i = 0; i < 30; ++i) {
            const double se = std::hypot(snap.channel[c].rdStderr[i], cpu.channel[c].rdStderr[i]);
            if (se > 0)
                worst =
                    std::max(worst, std::abs(snap.channel[c].rd[i] - cpu.channel[c].rd[i]) / se);
        }
    EXPECT_LT(worst, core::normalUpperQuantile(0.001 / (2 * 90)));

    // a broken shader edit keeps the old program running and names file:line; a fix recovers
    wb.referenceSettings().device = app::TracerDevice::Gpu;
    wb.update();
    const auto file = root / "shaders/pathtrace_slab.comp";
    const std::string good = testsupport::readText(file);
    const std::string marker = "void main()";
    const int line = testsupport::lineOf(good, marker);
    core::writeFile(
        file, testsupport::replaced(good, marker, "void main() { brokenCall(); }\nvoid main2()"));
    core::Stopwatch sw;
    while (wb.reference().snapshot().problem.empty() && sw.ms() < 5000)
        wb.update();
    const std::string problem = wb.reference().snapshot().problem;
    EXPECT_NE(problem.find("shaders/pathtrace_slab.comp:" + std::to_string(line)),
              std::string::npos)
        << problem;
    const uint64_t before = wb.reference().snapshot().pathsDone;
    for (int i = 0; i < 3; ++i)
        wb.update();
    EXPECT_GE(wb.reference().snapshot().pathsDone, before); // still running on the old program
    core::writeFile(file, good);
    sw.reset();
    while (!wb.reference().snapshot().problem.empty() && sw.ms() < 5000)
        wb.update();
    EXPECT_TRUE(wb.reference().snapshot().problem.empty()) << wb.reference().snapshot().problem;
    std::filesystem::remove_all(root);
}

// What the windowed loop's pacing asks (gui/frame_pacing.h): the workbench is working while the
// reference's run is under way (one slice per frame on the GPU), and not once it is done.
TEST(Reference, TheWorkbenchIsWorkingWhileTheRunIsUnderWay) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refworking", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.update();
    EXPECT_FALSE(wb.working()); // nothing enabled: nothing to do
    wb.referenceSettings() = {true, 4000, 30, 3, app::TracerDevice::Gpu};
    wb.update();
    ASSERT_LT(wb.reference().snapshot().pathsDone, 4000u);
    EXPECT_TRUE(wb.working());
    wb.finishReference();
    wb.update();
    EXPECT_FALSE(wb.working());
}
