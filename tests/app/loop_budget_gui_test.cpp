// A model whose loop runs away only for some parameter values passes its first check and is
// adopted; moved there in the GUI, every consumer the workbench runs (the pencil plot, the lit
// sphere's integration, the scene's renderer) stops at the loop budget (bssrdf/loop_budget.h)
// and the Errors panel names the loop's line, while frames keep coming; moved back, the error goes
// and the plot is what it was. The text "ran past the loop budget" is the budget's own (a driver
// that cut the loop would not write it), so the tests hold on any machine: they wait at most 10 s
// for it and print, not assert, how long it took and the slowest frame (the issue asks for 5 s;
// in Release here the first entry came after 0.04 s, all three after 1.0 s).
#include "../support/gl_fixture.h"
#include "../support/workbench_values.h"
#include "core/core.h"
#include "gui/gui.h"
#include "pipeline/workbench.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

namespace {

const char* kRunaway = "analytic radial no_wi no_wo\n"
                       "::begin parameters\n"
                       "float Knob 0.0 1.0 0.0\n"
                       "::end parameters\n"
                       "::begin shader\n"
                       "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                       "    float x = length(Xo - Xi) + 0.1;\n"
                       "    while (Knob > 0.5) { x = sin(x * 1.37 + 0.11) + cos(x * 0.73); }\n"
                       "    return vec3(0.05 * exp(-x)) * (1.0 + 1e-30 * x);\n"
                       "}\n"
                       "::end shader\n";

} // namespace

TEST(LoopBudgetGui, ARunawayLoopIsAnErrorWhileFramesKeepComing) {
    testsupport::context();
    const auto root = testsupport::makeProjectRoot("loop_budget_gui", {"dipole.bssrdf"});
    core::writeFile(root / "materials" / "runaway.bssrdf", kRunaway);
    const std::string path = "materials/runaway.bssrdf";
    app::Workbench wb(root, false);
    wb.scene().settings().model = path; // the renderer's model
    wb.plotSettings().solo = path;      // the lit sphere's
    auto& ls = wb.litSphereSettings();
    ls.enabled = true;
    ls.size = 32;
    app::HeadlessGui gui(wb, 1280, 800);
    for (int i = 0; i < 3; ++i)
        gui.frame();
    ASSERT_TRUE(wb.library().find(path) && wb.library().find(path)->usable());
    EXPECT_TRUE(testsupport::errorNaming(wb, "runaway").empty())
        << testsupport::errorNaming(wb, "runaway");
    const double before = testsupport::valueAt0(wb, path);
    ASSERT_GT(before, 0.0);

    wb.library().find(path)->values["Knob"] = {1.0f, 1.0f, 1.0f}; // the Models panel's slider
    // every consumer says it: the plot, the renderer, the lit sphere's integration
    auto entries = [&] {
        int n = 0;
        for (const auto& e : wb.errors())
            n += e.text.find(path + ":8: the loop at line 8 ran past") != std::string::npos;
        return n;
    };
    core::Stopwatch clock;
    std::vector<double> frames;
    std::string error;
    double first = -1;
    while (clock.ms() < 10000 && entries() < 3) {
        core::Stopwatch frame;
        gui.frame();
        frames.push_back(frame.ms());
        error = testsupport::errorNaming(wb, path + ":8:");
        if (first < 0 && !error.empty()) first = clock.ms() / 1000.0;
    }
    const double seconds = clock.ms() / 1000.0;
    std::printf("the first error came after %.2f s, all three after %.2f s, %zu frames, the "
                "slowest %.0f ms\n",
                first, seconds, frames.size(), *std::max_element(frames.begin(), frames.end()));
    ASSERT_FALSE(error.empty()) << "no Errors entry at the loop's line after 10 s";
    EXPECT_EQ(entries(), 3);
    EXPECT_NE(error.find("ran past the loop budget"), std::string::npos) << error;
    // frames keep coming, and each consumer says it once
    for (int i = 0; i < 5; ++i)
        gui.frame();
    EXPECT_EQ(entries(), 3);
    EXPECT_NE(wb.litSpheres().problem().find(path + ":8:"), std::string::npos)
        << wb.litSpheres().problem();
    for (const auto& e : wb.errors())
        std::printf("Errors panel: %s\n", e.text.c_str());

    wb.library().find(path)->values["Knob"] = {0.0f, 0.0f, 0.0f};
    EXPECT_TRUE(testsupport::waitFor(wb, [&] {
        return testsupport::errorNaming(wb, path + ":8:").empty();
    })) << testsupport::errorNaming(wb, path + ":8:");
    EXPECT_NEAR(testsupport::valueAt0(wb, path), before, 1e-6 * before);
    std::filesystem::remove_all(root);
}

