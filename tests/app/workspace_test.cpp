// The workspace layout: the tiling alone (areas inside the window, no overlaps, the limits, the
// splitters), then the real GUI headless at 800×600, 1280×720 and 1920×1080 — read from
// ImGui's window rectangles, no panel leaves the viewport and no two docked areas overlap;
// every panel is shown in its area on request; a splitter drags with injected mouse input; a
// floating panel saved on a large screen comes back inside a small one; every panel's content
// fits its width, idle at the three sizes and busy at the smallest.
// BW_LAYOUT_PNG_DIR=docs/ saves the screenshots of the three sizes (docs/layout-WxH.png);
// BW_PANEL_PNG_DIR=DIR one per panel and size, and busy-PANEL.png of the busy panels, to look at.
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "../support/small_scene.h"
#include "gui/gui.h"
#include "gui/panels/panels.h"
#include "gui/panels/registry.h"
#include "gui/widgets.h"
#include "gui/workspace_layout.h"

#include <imgui.h>
#include <imgui_internal.h>

#include <cstdlib>
#include <random>

namespace {
namespace fs = std::filesystem;
using app::Area;
using app::idx;
using app::Rect;

// Every present area lies in the view, no two present areas overlap, splitters sit between.
void expectTiled(const app::WorkspaceRects& t, const Rect& view) {
    for (size_t a = 0; a < app::kAreaCount; ++a) {
        if (!t.present[a]) continue;
        EXPECT_TRUE(view.contains(t.area[a])) << app::areaName(Area(a));
        EXPECT_GT(t.area[a].width(), 0.0f) << app::areaName(Area(a));
        EXPECT_GT(t.area[a].height(), 0.0f) << app::areaName(Area(a));
        for (size_t b = a + 1; b < app::kAreaCount; ++b)
            if (t.present[b]) {
                EXPECT_FALSE(t.area[a].overlaps(t.area[b]))
                    << app::areaName(Area(a)) << " / " << app::areaName(Area(b));
            }
        for (size_t s = 0; s < app::kSplitterCount; ++s)
            if (t.splitterPresent[s]) {
                EXPECT_FALSE(t.splitter[s].overlaps(t.area[a]));
            }
    }
}

} // namespace

TEST(WorkspaceTiling, AreasStayInsideAndApartForAnySizeAndSplit) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> frac(0.0f, 1.0f), size(200.0f, 2600.0f);
    for (int trial = 0; trial < 2000; ++trial) {
        const Rect view{0, 19, size(rng), 19 + size(rng)};
        app::WorkspaceSplits s{frac(rng), frac(rng), frac(rng), frac(rng)};
        std::array<bool, app::kAreaCount> occ{};
        for (auto& o : occ)
            o = frac(rng) < 0.6f;
        const app::WorkspaceRects t = app::tileWorkspace(view, s, occ);
        expectTiled(t, view);
        EXPECT_TRUE(t.present[idx(Area::Centre)]);
        for (size_t a = 0; a < app::kAreaCount; ++a)
            if (a != idx(Area::Centre)) {
                EXPECT_EQ(t.present[a], occ[a]);
            }
    }
}

TEST(WorkspaceTiling, LimitsHoldFrom800x600AndSplittersMoveTheirBoundary) {
    const app::WorkspaceLimits lim;
    std::array<bool, app::kAreaCount> all;
    all.fill(true);
    for (auto [w, h] : {std::pair{800.0f, 600.0f}, {1280.0f, 720.0f}, {1920.0f, 1080.0f}}) {
        const Rect view{0, 19, w, h};
        for (float f : {0.0f, 0.5f, 1.0f}) {
            const app::WorkspaceRects t =
                app::tileWorkspace(view, app::WorkspaceSplits{f, f, f, f}, all);
            expectTiled(t, view);
            EXPECT_GE(t.area[idx(Area::Centre)].width(), lim.minCentre - 0.5f) << w << " " << f;
            EXPECT_GE(t.area[idx(Area::LeftTop)].width(), lim.minSide - 0.5f);
            EXPECT_GE(t.area[idx(Area::Right)].width(), lim.minSide - 0.5f);
            EXPECT_GE(t.area[idx(Area::Bottom)].height(), lim.minBottom - 0.5f);
            EXPECT_GE(t.area[idx(Area::Centre)].height(), lim.minMain - 0.5f);
        }
    }
    // Dragging the left splitter 40 px right widens the left column by 40 px.
    const Rect view{0, 19, 1280, 720};
    app::WorkspaceSplits s;
    const auto before = app::tileWorkspace(view, s, all);
    app::dragSplitter(s, app::Splitter::Left, 40, view, before);
    app::dragSplitter(s, app::Splitter::Bottom, -30, view, before);
    const auto after = app::tileWorkspace(view, s, all);
    EXPECT_NEAR(after.area[idx(Area::LeftTop)].width(),
                before.area[idx(Area::LeftTop)].width() + 40, 0.01);
    EXPECT_NEAR(after.area[idx(Area::Bottom)].height(),
                before.area[idx(Area::Bottom)].height() + 30, 0.01);
    // A floating window saved on a larger screen is moved (and shrunk) back inside.
    const Rect in = app::clampInto({1500, 900, 2400, 1500}, view);
    EXPECT_TRUE(view.contains(in));
    EXPECT_NEAR(in.width(), 900, 0.01);
}

