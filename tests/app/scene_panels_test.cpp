// The scene panels headless: Point cloud (every colour mode), Octree (levels, decoder, the
// traced nodes), Irradiance (every light mode), Render (every heatmap) and the traversal
// debugger draw with a real scene and leave no problem behind; the rendered bunny is on
// screen.
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "gui/gui.h"

#include <cstdlib>

namespace {

// A pixel of the last frame that shows the surface (the first one found from the centre out).
std::pair<int, int> hitPixel(app::SceneStage& scene) {
    render::Readback rb = scene.readback();
    for (int r = 0; r < rb.width; ++r)
        for (int dy = -r; dy <= r; ++dy)
            for (int dx = -r; dx <= r; ++dx) {
                const int x = rb.width / 2 + dx, y = rb.height / 2 + dy;
                if (x < 0 || y < 0 || x >= rb.width || y >= rb.height) continue;
                if (rb.position[rb.index(x, y)].w > 0.5f) return {x, y};
            }
    return {-1, -1};
}

} // namespace

TEST(ScenePanels, EveryPanelAndModeDraws) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("scenepanels", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1600, 1000);
    app::UiState& ui = gui.ui();
    ui.shared.isOpen(app::PanelId::Octree) = ui.shared.isOpen(app::PanelId::Irradiance) =
        ui.shared.isOpen(app::PanelId::Traversal) = true;
    app::SceneSettings& s = wb.scene().settings();
    testsupport::useSmallScene(s);
    s.light.occludedTotalSamples = 8;
    gui.frame(); // enables the scene (its panels are open)
    ASSERT_TRUE(s.enabled);
    wb.finishScene();
    gui.frame();
    ASSERT_TRUE(wb.scene().hasFrame());
    EXPECT_EQ(wb.scene().cloud().points.size(), 3000u);

    const auto [x, y] = hitPixel(wb.scene());
    ASSERT_GE(x, 0);
    ui.shared.inspect.debug = wb.scene().debugPixel(x, y);
    ASSERT_TRUE(ui.shared.inspect.debug->hit);
    EXPECT_FALSE(ui.shared.inspect.debug->trace.steps.empty());
    ui.shared.show(app::PanelId::PointCloud);
    for (int c = 0; c < 4; ++c) {
        ui.shared.inspect.colorBy = static_cast<app::PointColor>(c);
        gui.frame();
        EXPECT_NE(testsupport::panelWindow(app::PanelId::PointCloud), nullptr);
    }
    const std::vector<glm::vec4> brute = wb.scene().bruteForceExitance();
    // the pass belongs to the displayed frame
    ASSERT_NE(wb.scene().comparison().bruteForceResult(), nullptr);
    EXPECT_EQ(brute.size(), size_t(96 * 54));
    ui.shared.show(app::PanelId::Render);
    for (int h = 0; h < 4; ++h) {
        ui.render.heatmap = static_cast<app::Heatmap>(h);
        gui.frame();
    }
    ui.shared.show(app::PanelId::Octree);
    for (int level = 0; level <= wb.scene().tree()->stats.maxDepth; ++level) {
        ui.octree.level = level;
        ui.octree.selectedNode = level * 7;
        gui.frame();
        EXPECT_NE(testsupport::panelWindow(app::PanelId::Octree), nullptr);
    }
    ui.shared.inspect.highlightTrace = false;
    gui.frame();
    ui.shared.show(app::PanelId::Irradiance);
    for (auto mode : {irradiance::LightMode::Filtered, irradiance::LightMode::Ibl,
                      irradiance::LightMode::OccludedIbl, irradiance::LightMode::Directional}) {
        s.light.mode = mode;
        gui.frame();
        wb.finishScene();
        gui.frame();
        EXPECT_TRUE(wb.errors().empty()) << int(mode) << ": " << wb.errors().front().text;
    }
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;

    // The Render panel (the centre area, default layout) shows the lit bunny: bright pixels.
    ui.shared.show(app::PanelId::Render);
    gui.frame();
    for (auto id : {app::PanelId::Render, app::PanelId::Traversal})
        EXPECT_NE(testsupport::panelWindow(id), nullptr) << app::panelEntry(id).title;
    auto px = gui.pixels();
    size_t bright = 0;
    for (int yy = 100; yy < 480; ++yy)
        for (int xx = 350; xx < 960; ++xx) {
            const size_t i = (size_t(yy) * 1600 + size_t(xx)) * 4;
            bright += px[i] > 150 && px[i + 1] > 150 && px[i + 2] > 150 ? 1 : 0;
        }
    EXPECT_GT(bright, 2000u);

    // The traversal debugger copies its steps as CSV: a comment, a header, a line a step.
    ImGui::SetClipboardText("");
    testsupport::click(gui, ui.traversal.copySteps);
    const std::string csv = ImGui::GetClipboardText();
    EXPECT_EQ(size_t(std::count(csv.begin(), csv.end(), '\n')),
              ui.shared.inspect.debug->trace.steps.size() + 2)
        << csv.substr(0, 400);
    EXPECT_EQ(csv.find("# traversal of pixel (" + std::to_string(x) + ", " + std::to_string(y)), 0u)
        << csv.substr(0, 400);
    EXPECT_NE(csv.find("\n0,0,0,recurse,"), std::string::npos) << csv.substr(0, 400);
    // For looking at the panels: BW_SCENE_PANELS_PNG=/tmp/x.png saves what was drawn.
    if (const char* out = std::getenv("BW_SCENE_PANELS_PNG")) gl::writePng(out, 1600, 1000, px);
    std::filesystem::remove_all(root);
}

