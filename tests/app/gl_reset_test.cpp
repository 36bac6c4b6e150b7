// Recovery from a GPU driver reset (gui.h, kGlResetRestart; gl/reset.cpp). No driver here
// resets, so the reset is simulated ($BSSRDF_WORKBENCH_SIMULATE_GL_RESET=N: the N-th status
// query on reports a reset this program caused). The GUI saves the workbench's state and the
// program starts again on a new context from it, with an Errors entry naming the reset; nothing
// the user set is lost and nothing hangs.
#include "../support/cli_runner.h"
#include "../support/gl_fixture.h"
#include "capture/capture.h"
#include "captures/manifest.h"
#include "captures/settings_json.h"
#include "core/core.h"
#include "gui/gui.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace fs = std::filesystem;

// In process: runGui stops at the reset with kGlResetRestart and saves the state; the workbench
// rebuilt from it has the same models, parameters and settings as before, and the Errors entry.
TEST(GlReset, TheGuiSavesItsStateAndTheRestartedWorkbenchHasIt) {
    ASSERT_EQ(setenv("BSSRDF_WORKBENCH_SIMULATE_GL_RESET", "2", 1), 0);
    auto ctx = gl::createHeadlessContext();
    auto root = testsupport::makeProjectRoot("glreset", {"dipole.bssrdf", "multipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Ketchup");
    wb.referenceSettings().paths = 123457;
    wb.update();
    const nlohmann::json params = app::paramsJson(wb);
    app::GuiOptions opt;
    opt.width = 640;
    opt.height = 400;
    opt.frames = 5;
    opt.persistLayout = false;
    EXPECT_EQ(app::runGui(wb, *ctx, opt), app::kGlResetRestart);
    ASSERT_TRUE(fs::exists(app::glResetRequest(root)));
    // the state as the reset found it (the scene's background work may move on after it)
    nlohmann::json settings = capture::readInputs(app::glResetRequest(root)).settings;
    EXPECT_EQ(settings["reference"]["paths"], 123457);
    settings.erase("r_max_mm"); // informational, derived by the next update
    unsetenv("BSSRDF_WORKBENCH_SIMULATE_GL_RESET");
    std::unique_ptr<app::Workbench> again = app::workbenchAfterReset(root, false);
    nlohmann::json restored = app::settingsJson(*again, -1, -1);
    restored.erase("r_max_mm");
    EXPECT_EQ(restored.dump(), settings.dump());
    EXPECT_EQ(app::paramsJson(*again).dump(), params.dump());
    EXPECT_EQ(again->library().entries().size(), wb.library().entries().size());
    bool named = false;
    for (const app::ErrorItem& e : again->errors())
        named |= e.text.find("GPU: the GPU driver reset the OpenGL context, after GPU work of "
                             "this program hung or faulted; the workbench started again") == 0;
    EXPECT_TRUE(named);
    EXPECT_FALSE(fs::exists(app::glResetRequest(root).parent_path())); // read once, then gone
    fs::remove_all(root);
}

// The program: `screenshot` meets the reset at its second query, starts itself again with the
// saved state on a new context, and writes the image, with the Errors entry in its log. A bad
// value of the variable is an error naming it.
TEST(GlReset, TheProgramStartsAgainOnANewContextAndFinishes) {
    auto root = testsupport::makeProjectRoot("glresetcli", {"dipole.bssrdf"});
    auto run = [&](const char* simulate) {
        setenv("BSSRDF_WORKBENCH_SIMULATE_GL_RESET", simulate, 1);
        clitest::RunResult r =
            clitest::runCommand({BW_EXE, "--root", root.string(), "screenshot", "--out", "shot.png",
                                 "--size", "640x400", "--frames", "3"},
                                root);
        unsetenv("BSSRDF_WORKBENCH_SIMULATE_GL_RESET");
        return r;
    };
    clitest::RunResult r = run("2");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(root / "shot.png")) << r.output;
    EXPECT_NE(r.output.find("the workbench starts again on a new context with its state"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("started again on a new OpenGL context with the state it had"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(app::glResetRequest(root).parent_path()));
    r = run("soon");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("BSSRDF_WORKBENCH_SIMULATE_GL_RESET"), std::string::npos) << r.output;
    // and so is a bad deadline for the GPU waits (gl/waits.cpp)
    setenv("BSSRDF_WORKBENCH_GPU_WAIT_SECONDS", "-1", 1);
    r = clitest::runCommand({BW_EXE, "--root", root.string(), "screenshot", "--out", "shot2.png",
                             "--size", "640x400", "--frames", "1"},
                            root);
    unsetenv("BSSRDF_WORKBENCH_GPU_WAIT_SECONDS");
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.output.find("BSSRDF_WORKBENCH_GPU_WAIT_SECONDS: expected seconds in (0, 86400], "
                            "got '-1'"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(root / "shot2.png"));
    fs::remove_all(root);
}