using testsupport::expectFitsItsWidth;
using testsupport::panelWindow;
using testsupport::rectOf;
using testsupport::topWindows;

TEST(WorkspaceLayout, EveryPanelFitsTheWindowAt800x600To1920x1080AndUiScales1To2) {
    testsupport::context();
    // every shipped model, as the workbench starts on the project (the Models panel lists them
    // all, with their parameters)
    std::vector<std::string> models;
    for (const auto& e : fs::directory_iterator(testsupport::sourceRoot() / "materials"))
        if (e.path().extension() == ".bssrdf") models.push_back(e.path().filename().string());
    auto root = testsupport::makeProjectRoot("layout3", models);
    app::Workbench wb(root, false);
    wb.scene().settings().render.width = 64;
    wb.scene().settings().render.height = 36;
    const char* pngDir = std::getenv("BW_LAYOUT_PNG_DIR");
    if (pngDir) { // a picture worth looking at
        wb.scene().settings().render.width = 320;
        wb.scene().settings().render.height = 180;
    }
    // (1304x744: a size where the Render panel flipped between two layouts every frame; at UI
    // scales 2 and 1.5, a 4K screen at 200 % and a laptop's at 150 %: the same layout in UI
    // units with the text rasterised at the screen's pixels)
    struct Size {
        int w, h;
        float scale;
    };
    for (auto [w, h, scale] : {Size{800, 600, 1},
                               {1280, 720, 1},
                               {1304, 744, 1},
                               {1920, 1080, 1},
                               {800, 600, 2},
                               {1280, 720, 1.5f}}) {
        SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " at UI scale " +
                     std::to_string(scale));
        app::HeadlessGui gui(wb, w, h, scale);
        app::UiState& ui = gui.ui();
        ui = app::UiState{};
        for (const auto& p : app::panelRegistry())
            ui.shared.isOpen(p.id) = true;
        gui.frame();
        wb.finishScene(); // the panels with their images
        gui.frame();
        const Rect viewport{0, 0, float(w), float(h)};
        std::vector<Rect> areas;
        for (ImGuiWindow* win : topWindows()) {
            EXPECT_TRUE(viewport.contains(rectOf(win))) << win->Name;
            if (std::string(win->Name).rfind("##area.", 0) == 0) areas.push_back(rectOf(win));
        }
        EXPECT_EQ(areas.size(), app::kAreaCount);
        for (size_t a = 0; a < areas.size(); ++a)
            for (size_t b = a + 1; b < areas.size(); ++b)
                EXPECT_FALSE(areas[a].overlaps(areas[b])) << a << " " << b;
        if (pngDir) {
            wb.finishScene(); // the rendered bunny in the picture, not "waiting"
            gui.frame();
            if (scale == 1)
                gl::writePng((fs::path(pngDir) /
                              ("layout-" + std::to_string(w) + "x" + std::to_string(h) + ".png"))
                                 .string(),
                             w, h, gui.pixels());
        }
        // Every panel comes to the front of its area on request, inside the viewport.
        for (const auto& p : app::panelRegistry()) {
            ui.shared.show(p.id);
            gui.frame();
            ImGuiWindow* pw = panelWindow(p.id);
            ASSERT_NE(pw, nullptr) << p.title;
            EXPECT_TRUE(viewport.contains(rectOf(pw))) << p.title;
            expectFitsItsWidth(gui, p.id);
            if (const char* dir = std::getenv("BW_PANEL_PNG_DIR"))
                gl::writePng(
                    (fs::path(dir) / (std::string(p.iniKey) + "-" + std::to_string(w) + "x" +
                                      std::to_string(h) + "@" + core::formatNumber(scale) + ".png"))
                        .string(),
                    gui.pixelWidth(), gui.pixelHeight(), gui.pixels());
        }
        // A floating panel stays inside the viewport too, and docks back.
        ui.shared.workspace.floating[size_t(app::PanelId::Render)] = true;
        ui.shared.workspace.floatRect[size_t(app::PanelId::Render)] = {1500, 900, 2600, 1700};
        gui.frame();
        gui.frame();
        ImGuiWindow* fw = ImGui::FindWindowByName("Render###Render");
        ASSERT_NE(fw, nullptr);
        EXPECT_TRUE(fw->Active);
        EXPECT_TRUE(viewport.contains(rectOf(fw)));
        ui.shared.workspace.floating[size_t(app::PanelId::Render)] = false;
        gui.frame();
        EXPECT_FALSE(ImGui::FindWindowByName("Render###Render")->Active);
    }
    EXPECT_TRUE(wb.errors().empty());
    fs::remove_all(root);
}

