// The Scoreboard panel (scoreboard_stage.h) headless: every model scored against the pencil
// plot's reference with the same numbers `compare` computes, re-scored after a model is added by
// hot reload, and a click on a row solos that model in the pencil plot on that channel.
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "core/core.h"
#include "gl/gl.h"
#include "gui/gui.h"
#include "pipeline/scoring.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

namespace {
namespace fs = std::filesystem;

const app::ScoreboardRow* findRow(const std::vector<app::ScoreboardRow>& rows,
                                  const std::string& model, const std::string& channel) {
    for (const auto& r : rows)
        if (r.score.model == model && r.score.channel == channel) return &r;
    return nullptr;
}

} // namespace

TEST(ScoreboardPanel, ScoresEveryModelFollowsHotReloadAndAClickOpensThePencilPlot) {
    testsupport::context();
    auto root =
        testsupport::makeProjectRoot("scoreboard", {"dipole.bssrdf", "better_dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.referenceSettings().enabled = true;
    wb.referenceSettings().paths = 20000;
    app::HeadlessGui gui(wb, 1280, 860);
    gui.ui().shared.show(app::PanelId::Scoreboard);
    gui.frame();
    gui.frame();
    wb.finishReference();
    gui.frame();
    gui.frame();
    std::vector<app::ScoreboardRow> rows = wb.scoreboard().rows();
    ASSERT_EQ(rows.size(), 6u); // 2 models × 3 channels of the default preset
    for (const auto& r : rows) {
        EXPECT_TRUE(std::isfinite(r.score.relErr)) << r.score.model;
        EXPECT_GT(r.score.relErrSe, 0.0) << r.score.model;
        EXPECT_GE(r.score.rank, 1);
        EXPECT_EQ(r.score.channel, std::string(1, "RGB"[r.channel]));
    }
    EXPECT_EQ(wb.scoreboard().referencePaths(), 20000u);

    // the numbers are compare's: scoreAgainstReference on the same reference and profile
    const app::ReferenceSnapshot snap = wb.reference().snapshot();
    const std::string dipole = "materials/dipole.bssrdf";
    const bssrdf::ModelEntry* e = wb.library().find(dipole);
    ASSERT_NE(e, nullptr);
    const bssrdf::Builtins b = app::builtinsOf(*wb.view(dipole).effective);
    const GLuint program = e->programs.at("pencil_profile.comp").id();
    for (int c = 0; c < 3; ++c) {
        const pathtrace::SlabResult& ref = snap.channel[size_t(c)];
        const auto m = app::mediaOf(*wb.view(dipole).effective)[size_t(c)];
        const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
        const std::vector<double> edges = app::binEdges(ref.rMid);
        std::string bad;
        const bssrdf::Profile p = app::binAverageProfile(program, *e, b, edges, bad);
        ASSERT_EQ(bad, "");
        const std::vector<double> mv = app::channelOf(p, c);
        const app::ScoreRow want = app::scoreAgainstReference(
            edges, ref.rd, ref.rdStderr, ref.specular, ref.totalRd, ref.totalRdStderr, ld, mv,
            app::modelTotalRd(program, *e, b, ld, c), ref.rdBatches);
        const app::ScoreboardRow* got = findRow(rows, "dipole", std::string(1, "RGB"[c]));
        ASSERT_NE(got, nullptr);
        EXPECT_DOUBLE_EQ(got->score.relErr, want.relErr);
        EXPECT_DOUBLE_EQ(got->score.relErrSe, want.relErrSe);
        EXPECT_DOUBLE_EQ(got->score.totalRatio, want.totalRatio);
    }

    // a model added while the workbench runs (the dipole at twice its Multiplier) is scored too:
    // its ratios are exactly twice the dipole's
    std::string text = core::readFile(root / "materials" / "dipole.bssrdf");
    const std::string param = "float Multiplier 0.0 10.0 1.0";
    ASSERT_NE(text.find(param), std::string::npos);
    text.replace(text.find(param), param.size(), "float Multiplier 0.0 10.0 2.0");
    core::writeFile(root / "materials" / "twice.bssrdf", text);
    wb.reloadAll();
    gui.frame();
    gui.frame();
    rows = wb.scoreboard().rows();
    ASSERT_EQ(rows.size(), 9u);
    for (const char* ch : {"R", "G", "B"}) {
        const app::ScoreboardRow* one = findRow(rows, "dipole", ch);
        const app::ScoreboardRow* two = findRow(rows, "twice", ch);
        ASSERT_TRUE(one && two) << ch;
        EXPECT_NEAR(two->score.totalRatio, 2 * one->score.totalRatio, 1e-5 * one->score.totalRatio);
        EXPECT_NEAR(two->score.ratio1, 2 * one->score.ratio1, 1e-5 * one->score.ratio1);
    }
    if (const char* dir = std::getenv("BW_SCOREBOARD_PNG"))
        gl::writePng(dir, gui.width(), gui.height(), gui.pixels());
    // every column fits the panel of a 1280-wide window: the rows end inside it
    const ImGuiWindow* panel = testsupport::panelWindow(app::PanelId::Scoreboard);
    ASSERT_NE(panel, nullptr);
    ASSERT_FALSE(gui.ui().scoreboard.rowRects.empty());
    for (const app::Rect& row : gui.ui().scoreboard.rowRects)
        EXPECT_LE(row.x1, panel->InnerRect.Max.x + 0.5f)
            << "a column is cut at the panel's edge (" << panel->InnerRect.Max.x << ")";

    // a click on the better dipole's G row solos it in the pencil plot on channel G
    const app::ScoreboardPanelState& ps = gui.ui().scoreboard;
    ASSERT_EQ(ps.rowRects.size(), rows.size());
    size_t k = 0;
    while (k < rows.size() && !(rows[k].score.model == "better_dipole" && rows[k].channel == 1))
        ++k;
    ASSERT_LT(k, rows.size());
    testsupport::click(gui, ps.rowRects[k]);
    EXPECT_EQ(wb.plotSettings().solo, "materials/better_dipole.bssrdf");
    EXPECT_EQ(wb.plotSettings().channel, 1);
    gui.frame();
    EXPECT_NE(testsupport::panelWindow(app::PanelId::Pencil), nullptr);
    fs::remove_all(root);
}