// Occluded IBL is progressive: the Irradiance panel says how many of the K samples the E_t in
// use averages (kept, marked stopped, when the user stops it), how long the last step took and
// the standard error of that mean, which it takes from the stage's own per-point errors.
TEST(ScenePanels, OccludedIblSaysWhichSamplesItAveragesAndTheirStandardError) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("occludedpanel", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1600, 1000);
    app::UiState& ui = gui.ui();
    app::SceneSettings& s = wb.scene().settings();
    testsupport::useSmallScene(s);
    s.light.mode = irradiance::LightMode::Directional;
    ui.shared.show(app::PanelId::Irradiance);
    gui.frame(); // enables the scene (its panel is open)
    wb.finishScene();
    std::string text = testsupport::panelText(gui, app::PanelId::Irradiance);
    EXPECT_NE(text.find("first pass (E_t at the points): "), std::string::npos) << text;
    {
        // "run once" / "run N times", as often as the stage ran
        const auto st = wb.scene().stats().find("scene.irradiance");
        ASSERT_NE(st, wb.scene().stats().end());
        const long long runs = st->second.runs;
        const std::string said =
            runs == 1 ? "run once (" : "run " + std::to_string(runs) + " times (";
        EXPECT_NE(text.find(said + "it runs again only when the light or the points change)"),
                  std::string::npos)
            << said << "\n"
            << text;
    }

    s.light.mode = irradiance::LightMode::OccludedIbl;
    s.light.occludedTotalSamples = 12;
    s.light.occludedSamplesPerStep = 4;
    text = testsupport::panelText(gui, app::PanelId::Irradiance); // its update takes one step
    app::SceneStage& scene = wb.scene();
    ASSERT_TRUE(scene.occludedRunning());
    ASSERT_EQ(scene.occludedSamplesDone(), 4);
    EXPECT_NE(text.find("4 / 12 samples"), std::string::npos) << text;
    EXPECT_NE(text.find("progressive: "), std::string::npos) << text;
    EXPECT_NE(text.find("ms for the last step of 4 samples"), std::string::npos) << text;
    // Σ standard error / Σ E_t over the points, per channel, from the stage's estimates
    irradiance::Stage& stage = *scene.irradianceStage();
    const std::vector<glm::vec3> mean = stage.occludedResult(), se = stage.occludedStdError();
    ASSERT_EQ(mean.size(), scene.cloud().points.size());
    ASSERT_EQ(se.size(), mean.size());
    glm::dvec3 sumSe(0.0), sumE(0.0);
    for (size_t i = 0; i < mean.size(); ++i) {
        sumSe += glm::dvec3(se[i]);
        sumE += glm::dvec3(mean[i]);
    }
    char expected[160];
    std::snprintf(expected, sizeof expected, "standard error: R %.2g %%, G %.2g %%, B %.2g %%",
                  100 * sumSe.x / sumE.x, 100 * sumSe.y / sumE.y, 100 * sumSe.z / sumE.z);
    EXPECT_NE(text.find(expected), std::string::npos) << expected << "\n" << text;
    EXPECT_GT(sumSe.x, 0.0); // four shadow maps over a lit bunny do not agree everywhere
    EXPECT_LT(sumSe.x, sumE.x);

    // Stopped: the estimate of 4 samples stays in use and the panel says so.
    scene.cancelOccluded();
    text = testsupport::panelText(gui, app::PanelId::Irradiance);
    EXPECT_FALSE(scene.occludedRunning());
    EXPECT_NE(text.find("4 / 12 samples, stopped"), std::string::npos) << text;
    EXPECT_NE(text.find("standard error: R "), std::string::npos) << text;

    // A change of the light starts over and runs to its K.
    s.light.occludedTotalSamples = 8;
    for (int k = 0; k < 20 && (k == 0 || scene.occludedRunning()); ++k)
        gui.frame();
    ASSERT_FALSE(scene.occludedRunning());
    text = testsupport::panelText(gui, app::PanelId::Irradiance);
    EXPECT_NE(text.find("8 / 8 samples"), std::string::npos) << text;
    EXPECT_EQ(text.find("stopped"), std::string::npos) << text;
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    std::filesystem::remove_all(root);
}
