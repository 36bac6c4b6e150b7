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
