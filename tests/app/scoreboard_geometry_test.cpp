// The Scoreboard's geometry tab (pipeline/geometry_stage.h) headless, through real clicks: Run
// traces the references in the background while frames keep coming, every model's image of each
// shape is scored with exactly the numbers `compare --geometry` computes, a model added by hot
// reload is scored too, a click on a cell shows its images, and Cancel stops a run.
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "core/core.h"
#include "core/text.h"
#include "gui/gui.h"
#include "pipeline/geometry_scoring.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>

namespace {
namespace fs = std::filesystem;

// Frames until the geometry stage has nothing left to do (at most `seconds`); returns how many
// frames ended with the run still under way (a frame that waited for it would end with it done).
int runToTheEnd(app::HeadlessGui& gui, app::Workbench& wb, double seconds) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    int whileRunning = 0;
    for (int k = 0; k < 3 || wb.geometry().status().running; ++k) {
        gui.frame();
        whileRunning += wb.geometry().status().running;
        if (std::chrono::duration<double>(clock::now() - start).count() > seconds) break;
    }
    return whileRunning;
}

} // namespace

TEST(ScoreboardGeometry, RunScoresEveryModelAsTheCliFollowsHotReloadAndCancels) {
    testsupport::context();
    auto root =
        testsupport::makeProjectRoot("geometry-tab", {"dipole.bssrdf", "better_dipole.bssrdf"});
    ::setenv("BSSRDF_WORKBENCH_CACHE", (root / "cache").c_str(), 1);
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 860);
    gui.ui().shared.show(app::PanelId::Scoreboard);
    app::GeometryTabSettings& tab = wb.geometryTab();
    tab.preset = "Skin1";
    tab.channel = 1;
    tab.shapes = {"sphere:r=1", "corner:s=3"};
    tab.settings.size = 16;
    tab.settings.referenceSpp = 16;
    tab.settings.modelSpp = 8;
    gui.frame();
    gui.frame();
    for (int k = 0; k < 4; ++k) // the docked panel and its tab bar take a few frames to lay out
        gui.frame();
    testsupport::click(gui, gui.ui().scoreboard.geometryTabRect);
    gui.frame();
    ASSERT_TRUE(gui.ui().scoreboard.geometryTab);
    EXPECT_FALSE(tab.enabled);
    wb.geometry().frameBudgetMs = 0; // one step a frame: the frames are counted, not timed
    testsupport::click(gui, gui.ui().scoreboard.geometryRun);
    EXPECT_TRUE(tab.enabled);
    EXPECT_GE(runToTheEnd(gui, wb, 120), 3) << "a frame waited for the references or the models";
    ASSERT_FALSE(wb.geometry().status().running);
    EXPECT_TRUE(wb.geometry().status().problems.empty());

    // the numbers are compare --geometry's: the same reference (from the cache the tab filled)
    // and the same image, whatever the step sizes
    const bssrdf::ModelEntry* dipole = wb.library().find("materials/dipole.bssrdf");
    ASSERT_NE(dipole, nullptr);
    std::vector<app::GeometrySkip> skipped;
    const auto cases = app::geometryCases(wb.presets(), tab.shapes, {"Skin1"}, &skipped);
    ASSERT_EQ(cases.size(), 6u);
    for (const app::GeometryCase& c : cases) {
        if (c.channel != 1) continue;
        bool fromCache = false;
        const auto ref = app::geometryReference(c, tab.settings, {}, nullptr, fromCache);
        EXPECT_TRUE(fromCache);
        const auto img = app::geometryModelImage(*dipole, app::geometryMaterial(wb.presets(), c), c,
                                                 tab.settings, nullptr);
        ASSERT_TRUE(ref && img);
        const app::ImageScore want = app::imageRelativeL2(*img, *ref);
        const app::GeometryCell* got = wb.geometry().cell("materials/dipole.bssrdf", c.shape);
        ASSERT_TRUE(got && got->image) << c.shape;
        EXPECT_DOUBLE_EQ(got->score.relL2, want.relL2) << c.shape;
        EXPECT_DOUBLE_EQ(got->score.meanRatio, want.meanRatio) << c.shape;
        EXPECT_GE(got->rank, 1);
    }

    // a model added while it runs (the dipole at twice its Multiplier) is scored too: its
    // images are twice the dipole's
    std::string text = core::readFile(root / "materials" / "dipole.bssrdf");
    const std::string param = "float Multiplier 0.0 10.0 1.0";
    ASSERT_NE(text.find(param), std::string::npos);
    text.replace(text.find(param), param.size(), "float Multiplier 0.0 10.0 2.0");
    core::writeFile(root / "materials" / "twice.bssrdf", text);
    wb.reloadAll();
    runToTheEnd(gui, wb, 120);
    for (const std::string& shape : wb.geometry().shapes()) {
        const app::GeometryCell* one = wb.geometry().cell("materials/dipole.bssrdf", shape);
        const app::GeometryCell* two = wb.geometry().cell("materials/twice.bssrdf", shape);
        ASSERT_TRUE(one && two && one->image && two->image) << shape;
        EXPECT_NEAR(two->score.meanRatio, 2 * one->score.meanRatio, 1e-5 * one->score.meanRatio);
    }

    // a click on a cell selects it and shows its images; a click on an image probes a pixel
    app::ScoreboardPanelState& ps = gui.ui().scoreboard;
    ASSERT_EQ(ps.geometryCells.size(), 6u); // 3 models × 2 shapes
    for (const auto& [name, rect] : ps.geometryCells)
        if (name == "materials/better_dipole.bssrdf|corner:s=3") testsupport::click(gui, rect);
    EXPECT_EQ(ps.geometryModel, "materials/better_dipole.bssrdf");
    EXPECT_EQ(ps.geometryShape, "corner:s=3");
    gui.frame();
    if (const char* png = std::getenv("BW_GEOMETRY_TAB_PNG"))
        gl::writePng(png, gui.width(), gui.height(), gui.pixels());

    // another preset starts over; Cancel stops it within a frame or two
    tab.preset = "Marble";
    gui.frame();
    ASSERT_TRUE(wb.geometry().status().running);
    testsupport::click(gui, ps.geometryRun); // the button reads Cancel while it runs
    EXPECT_FALSE(tab.enabled);
    gui.frame();
    EXPECT_FALSE(wb.geometry().status().running);
    fs::remove_all(root);
}