// The same model in the consumers the GUI runs while their panels show: the texture-space
// renderer and its hybrid mode (the Render panel), the BSSRDF slice and the scoreboard. Each
// names the loop's line in the Errors panel (waited for at most 10 s) while frames keep coming,
// and each recovers when the parameter is back.
TEST(LoopBudgetGui, TextureSpaceHybridSliceAndScoreboardStopToo) {
    testsupport::context();
    const auto root = testsupport::makeProjectRoot("loop_budget_gui2", {"dipole.bssrdf"});
    core::writeFile(root / "materials" / "runaway.bssrdf", kRunaway);
    const std::string path = "materials/runaway.bssrdf";
    app::Workbench wb(root, false);
    wb.scene().settings().model = path; // the texture-space renderer's model
    auto& rs = wb.referenceSettings();  // the scoreboard scores against it
    rs.enabled = true;
    rs.paths = 20000;
    wb.sliceSettings().paths = 20000;
    app::HeadlessGui gui(wb, 1280, 800);
    app::UiState& ui = gui.ui();
    for (app::PanelId id : {app::PanelId::Render, app::PanelId::Slice, app::PanelId::Scoreboard}) {
        ui.shared.workspace.floating[static_cast<size_t>(id)] = true;
        ui.shared.show(id);
    }
    ui.render.mode = app::RenderMode::TextureSpace;
    for (const bool hybrid : {false, true}) {
        SCOPED_TRACE(hybrid ? "hybrid" : "texture space");
        wb.textureSpaceSettings().sampling.hybrid = hybrid;
        for (int i = 0; i < 5; ++i)
            gui.frame();
        ASSERT_TRUE(wb.library().find(path) && wb.library().find(path)->usable());
        ASSERT_TRUE(testsupport::errorNaming(wb, path).empty())
            << testsupport::errorNaming(wb, path);
        ASSERT_TRUE(wb.textureSpaceSettings().enabled && wb.sliceSettings().enabled);
        ASSERT_TRUE(wb.textureSpace().pipeline());
        EXPECT_EQ(wb.textureSpace().pipeline()->hybridTaps().empty(), !hybrid);

        wb.library().find(path)->values["Knob"] = {1.0f, 1.0f, 1.0f};
        const std::vector<std::string> sources{"texture space", "slice", "scoreboard"};
        auto named = [&](const std::string& source) {
            int n = 0;
            for (const auto& e : wb.errors())
                n += e.source == source &&
                     e.text.find(path + ":8: the loop at line 8 ran past") != std::string::npos;
            return n;
        };
        core::Stopwatch clock;
        std::vector<double> frames;
        bool all = false;
        while (clock.ms() < 10000 && !all) {
            core::Stopwatch frame;
            gui.frame();
            frames.push_back(frame.ms());
            all = std::all_of(sources.begin(), sources.end(),
                              [&](const std::string& s) { return named(s) > 0; });
        }
        const double seconds = clock.ms() / 1000.0;
        for (int i = 0; i < 5; ++i) { // frames keep coming
            core::Stopwatch frame;
            gui.frame();
            frames.push_back(frame.ms());
        }
        // A frame may hold one dispatch of the runaway model, which the budget bounds, and the
        // consumers' handling of its error (the slowest frame: 0.06 s in Release, 1.28 s under
        // ASan + UBSan beside another test). A frame waiting on an unbounded loop would not end
        // on a GPU; on llvmpipe the driver would cut it, and the entry would not name the budget.
        std::printf("every consumer named the loop after %.2f s, %zu frames, the slowest %.0f ms\n",
                    seconds, frames.size(), *std::max_element(frames.begin(), frames.end()));
        ASSERT_TRUE(all) << "not every consumer named the loop after 10 s";
        for (const std::string& s : sources)
            EXPECT_EQ(named(s), 1) << s << " (once per consumer)";

        wb.library().find(path)->values["Knob"] = {0.0f, 0.0f, 0.0f};
        clock = core::Stopwatch();
        while (clock.ms() < 10000 && !testsupport::errorNaming(wb, path + ":8:").empty())
            gui.frame();
        EXPECT_EQ(testsupport::errorNaming(wb, path + ":8:"), "");
    }
    std::filesystem::remove_all(root);
}