// At the smallest window the layout supports, the panels with everything they show while
// working — the reference's progress, the lit spheres' images and statistics, the BSSRDF
// slice's maps, each renderer's controls, the A/B split, a traced pixel, a long error, a model
// with a long name — still fit their width.
TEST(WorkspaceLayout, BusyPanelsFitTheirWidthAt800x600) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("layoutbusy", {"dipole.bssrdf"});
    // and a model whose name is wider than any panel (File → New model takes any length)
    fs::copy_file(root / "materials" / "dipole.bssrdf",
                  root / "materials" /
                      "a_dipole_for_the_skin_of_the_back_of_the_left_hand_measured_in_june.bssrdf");
    app::Workbench wb(root, false);
    testsupport::useSmallScene(wb.scene().settings());
    wb.referenceSettings().enabled = true;
    wb.referenceSettings().paths = 20000;
    app::LitSphereSettings& ls = wb.litSphereSettings();
    ls.enabled = true;
    ls.size = 16;
    ls.pathSpp = 2;
    ls.integratedSpp = 16;
    app::SliceSettings& sl = wb.sliceSettings();
    sl.enabled = true;
    sl.rBins = 6;
    sl.thetaSBins = 4;
    sl.paths = 20000;
    sl.device = app::TracerDevice::Cpu;
    wb.reportActionError(
        "materials/dipole.bssrdf:12: a long problem, as a compiler writes them, that names the "
        "file, the line and what was expected there: 'Bssrdf' : no matching overloaded function "
        "found (a word_without_a_single_space_in_it_that_is_wider_than_the_errors_panel_is)");
    app::HeadlessGui gui(wb, 800, 600);
    app::UiState& ui = gui.ui();
    for (const auto& p : app::panelRegistry())
        ui.shared.isOpen(p.id) = true;
    gui.frame();
    wb.finishScene();
    wb.finishLitSpheres();
    wb.finishSlice(); // its heat maps, legend and the hovered cell's figures
    ui.shared.inspect.debug = wb.scene().debugPixel(48, 27);
    ui.render.abSplit = true;
    const char* dir = std::getenv("BW_PANEL_PNG_DIR");
    for (const auto& p : app::panelRegistry()) {
        SCOPED_TRACE(p.title);
        ui.shared.show(p.id);
        expectFitsItsWidth(gui, p.id);
        if (dir)
            gl::writePng((fs::path(dir) / (std::string("busy-") + p.iniKey + ".png")).string(), 800,
                         600, gui.pixels());
    }
    // the A/B split's labels, the long model's name on the A side, each on its own side
    ui.shared.show(app::PanelId::Render);
    for (int k = 0; k < 3; ++k)
        gui.frame();
    const app::Rect* labels = ui.render.abLabels;
    ASSERT_GT(labels[0].width(), 0.0f);
    ASSERT_GT(labels[1].width(), 0.0f) << "no B label: the brute-force side is not drawn";
    EXPECT_FALSE(labels[0].overlaps(labels[1]))
        << "A ends at " << labels[0].x1 << ", B starts at " << labels[1].x0;
    const float divider = ui.render.imageRect.x0 + ui.render.split * ui.render.imageRect.width();
    EXPECT_LE(labels[0].x1, divider);
    EXPECT_LE(labels[1].x1, ui.render.imageRect.x1);
    for (auto mode : {app::RenderMode::MonteCarlo, app::RenderMode::TextureSpace}) {
        ui.render.mode = mode;
        for (bool hybrid : {false, true}) {
            SCOPED_TRACE(std::to_string(int(mode)) + (hybrid ? " hybrid" : ""));
            wb.textureSpaceSettings().sampling.hybrid = hybrid;
            expectFitsItsWidth(gui, app::PanelId::Render);
        }
    }
    fs::remove_all(root);
}