// The tab states the unit of the suite's lengths, l_d of the preset and channel chosen, before
// any run (it said "0 mm") and again after either is changed (it kept the last run's), and says
// when a channel has none.
TEST(ScoreboardGeometry, StatesTheChosenChannelsLdBeforeARun) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("geometry-ld", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 860);
    gui.ui().shared.show(app::PanelId::Scoreboard);
    app::GeometryTabSettings& tab = wb.geometryTab();
    for (int k = 0; k < 6; ++k) // the docked panel and its tab bar take a few frames to lay out
        gui.frame();
    testsupport::click(gui, gui.ui().scoreboard.geometryTabRect);
    ASSERT_TRUE(gui.ui().scoreboard.geometryTab);
    ASSERT_FALSE(tab.enabled);
    // Marble (Jensen et al. 2001), green: σa 0.0041/mm, σs' 2.62/mm, l_d = 1/sqrt(3 σa σt')
    tab.preset = "Marble";
    tab.channel = 1;
    const double marbleG = 1.0 / std::sqrt(3 * 0.0041 * (0.0041 + 2.62));
    std::string text = testsupport::panelText(gui, app::PanelId::Scoreboard);
    EXPECT_NE(text.find("l_d of the channel: " + core::formatNumber(marbleG, 3) + " mm"),
              std::string::npos)
        << text;
    tab.channel = 0;
    const double marbleR = 1.0 / std::sqrt(3 * 0.0021 * (0.0021 + 2.19));
    text = testsupport::panelText(gui, app::PanelId::Scoreboard);
    EXPECT_NE(text.find("l_d of the channel: " + core::formatNumber(marbleR, 3) + " mm"),
              std::string::npos)
        << text;
    EXPECT_DOUBLE_EQ(app::geometryLdMm(wb.presets(), "Marble", 0), marbleR);
    fs::remove_all(root);
}
