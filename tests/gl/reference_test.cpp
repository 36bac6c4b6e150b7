// The path-traced reference in the pencil plot: runs in the background, restarts when the
// material changes, appears as a series with a ±2σ band normalised to unit power entering
// (R_d / (1 − R_sp)), and gives every model that shares its σ error figures.
#include "../support/gl_fixture.h"
#include "capture/capture.h"
#include "capture_io.h"
#include "reference_plot.h"
#include "workbench.h"

#include <cmath>

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
    auto series = wb.plotSeries();
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
    const double w[3] = {0.2126, 0.7152, 0.0722};
    double mean = 0, var = 0;
    for (int c = 0; c < 3; ++c) {
        const auto& ch = snap.channel[c];
        mean += w[c] * ch.rd[5] / (1 - ch.specular);
        var += std::pow(w[c] * ch.rdStderr[5] / (1 - ch.specular), 2);
    }
    EXPECT_NEAR(ref.y[5], mean, 1e-12 * mean);
    EXPECT_NEAR(ref.bandHi[5] - ref.y[5], 2 * std::sqrt(var), 1e-9 * mean);
    // the model's legend carries its error figures against the reference
    EXPECT_NE(series[0].label.find("rel.L2"), std::string::npos) << series[0].label;
    EXPECT_NE(series[0].label.find("ratio@1ld"), std::string::npos) << series[0].label;

    // a material change restarts the run
    wb.applyPreset(wb.shared(), "Marble");
    wb.update();
    snap = wb.finishReference();
    EXPECT_EQ(snap.pathsDone, 20000u);
    EXPECT_NEAR(snap.channel[0].rMid.back(), 8.0 - 0.1, 1e-12);
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

TEST(Reference, CaptureRecordsAndReplaysItStatistically) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("refcap", {"dipole.bssrdf"});
    const auto dir = root / "captures/ref";
    {
        app::Workbench wb(root, false);
        wb.applyPreset(wb.shared(), "Skin1");
        wb.referenceSettings() = {true, 5000, 30, 7};
        app::recordCaptureTo(wb, dir, "ref");
    }
    auto m = capture::readManifest(dir);
    ASSERT_EQ(m.outputs.back().stage, "reference");
    EXPECT_EQ(m.outputs.back().kind, "csv_stat");
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("PASS reference"), std::string::npos) << out;
    // a bin moved by 10 standard errors fails, naming the stage
    auto t = capture::readCsv(dir / "reference.csv");
    t.rows[3][1] += 10 * t.rows[3][2];
    capture::writeCsv(dir / "reference.csv", t);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1);
    EXPECT_NE(out.find("FAIL reference"), std::string::npos) << out;
    std::filesystem::remove_all(root);
}