// Wrapped text breaks at spaces, never inside a number; a word wider than the line is cut.
TEST(WorkspaceLayout, TextBreaksAtSpacesAndCutsOnlyAWordWiderThanTheLine) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("layoutbreak", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 800, 600);
    gui.frame(); // the font
    auto width = [](const char* s) { return ImGui::CalcTextSize(s).x; };
    EXPECT_EQ(app::breakLines("depth 6, 1.66 MiB", width("depth 6, 1.6")), "depth 6,\n1.66 MiB");
    EXPECT_EQ(app::breakLines("abcdefghij", width("abcd")), "abcd\nefgh\nij");
    EXPECT_EQ(app::breakLines("x abcdefghij", width("abcd")), "x\nabcd\nefgh\nij");
    EXPECT_EQ(app::breakLines("aaaa    bbbb", width("aaaa b")), "aaaa\nbbbb");
    EXPECT_EQ(app::breakLines("GPU  %   1.5", 1000), "GPU  %   1.5"); // spaces kept in a line
    EXPECT_EQ(app::breakLines("one\n  two three", width("  two")), "one\n  two\nthree");
    EXPECT_EQ(app::breakLines("", 100), "");
    fs::remove_all(root);
}

// The menu bar's right end (problems, hot reload, the last status) ends inside the window at
// 800×600 and UI scale 2, however long the status: a long one is cut, whole characters at a
// time, and shown whole on hover. (It used to start at a fixed 360 units from the right edge
// and run past it.)
TEST(WorkspaceLayout, TheMenuBarsStatusEndsInsideTheWindow) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("layoutstatus", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.reportActionError("a problem, so that the bar says how many");
    for (float scale : {1.0f, 2.0f}) {
        SCOPED_TRACE(scale);
        app::HeadlessGui gui(wb, 800, 600, scale);
        app::UiState& ui = gui.ui();
        ui = app::UiState{};
        ui.shared.isOpen(app::PanelId::Render) = false; // no scene needed here
        for (const std::string& status :
             {std::string("opened dipole.bssrdf"), "created materials/" + std::string(40, 'x') +
                                                       "_\xc3\xa9t\xc3\xa9_\xc3\xa9t\xc3\xa9_" +
                                                       std::string(30, 'y') + ".bssrdf"}) {
            ui.shared.status = status;
            gui.frame();
            gui.frame();
            ImGuiWindow* bar = ImGui::FindWindowByName("##MainMenuBar");
            ASSERT_NE(bar, nullptr);
            // where the last item ends (ImGui 1.86 keeps no item extent of a menu bar)
            const float end = bar->DC.CursorPosPrevLine.x;
            const float edge = bar->Pos.x + bar->Size.x - ImGui::GetStyle().WindowPadding.x;
            EXPECT_LE(end, edge + 0.5f) << status;
            EXPECT_GT(end, bar->Pos.x + 0.6f * bar->Size.x) << status; // right-aligned
            if (status.size() > 60) {                                  // cut to fit
                EXPECT_NEAR(end, edge, 12.0f * scale) << status;
            }
        }
        // whole characters
        auto width = [](const std::string& s) { return ImGui::CalcTextSize(s.c_str()).x; };
        const std::string cut = app::cutToWidth("ab\xc3\xa9\xc3\xa9\xc3\xa9"
                                                "cd",
                                                width("ab\xc3\xa9..."));
        EXPECT_EQ(cut, "ab\xc3\xa9...");
        EXPECT_EQ(app::cutToWidth("\xc3\xa9\xc3\xa9\xc3\xa9\xc3\xa9", width("...")), "...");
    }
    fs::remove_all(root);
}

TEST(WorkspaceLayout, SplitterDragsWithTheMouseAndTabsFollowShowRequests) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("layoutdrag", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui = app::UiState{};
    ui.shared.isOpen(app::PanelId::Render) = false; // no scene needed here
    gui.frame();
    gui.frame();
    ImGuiWindow* left = ImGui::FindWindowByName("##area.left-top");
    ASSERT_NE(left, nullptr);
    const float before = left->Size.x;
    // press on the splitter right of the left column, drag 60 px right, release
    const float x = left->Pos.x + left->Size.x + 3, y = 300;
    gui.mouse(x, y, false);
    gui.frame();
    gui.mouse(x, y, true);
    gui.frame();
    for (int i = 1; i <= 6; ++i) {
        gui.mouse(x + 10.0f * float(i), y, true);
        gui.frame();
    }
    gui.mouse(x + 60, y, false);
    gui.frame();
    gui.noMouse();
    gui.frame();
    EXPECT_NEAR(ImGui::FindWindowByName("##area.left-top")->Size.x, before + 60, 1.0);

    // show() selects a tab in this very frame; the area keeps it afterwards
    ui.shared.show(app::PanelId::Octree);
    EXPECT_TRUE(app::shownPanels(ui.shared)[size_t(app::PanelId::Octree)]);
    gui.frame();
    EXPECT_NE(panelWindow(app::PanelId::Octree), nullptr);
    gui.frame();
    EXPECT_NE(panelWindow(app::PanelId::Octree), nullptr);
    EXPECT_EQ(panelWindow(app::PanelId::Pencil), nullptr);
    EXPECT_TRUE(wb.scene().settings().enabled); // the octree needs the scene
    ui.shared.show(app::PanelId::Pencil);
    gui.frame();
    EXPECT_FALSE(wb.scene().settings().enabled);
    fs::remove_all(root);
}

// At 800×600 the centre area's tabs do not fit: its ◀ ▶ arrows select the previous / next tab
// (real clicks), every tab is reachable that way and scrolled into view, and a narrower window
// scrolls the selected tab into view again.
TEST(WorkspaceLayout, TabBarArrowsReachEveryTabAt800x600) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("tabarrows", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 800, 600);
    app::UiState& ui = gui.ui();
    ui = app::UiState{};
    ui.shared.isOpen(app::PanelId::Render) = false; // no scene needed here
    std::vector<app::PanelId> centre;
    for (const auto& p : app::panelRegistry())
        if (p.area == app::Area::Centre) {
            ui.shared.isOpen(p.id) = true;
            centre.push_back(p.id);
        }
    ASSERT_GE(centre.size(), 6u);
    ui.shared.show(centre.front());
    for (int i = 0; i < 3; ++i)
        gui.frame();
    ImGuiWindow* area = ImGui::FindWindowByName("##area.centre");
    ASSERT_NE(area, nullptr);
    ImGuiTabBar* bar = ImGui::GetCurrentContext()->TabBars.GetByKey(area->GetID("tabs"));
    ASSERT_NE(bar, nullptr);
    ASSERT_GT(bar->WidthAllTabsIdeal, area->WorkRect.GetWidth()) << "the tabs fit: no arrows";
    // the arrows sit at the bar's right end, ▶ last (imgui's TabBarScrollingButtons)
    const float arrowW = ImGui::GetFontSize() - 2.0f;
    const float y = 0.5f * (bar->BarRect.Min.y + bar->BarRect.Max.y);
    auto click = [&](float x) {
        testsupport::clickAt(gui, x, y);
        for (int i = 0; i < 30; ++i) // let the bar's scrolling settle
            gui.frame();
    };
    const float right = area->WorkRect.Max.x - 0.5f * arrowW, left = right - arrowW;
    auto selectedTabVisible = [&] {
        const ImGuiTabItem* t = ImGui::TabBarFindTabByID(bar, bar->SelectedTabId);
        if (!t) return false;
        const float x0 = bar->BarRect.Min.x + t->Offset - bar->ScrollingAnim;
        return x0 >= bar->ScrollingRectMinX - 1 && x0 + t->Width <= bar->ScrollingRectMaxX + 1;
    };
    const int at = [&] { return ui.shared.workspace.selected[size_t(app::Area::Centre)]; }();
    EXPECT_EQ(at, int(centre.front()));
    std::vector<int> reached{at};
    for (size_t k = 1; k < centre.size(); ++k) {
        click(right);
        const int now = ui.shared.workspace.selected[size_t(app::Area::Centre)];
        EXPECT_EQ(now, int(centre[k])) << "after " << k << " clicks on the right arrow";
        EXPECT_NE(panelWindow(centre[k]), nullptr) << app::panelEntry(centre[k]).title;
        EXPECT_TRUE(selectedTabVisible()) << app::panelEntry(centre[k]).title;
        reached.push_back(now);
    }
    EXPECT_EQ(reached.size(), centre.size());
    click(left);
    EXPECT_EQ(ui.shared.workspace.selected[size_t(app::Area::Centre)],
              int(centre[centre.size() - 2]));
    EXPECT_TRUE(selectedTabVisible());

    // the last tab, selected in a wide window, is scrolled into view when the window narrows
    gui.resize(1920, 1080);
    ui.shared.show(centre.back());
    for (int i = 0; i < 30; ++i)
        gui.frame();
    gui.resize(800, 600);
    for (int i = 0; i < 30; ++i)
        gui.frame();
    EXPECT_EQ(ui.shared.workspace.selected[size_t(app::Area::Centre)], int(centre.back()));
    EXPECT_TRUE(selectedTabVisible());
    fs::remove_all(root);
}
