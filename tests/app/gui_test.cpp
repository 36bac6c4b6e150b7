// The full GUI headless: every panel draws, the pencil plot exports a PNG of itself, and the
// window layout and panel visibility persist between runs.
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "captures/capture_io.h"
#include "core/core.h"
#include "gui/file_dialog.h"
#include "gui/fonts.h"
#include "gui/gui.h"
#include "gui/panels/panels.h"
#include "gui/panels/registry.h"
#include "pathtrace/image_io.h"
#include "pipeline/pencil_series.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <set>

#include <cstdio>
#include <cstdlib>

namespace {
namespace fs = std::filesystem;

// Decodes width and height from a PNG's IHDR chunk.
std::pair<int, int> pngSize(const fs::path& file) {
    std::string b = core::readFile(file);
    EXPECT_GE(b.size(), 24u);
    EXPECT_EQ(b.substr(1, 3), "PNG");
    auto be32 = [&](size_t o) {
        return (int(uint8_t(b[o])) << 24) | (int(uint8_t(b[o + 1])) << 16) |
               (int(uint8_t(b[o + 2])) << 8) | int(uint8_t(b[o + 3]));
    };
    return {be32(16), be32(20)};
}
} // namespace

TEST(HeadlessGui, DrawsAllPanelsAndExportsThePlotAsPng) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("gui", {"dipole.bssrdf", "better_dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 860);
    gui.ui().shared.show(app::PanelId::Pencil);
    gui.frame();
    gui.frame();
    auto px = gui.pixels();
    ASSERT_EQ(px.size(), 1280u * 860u * 4u);
    // the plot area has curves: count pixels that are neither background nor grey UI
    size_t coloured = 0;
    for (size_t i = 0; i < px.size(); i += 4) {
        int r = px[i], g = px[i + 1], b = px[i + 2];
        coloured += (std::abs(r - g) > 60 || std::abs(g - b) > 60) ? 1 : 0;
    }
    EXPECT_GT(coloured, 1000u);

    const fs::path png = root / "plot.png";
    gui.ui().pencil.plotPngRequest = png.string();
    gui.frame();
    ASSERT_TRUE(fs::exists(png));
    auto [w, h] = pngSize(png);
    EXPECT_GT(w, 300); // the plot widget, not the whole window
    EXPECT_LT(w, 1280);
    EXPECT_GT(h, 200);
    EXPECT_TRUE(wb.errors().empty());

    // an unwritable PNG path becomes an entry in the Errors panel, not a crash
    gui.ui().pencil.plotPngRequest = "/proc/no/such/dir/plot.png";
    gui.frame();
    auto errors = wb.errors();
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_NE(errors[0].text.find("/proc/no/such/dir/plot.png"), std::string::npos);
    fs::remove_all(root);
}

// At UI scale 2 (a 4K screen at 200 %) the UI is laid out in the same units at twice the pixels:
// the image is twice the size, and the plot's PNG is the plot's rectangle in the screen's
// pixels, twice what it is at scale 1.
TEST(HeadlessGui, AtUiScale2ThePixelsAndThePlotsPngAreTwiceAsLarge) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("guiscale", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    std::pair<int, int> size[2];
    for (int scale : {1, 2}) {
        app::HeadlessGui gui(wb, 900, 600, float(scale));
        EXPECT_EQ(gui.pixelWidth(), 900 * scale);
        EXPECT_EQ(gui.pixelHeight(), 600 * scale);
        gui.ui().shared.show(app::PanelId::Pencil);
        gui.frame();
        gui.frame();
        ASSERT_EQ(gui.pixels().size(), size_t(900 * 600 * 4 * scale * scale));
        const fs::path png = root / ("plot" + std::to_string(scale) + ".png");
        gui.ui().pencil.plotPngRequest = png.string();
        gui.frame();
        ASSERT_TRUE(fs::exists(png));
        const float* r = gui.ui().shared.pngRect;
        size[scale - 1] = pngSize(png);
        EXPECT_NEAR(size[scale - 1].first, (r[2] - r[0]) * scale, 1.0);
        EXPECT_NEAR(size[scale - 1].second, (r[3] - r[1]) * scale, 1.0);
    }
    EXPECT_NEAR(size[1].first, 2 * size[0].first, 2);
    EXPECT_NEAR(size[1].second, 2 * size[0].second, 2);
    EXPECT_TRUE(wb.errors().empty());
}

// The window moved to a screen that scales by 2: after the fonts are made again at that size the
// frames are those of a GUI started there (the menu bar and the tab bars pixel for pixel).
TEST(HeadlessGui, AChangedUiScaleDrawsAsAGuiStartedAtIt) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("guirescale", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    std::vector<unsigned char> started;
    {
        app::HeadlessGui gui(wb, 800, 600, 2.0f);
        for (int i = 0; i < 5; ++i)
            gui.frame();
        started = gui.pixels();
    }
    app::HeadlessGui gui(wb, 800, 600, 1.0f);
    for (int i = 0; i < 3; ++i)
        gui.frame();
    gui.setUiScale(2.0f);
    for (int i = 0; i < 5; ++i)
        gui.frame();
    const std::vector<unsigned char> moved = gui.pixels();
    ASSERT_EQ(moved.size(), started.size());
    size_t differ = 0; // the top 45 units: the menu bar's menus and the panels' tab bars
    for (int y = 0; y < 90; ++y)
        for (int x = 0; x < (y < 40 ? 400 : 1600); ++x)
            differ += std::memcmp(&moved[(size_t(y) * 1600 + x) * 4],
                                  &started[(size_t(y) * 1600 + x) * 4], 3) != 0;
    EXPECT_EQ(differ, 0u);
    EXPECT_TRUE(wb.errors().empty());
}

TEST(HeadlessGui, LayoutAndPanelVisibilityPersist) {
    auto& ctx = testsupport::context();
    auto root = testsupport::makeProjectRoot("layout", {"dipole.bssrdf"});
    const fs::path config = root / "config";
    ::setenv("XDG_CONFIG_HOME", config.c_str(), 1);
    app::GuiOptions opt;
    opt.frames = 2;
    opt.persistLayout = true;
    {
        app::Workbench wb(root, false);
        ASSERT_EQ(app::runGui(wb, ctx, opt), 0);
    }
    const fs::path ini = config / "bssrdf-workbench/imgui.ini";
    ASSERT_TRUE(fs::exists(ini));
    std::string text = core::readFile(ini);
    EXPECT_NE(text.find("[BssrdfWorkbench][Panels]"), std::string::npos) << text;
    EXPECT_NE(text.find("Timings=1"), std::string::npos) << text;
    EXPECT_NE(text.find("Splits=0.2500,0.2400,0.2200,0.3600"), std::string::npos) << text;
    EXPECT_NE(text.find("Tab.centre=Render"), std::string::npos) << text;
    // As a user would have: Timings hidden, splitters moved, the pencil plot floating and the
    // octree the centre's tab; a malformed line is ignored. The next run keeps all of it.
    text = testsupport::replaced(text, "Timings=1", "Timings=0");
    text = testsupport::replaced(text, "Splits=0.2500,0.2400,0.2200,0.3600",
                                 "Splits=0.3000,0.2000,0.3000,0.5000\nSplits=nan,2,x");
    text = testsupport::replaced(text, "Tab.centre=Render",
                                 "Tab.centre=Octree\nFloat.PencilPlot=100,120,600,500");
    // the panels' view choices by name: the Render panel's renderer and what it shows, the lit
    // spheres' view, the splats' colour
    for (const auto& [was, now] :
         {std::pair{"Renderer=point_cloud", "Renderer=monte_carlo\nRenderer=bogus"},
          {"Render.show=image", "Render.show=stack_depth"},
          {"LitSpheres.view=path_traced", "LitSpheres.view=difference"},
          {"Points.colour=normal", "Points.colour=irradiance\nPoints.colour=7"},
          {"Log.level=info", "Log.level=warning"},
          // and its view numbers, within their sliders' ranges
          {"LitSpheres.exposure=0", "LitSpheres.exposure=1.5\nLitSpheres.exposure=99"},
          {"LitSpheres.gamma=2.2", "LitSpheres.gamma=1.8\nLitSpheres.gamma=2x"},
          {"Slice.decades=4", "Slice.decades=6\nSlice.decades=nan"}}) {
        EXPECT_NE(text.find(was), std::string::npos) << was << "\n" << text;
        text = testsupport::replaced(text, was, now);
    }
    core::writeFile(ini, text);
    {
        app::Workbench wb(root, false);
        ASSERT_EQ(app::runGui(wb, ctx, opt), 0);
    }
    std::string after = core::readFile(ini);
    for (const char* kept :
         {"Timings=0", "Splits=0.3000,0.2000,0.3000,0.5000", "Tab.centre=Octree",
          "Float.PencilPlot=100,120,600,500", "Renderer=monte_carlo", "Render.show=stack_depth",
          "LitSpheres.view=difference", "Points.colour=irradiance", "Log.level=warning",
          "LitSpheres.exposure=1.5", "LitSpheres.gamma=1.8", "Slice.decades=6"})
        EXPECT_NE(after.find(kept), std::string::npos) << kept << "\n" << after;
    EXPECT_EQ(after.find("nan"), std::string::npos) << after;
    EXPECT_EQ(after.find("bogus"), std::string::npos) << after;
    EXPECT_EQ(after.find("colour=7"), std::string::npos) << after;
    EXPECT_EQ(after.find("exposure=99"), std::string::npos) << after;

    // the window's size is saved, and the next start opens at it (gui --size overrides)
    EXPECT_NE(after.find("Window=1600,1000"), std::string::npos) << after;
    opt.width = 1024;
    opt.height = 700;
    {
        app::Workbench wb(root, false);
        ASSERT_EQ(app::runGui(wb, ctx, opt), 0);
    }
    auto size = app::rememberedWindowSize();
    ASSERT_TRUE(size.has_value());
    EXPECT_EQ(*size, std::make_pair(1024, 700));
    // nonsense or absurd sizes are not remembered
    for (const char* bad :
         {"Window=abc", "Window=100,100", "Window=800,600x", "Window=99999,600"}) {
        core::writeFile(ini, testsupport::replaced(core::readFile(ini), "Window=1024,700", bad));
        EXPECT_FALSE(app::rememberedWindowSize().has_value()) << bad;
        core::writeFile(ini, testsupport::replaced(core::readFile(ini), bad, "Window=1024,700"));
    }
    ::unsetenv("XDG_CONFIG_HOME");
    fs::remove_all(root);
}

// The panel registry lists every panel once, in PanelId order, with distinct titles and saved
// keys; a fresh UiState opens the defaults; the scene pipeline runs exactly while a panel that
// needs it is shown (its tab selected); closing a panel stops drawing it.
TEST(PanelRegistry, EveryPanelOnceAndTheSceneFollowsItsPanels) {
    const auto& reg = app::panelRegistry();
    std::set<std::string> titles, keys;
    for (size_t i = 0; i < reg.size(); ++i) {
        EXPECT_EQ(static_cast<size_t>(reg[i].id), i);
        EXPECT_TRUE(titles.insert(reg[i].title).second) << reg[i].title;
        EXPECT_TRUE(keys.insert(reg[i].iniKey).second) << reg[i].iniKey;
        EXPECT_NE(reg[i].draw, nullptr);
    }
    app::UiState fresh;
    for (const auto& p : reg)
        EXPECT_EQ(fresh.shared.isOpen(p.id), p.defaultOpen) << p.title;
    // the README's layout: the right inspector holds the Traversal debugger from the start
    EXPECT_TRUE(fresh.shared.isOpen(app::PanelId::Traversal));

    testsupport::context();
    auto root = testsupport::makeProjectRoot("registry", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 860);
    app::UiState& ui = gui.ui();
    for (const auto& p : reg)
        ui.shared.isOpen(p.id) = false;
    gui.frame();
    EXPECT_FALSE(wb.scene().settings().enabled);
    EXPECT_EQ(testsupport::panelWindow(app::PanelId::Octree), nullptr);
    ui.shared.show(app::PanelId::Octree);
    gui.frame(); // a tab that did not exist shows from its second frame
    EXPECT_TRUE(wb.scene().settings().enabled);
    gui.frame();
    EXPECT_NE(testsupport::panelWindow(app::PanelId::Octree), nullptr);
    // the octree stays open behind the pencil plot's tab: not drawn, no scene
    ui.shared.show(app::PanelId::Pencil);
    gui.frame();
    EXPECT_FALSE(wb.scene().settings().enabled);
    gui.frame();
    EXPECT_EQ(testsupport::panelWindow(app::PanelId::Octree), nullptr);
    EXPECT_NE(testsupport::panelWindow(app::PanelId::Pencil), nullptr);
    EXPECT_TRUE(ui.shared.isOpen(app::PanelId::Octree));
    // closed, it is gone from its area
    ui.shared.isOpen(app::PanelId::Pencil) = false;
    ui.shared.isOpen(app::PanelId::Octree) = false;
    gui.frame();
    EXPECT_EQ(testsupport::panelWindow(app::PanelId::Octree), nullptr);
    EXPECT_FALSE(wb.scene().settings().enabled);
    std::filesystem::remove_all(root);
}

// File → Open model: the dialog lists a folder's subfolders and its .bssrdf files (hidden ones
// left out), opening a model remembers it among the recent files (newest first, no
// duplicates, saved with the layout), and a bad file is an Errors entry naming it.
TEST(FileDialog, ListsFoldersAndModelsAndRemembersRecentFiles) {
    auto& ctx = testsupport::context();
    auto root = testsupport::makeProjectRoot("dialog", {"dipole.bssrdf"});
    const fs::path d = root / "browse";
    fs::create_directories(d / "sub");
    fs::create_directories(d / ".hidden");
    core::writeFile(d / "b.bssrdf", core::readFile(root / "materials/dipole.bssrdf"));
    core::writeFile(d / "a.txt", "x");
    core::writeFile(d / ".c.bssrdf", "x");
    const auto entries = app::listDirectory(d, ".bssrdf");
    ASSERT_EQ(entries.size(), 2u);
    EXPECT_EQ(entries[0].name, "sub");
    EXPECT_TRUE(entries[0].directory);
    EXPECT_EQ(entries[1].name, "b.bssrdf");
    EXPECT_EQ(app::listDirectory(d, "").size(), 3u);
    try {
        app::listDirectory(d / "nope", ".bssrdf");
        ADD_FAILURE() << "listing a missing folder";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos) << e.what();
    }

    std::vector<std::string> recent{"x", "y"};
    app::rememberRecent(recent, "y");
    EXPECT_EQ(recent, (std::vector<std::string>{"y", "x"}));
    for (int i = 0; i < 10; ++i)
        app::rememberRecent(recent, std::to_string(i), 8);
    EXPECT_EQ(recent.size(), 8u);
    EXPECT_EQ(recent.front(), "9");

    {
        app::Workbench wb(root, false);
        app::HeadlessGui gui(wb, 1280, 720);
        app::UiState& ui = gui.ui();
        ui.menu.openModelPopup = true;
        ui.menu.openDialog.dir = d;
        gui.frame();
        gui.frame();
        ImGuiWindow* modal = ImGui::FindWindowByName("Open model");
        ASSERT_NE(modal, nullptr);
        EXPECT_TRUE(modal->Active);
        EXPECT_EQ(ui.menu.openDialog.entries.size(), 2u);
        app::openModelFile(wb, ui.shared, d / "b.bssrdf");
        ASSERT_NE(wb.library().find("b"), nullptr);
        ASSERT_FALSE(ui.shared.recent.empty());
        EXPECT_EQ(ui.shared.recent.front(), (d / "b.bssrdf").string());
        app::openModelFile(wb, ui.shared, d / "a.txt");
        const auto errors = wb.errors();
        ASSERT_EQ(errors.size(), 1u);
        EXPECT_NE(errors[0].text.find("a.txt"), std::string::npos) << errors[0].text;
        EXPECT_EQ(ui.shared.recent.size(), 1u); // a failed open is not remembered
    }
    { // Open MCML reference starts in the project (--root), wherever the program was started
        app::Workbench wb(root, false);
        app::HeadlessGui gui(wb, 1280, 720);
        app::UiState& ui = gui.ui();
        ui.menu.mcmlPopup = true;
        gui.frame();
        gui.frame();
        ASSERT_NE(ImGui::FindWindowByName("Open MCML reference"), nullptr);
        ASSERT_NE(fs::absolute(fs::current_path()), fs::absolute(root));
        EXPECT_EQ(ui.menu.mcmlDialog.dir, fs::absolute(root).lexically_normal());
    }
    // recent files persist with the layout
    const fs::path config = root / "config";
    ::setenv("XDG_CONFIG_HOME", config.c_str(), 1);
    app::GuiOptions opt;
    opt.frames = 1;
    opt.persistLayout = true;
    fs::create_directories(config / "bssrdf-workbench");
    core::writeFile(config / "bssrdf-workbench/imgui.ini",
                    "[BssrdfWorkbench][Panels]\nRecent=/some/where.bssrdf\n");
    {
        app::Workbench wb(root, false);
        ASSERT_EQ(app::runGui(wb, ctx, opt), 0);
    }
    EXPECT_NE(
        core::readFile(config / "bssrdf-workbench/imgui.ini").find("Recent=/some/where.bssrdf"),
        std::string::npos);
    ::unsetenv("XDG_CONFIG_HOME");
    fs::remove_all(root);
}

// The Captures panel replays a capture in a child process while the GUI keeps drawing, shows
// the report, loads the difference picture of a failing image stage, and cancels a replay.
TEST(CapturesPanel, ReplaysInAChildProcessAndShowsTheDifference) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("capspanel", {"dipole.bssrdf"});
    const fs::path dir = testsupport::copyCapture(root, "dipole_bunny_scene", "scene");
    auto img = pathtrace::readExr(dir / "scene_render.exr");
    for (size_t p = 0; p < img.mean.size(); p += 3 * 5)
        img.mean[p] *= 2.0f;
    pathtrace::writeExr(dir / "scene_render.exr", img);

    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui.captures.exe = BW_EXE;
    ui.shared.show(app::PanelId::Captures);
    gui.frame();
    gui.frame();
    ASSERT_EQ(ui.captures.names, std::vector<std::string>{"scene"});
    ui.captures.selected = "scene";
    app::startReplay(wb, ui.captures, "scene");
    int frames = 0;
    core::Stopwatch clock;
    while (!ui.captures.proc->done() && clock.ms() < 120000) {
        gui.frame(); // the GUI keeps drawing while the child replays
        ++frames;
    }
    ASSERT_TRUE(ui.captures.proc->done());
    EXPECT_GT(frames, 1);
    EXPECT_EQ(ui.captures.proc->exitCode(), 1) << ui.captures.report;
    EXPECT_NE(ui.captures.report.find("FAIL scene.render"), std::string::npos)
        << ui.captures.report;
    // the way to the state that failed, as a CI log shows it
    EXPECT_NE(ui.captures.report.find(
                  "look at the recorded state: bssrdf-workbench gui --capture " + dir.string()),
              std::string::npos)
        << ui.captures.report;
    gui.frame();
    ASSERT_EQ(ui.captures.pictures.size(), 1u) << ui.captures.report;
    EXPECT_TRUE(ui.captures.pictures[0].problem.empty()) << ui.captures.pictures[0].problem;
    EXPECT_EQ(ui.captures.pictures[0].width, 3 * img.width);

    // cancel: the child is killed and the panel says so
    app::startReplay(wb, ui.captures, "scene");
    ui.captures.proc->cancel();
    gui.frame();
    EXPECT_EQ(ui.captures.proc->exitCode(), 128 + 9);
    EXPECT_NE(ui.captures.report.find("(cancelled)"), std::string::npos);
    EXPECT_TRUE(wb.errors().empty());
    fs::remove_all(root);
}

// A model that evaluates to NaN somewhere is an entry in the Errors panel naming the model and
// where in r; the plot legend gives no error figures for it; a fixed model clears the entry.
// A capture just recorded shows in the Captures panel without Refresh (it was listed only when
// the panel first showed), and a capture recorded again holds only its new files (it was written
// over the old folder, keeping the previous recording's extra files; now it is written aside and
// renamed over it whole).
TEST(CapturesPanel, ACaptureJustRecordedIsListedAndReplacesTheOldWhole) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("capslist", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui.shared.show(app::PanelId::Captures);
    gui.frame();
    gui.frame();
    ASSERT_TRUE(ui.captures.names.empty());
    app::recordCapture(wb, "first");
    core::Stopwatch clock;
    while (ui.captures.names.empty() && clock.ms() < 1000 * (app::kCapturesListSeconds + 2))
        gui.frame();
    EXPECT_EQ(ui.captures.names, std::vector<std::string>{"first"});

    const fs::path dir = root / "captures" / "first";
    core::writeFile(dir / "stale_output.csv", "x\n1\n"); // as a larger earlier recording left
    app::recordCapture(wb, "first");
    EXPECT_FALSE(fs::exists(dir / "stale_output.csv"));
    EXPECT_TRUE(fs::exists(dir / "manifest.json"));
    for (const auto& entry : fs::directory_iterator(root / "captures"))
        EXPECT_EQ(entry.path().filename().string().find(".recording-"), std::string::npos)
            << "a temporary folder was left: " << entry.path();
    fs::remove_all(root);
}

// The pencil plot's Export CSV asks where (the file dialog) and writes what is shown there,
// giving the full path in the status line and the log.
TEST(HeadlessGui, PencilExportAsksWhere) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("pencilexport", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui.shared.show(app::PanelId::Pencil);
    gui.frame();
    gui.frame();
    auto click = [&](const std::array<float, 4>& r) {
        testsupport::click(gui, {r[0], r[1], r[2], r[3]});
    };
    ASSERT_EQ(ui.pencil.exportButtons.size(), 2u);
    click(ui.pencil.exportButtons[0]); // Export CSV
    app::FileDialogState& d = ui.pencil.exporter.dialog;
    EXPECT_EQ(std::string(d.path),
              (fs::current_path() / "pencil_plot.csv").lexically_normal().string());
    const fs::path target = root / "plot_here.csv";
    ImGui::GetIO().AddInputCharactersUTF8(target.c_str()); // typed over the proposed path
    gui.frame();
    click({d.actionRect[0], d.actionRect[1], d.actionRect[2], d.actionRect[3]});
    ASSERT_TRUE(fs::exists(target)) << ui.shared.status;
    EXPECT_NE(core::readFile(target).find("r_mm"), std::string::npos);
    EXPECT_EQ(ui.shared.status, "wrote " + target.string());
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    fs::remove_all(root);
}

// The dialogs answer the keyboard as they appear: the record dialog's name and the file dialog's
// path take what is typed (over the old text), Enter records or opens, Escape closes; a name
// that is not a capture's is said in the dialog and records nothing.
TEST(HeadlessGui, DialogsTakeTheKeyboardEnterActsEscapeCloses) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("dialogkeys", {"dipole.bssrdf"});
    fs::create_directories(root / "elsewhere");
    fs::copy_file(root / "materials/dipole.bssrdf", root / "elsewhere/other.bssrdf");
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui.captures.exe = BW_EXE;
    testsupport::mapDialogKeys();
    const auto type = [&](const std::string& text) { testsupport::typeText(gui, text); };
    const auto press = [&](int key) { testsupport::pressKey(gui, key); };
    const auto popups = testsupport::openPopups;
    const auto open = [&](bool& flag) {
        flag = true;
        gui.frame();
        gui.frame();
        ASSERT_EQ(popups(), 1);
    };

    open(ui.menu.recordPopup);
    type(".hidden");
    EXPECT_STREQ(ui.menu.nameBuffer, ".hidden") << "typed over the proposed name";
    press(GLFW_KEY_ENTER);
    EXPECT_FALSE(ui.captures.recorder) << "an invalid name recorded";
    EXPECT_EQ(popups(), 1);
    press(GLFW_KEY_ESCAPE);
    EXPECT_EQ(popups(), 0) << "Escape left the record dialog open";

    open(ui.menu.recordPopup);
    type("typed");
    EXPECT_STREQ(ui.menu.nameBuffer, "typed");
    press(GLFW_KEY_ENTER);
    EXPECT_EQ(popups(), 0);
    ASSERT_TRUE(ui.captures.recorder)
        << "Enter did not record: " << (wb.errors().empty() ? "" : wb.errors()[0].text);
    EXPECT_EQ(ui.captures.recording, "typed");
    ui.captures.recorder->cancel();
    while (!ui.captures.recorder->done())
        gui.frame();
    gui.frame();

    const size_t models = wb.library().entries().size();
    open(ui.menu.openModelPopup);
    type((root / "elsewhere/other.bssrdf").string());
    press(GLFW_KEY_ENTER);
    EXPECT_EQ(popups(), 0);
    EXPECT_EQ(wb.library().entries().size(), models + 1) << ui.shared.status;
    open(ui.menu.openModelPopup);
    press(GLFW_KEY_ESCAPE);
    EXPECT_EQ(popups(), 0) << "Escape left the file dialog open";
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    fs::remove_all(root);
}

// File → Record capture records in a child process: the GUI keeps drawing frames meanwhile, the
// Captures panel names the stage being recorded, the capture (with the path-traced reference)
// replays PASS, and nothing of the request is left; a cancelled recording leaves no folder.
TEST(CapturesPanel, RecordingRunsInTheBackgroundShowsItsStageAndCancels) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("caprecord", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.referenceSettings().enabled = true;
    wb.referenceSettings().paths = 40000; // a second or so in the child (2 cores, llvmpipe)
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui.captures.exe = BW_EXE;
    gui.frame();
    app::startRecording(wb, ui.captures, "background");
    ASSERT_TRUE(fs::exists(root / "captures/.background.request/request.json"));
    core::Stopwatch clock;
    double longest = 0;
    int framesWhileRecording = 0; // frames that ended with the child still at work
    bool stageShown = false;
    ui.shared.show(app::PanelId::Captures);
    while (!ui.captures.recorder->done() && clock.ms() < 120000) {
        core::Stopwatch one;
        gui.frame();
        longest = std::max(longest, one.ms());
        framesWhileRecording += !ui.captures.recorder->done();
        stageShown |= !app::lastStage(ui.captures.recorder->output(), "record").empty();
    }
    gui.frame();
    std::printf("%d frames while recording, the longest %.0f ms, in all %.1f s\n",
                framesWhileRecording, longest, clock.ms() / 1000.0);
    ASSERT_EQ(ui.captures.recorder->exitCode(), 0) << ui.captures.recorder->output();
    EXPECT_TRUE(stageShown) << ui.captures.recorder->output();
    // A frame that waited for the child would end with the recording done: frames kept coming
    // while it ran (counted, not timed, so that a loaded machine cannot fail it).
    EXPECT_GE(framesWhileRecording, 3) << "a frame waited for the recording";
    EXPECT_EQ(ui.shared.status, "recorded captures/background");
    EXPECT_FALSE(fs::exists(root / "captures/.background.request"));
    const std::string manifest = core::readFile(root / "captures/background/manifest.json");
    EXPECT_NE(manifest.find("\"reference\""), std::string::npos);
    std::string report;
    EXPECT_EQ(app::replayCapture(root / "captures/background", root, false, report), 0) << report;
    // the replay's workbench (its programs deleted, one of them current) leaves the GUI's frames
    // without GL errors
    gui.frame();

    // cancelled: no capture, no request, no temporary folder
    app::startRecording(wb, ui.captures, "cancelled");
    gui.frame();
    ui.captures.recorder->cancel();
    gui.frame();
    EXPECT_EQ(ui.captures.recordOutcome, "recording of cancelled cancelled");
    for (const auto& entry : fs::directory_iterator(root / "captures"))
        EXPECT_EQ(entry.path().filename().string().find("cancelled"), std::string::npos)
            << "left behind: " << entry.path();
    // a bad name is refused before anything starts
    EXPECT_THROW(app::startRecording(wb, ui.captures, "../escape"), core::Error);
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    fs::remove_all(root);
}

// The Errors panel's Copy puts every problem on the clipboard as it shows them, file and line
// included; the Log panel's Copy the lines it shows (its level filter applied).
TEST(HeadlessGui, ErrorsAndLogCopyWhatTheyShow) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("copyerrors", {"dipole.bssrdf"});
    core::writeFile(root / "materials/broken.bssrdf",
                    "analytic radial no_wi no_wo\n::begin shader\n"
                    "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { return nope; }\n"
                    "::end shader\n");
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ImGui::SetClipboardText("");
    ui.shared.show(app::PanelId::Errors);
    gui.frame();
    gui.frame();
    ASSERT_FALSE(wb.errors().empty());
    const app::Rect& copyErrors = ui.errors.copyErrors;
    ASSERT_GT(copyErrors.width(), 0) << "no Copy button";
    testsupport::click(gui, copyErrors);
    const std::string copied = ImGui::GetClipboardText();
    EXPECT_NE(copied.find("broken.bssrdf:3"), std::string::npos) << copied;
    EXPECT_NE(copied.find("nope"), std::string::npos) << copied;
    EXPECT_GE(std::count(copied.begin(), copied.end(), '\n'), long(wb.errors().size()));
    EXPECT_EQ(ui.shared.status.rfind("copied ", 0), 0u) << ui.shared.status;

    core::logInfo("a line to copy");
    core::logDebug("a debug line the level hides");
    ui.shared.show(app::PanelId::Log);
    gui.frame();
    gui.frame();
    ASSERT_GT(ui.errors.copyLog.width(), 0) << "no Copy button";
    testsupport::click(gui, ui.errors.copyLog);
    const std::string log = ImGui::GetClipboardText();
    EXPECT_NE(log.find("a line to copy"), std::string::npos) << log;
    EXPECT_EQ(log.find("a debug line the level hides"), std::string::npos) << log;
    fs::remove_all(root);
}

// View → a closed panel opens it in front (its tab shown, its contents drawn), not behind the
// tab its area shows; again closes it.
TEST(HeadlessGui, APanelOpenedFromTheViewMenuIsShown) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("viewmenu", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    gui.frame();
    ASSERT_FALSE(ui.shared.isOpen(app::PanelId::Fit));
    ASSERT_NE(testsupport::panelWindow(app::PanelId::Render), nullptr);
    app::togglePanel(ui.shared, app::PanelId::Fit);
    gui.frame();
    gui.frame();
    EXPECT_NE(testsupport::panelWindow(app::PanelId::Fit), nullptr) << "opened behind Render";
    app::togglePanel(ui.shared, app::PanelId::Fit);
    gui.frame();
    EXPECT_FALSE(ui.shared.isOpen(app::PanelId::Fit));
    EXPECT_EQ(testsupport::panelWindow(app::PanelId::Fit), nullptr);
    fs::remove_all(root);
}

TEST(HeadlessGui, ModelNanValuesAreAnErrorEntryWithTheRadii) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("nanmodel", {"dipole.bssrdf"});
    const fs::path bad = root / "materials" / "nan_model.bssrdf";
    auto write = [&](const char* red) {
        core::writeFile(bad, std::string("analytic radial no_wi no_wo\n::begin shader\n"
                                         "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                                         "    float r = length(Xo - Xi);\n"
                                         "    float nan = sqrt(-1.0 - r);\n"
                                         "    return vec3(") +
                                 red + ", 1.0, 1.0);\n}\n::end shader\n");
    };
    write("r < 1.0 ? nan : 1.0");
    app::Workbench wb(root, false);
    wb.update();
    bool found = false;
    for (const auto& e : wb.errors())
        if (e.text.find("materials/nan_model.bssrdf: R(r) is NaN at ") != std::string::npos &&
            e.text.find("channel R)") != std::string::npos)
            found = true;
    EXPECT_TRUE(found);
    // fixed: the entry goes
    write("1.0");
    wb.reloadAll();
    wb.update();
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.text;
    fs::remove_all(root);
}

namespace {

// The code points of every string literal in the C++ sources under `dir` (comments skipped).
std::set<uint32_t> codePointsInStringLiterals(const fs::path& dir) {
    std::set<uint32_t> out;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        const fs::path& p = entry.path();
        if (!entry.is_regular_file() || (p.extension() != ".cpp" && p.extension() != ".h"))
            continue;
        const std::string s = core::readFile(p);
        for (size_t i = 0; i < s.size(); ++i) {
            if (s.compare(i, 2, "//") == 0) {
                i = s.find('\n', i);
                if (i == std::string::npos) break;
            } else if (s.compare(i, 2, "/*") == 0) {
                i = s.find("*/", i + 2);
                if (i == std::string::npos) break;
                ++i;
            } else if (s[i] == '\'') { // a character literal: '"' is not a string
                for (++i; i < s.size() && s[i] != '\''; ++i)
                    if (s[i] == '\\') ++i;
            } else if (s[i] == '"') {
                for (++i; i < s.size() && s[i] != '"' && s[i] != '\n'; ++i) {
                    const auto b = uint8_t(s[i]);
                    if (b == '\\') {
                        ++i;
                    } else if (b >= 0xC0) { // UTF-8 lead byte: decode the sequence
                        const int n = b >= 0xF0 ? 3 : b >= 0xE0 ? 2 : 1;
                        uint32_t c = b & (0x3F >> n);
                        for (int k = 0; k < n && i + 1 < s.size(); ++k)
                            c = (c << 6) | (uint8_t(s[++i]) & 0x3F);
                        out.insert(c);
                    }
                }
            }
        }
    }
    return out;
}

} // namespace

// Every character the program prints beyond Latin-1 (its string literals in app/ and modules/:
// Greek letters, dashes, ellipses, primes, arrows) has a glyph in the GUI's font; ImGui's
// built-in font alone drew π, Σ, ′, →, … and — as '?'.
TEST(HeadlessGui, EveryCharacterTheProgramPrintsHasAGlyph) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("glyphs", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 800, 600);
    gui.frame();
    std::set<uint32_t> used = codePointsInStringLiterals(fs::path(BW_SOURCE_ROOT) / "app");
    for (uint32_t c : codePointsInStringLiterals(fs::path(BW_SOURCE_ROOT) / "modules"))
        used.insert(c);
    ASSERT_TRUE(used.count(0x03C0)) << "π is printed by the texture-space view";
    ASSERT_FALSE(ImGui::GetIO().Fonts->Fonts.empty());
    const ImFont* font = ImGui::GetIO().Fonts->Fonts[0];
    std::string missing;
    for (uint32_t c : used)
        if (c > 0xFF && (c > 0xFFFF || !font->FindGlyphNoFallback(ImWchar(c)))) {
            char hex[16];
            std::snprintf(hex, sizeof hex, " U+%04X", unsigned(c));
            missing += hex;
        }
    EXPECT_EQ(missing, "") << "no glyph in " << app::symbolFontFile();
    fs::remove_all(root);
}

// The Fit panel: a dipole mis-set to Multiplier 1.6, fitted with a click against the pencil
// plot's reference while frames go on (each frame serves evaluations for a bounded time), lowers
// rel_err on every channel; Apply, clicked, puts the fitted value in the model.
TEST(FitPanel, FitsAgainstTheReferenceWithoutHoldingTheFramesAndApplies) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("fitpanel", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    wb.referenceSettings().enabled = true;
    wb.referenceSettings().paths = 100000;
    const std::string dipole = "materials/dipole.bssrdf";
    wb.library().find(dipole)->values["Multiplier"] = {1.6f, 0, 0};
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui.shared.show(app::PanelId::Fit);
    ui.fit.model = dipole;
    ui.fit.params = {"Multiplier"};
    gui.frame();
    wb.finishReference();
    gui.frame();
    gui.frame();
    auto click = [&](const app::Rect& r) { testsupport::click(gui, r); };
    ASSERT_GT(ui.fit.fitButton.width(), 5.0f);
    wb.fit().frameBudgetMs = 0; // one evaluation a frame: the frames are counted, not timed
    click(ui.fit.fitButton);
    ASSERT_TRUE(wb.fit().snapshot().running || wb.fit().snapshot().result) << "not started";
    core::Stopwatch clock;
    double longest = 0;
    int framesWhileFitting = 0;
    while (wb.fit().snapshot().running && clock.ms() < 60000) {
        core::Stopwatch one;
        gui.frame();
        longest = std::max(longest, one.ms());
        framesWhileFitting += wb.fit().snapshot().running;
    }
    std::printf("%d frames while fitting, the longest %.0f ms, in all %.1f s\n", framesWhileFitting,
                longest, clock.ms() / 1000.0);
    const app::FitSnapshot snap = wb.fit().snapshot();
    ASSERT_TRUE(snap.result.has_value()) << snap.problem;
    EXPECT_TRUE(snap.result->converged) << snap.result->status;
    // each frame served one evaluation and let the fit go on (the click's frame and the last
    // may serve one more): no frame waited for the fit
    EXPECT_GE(framesWhileFitting + 2, int(snap.trace.size())) << "a frame waited for the fit";
    ASSERT_EQ(snap.targets.size(), snap.result->relErrBest.size());
    for (size_t t = 0; t < snap.targets.size(); ++t)
        EXPECT_LT(snap.result->relErrBest[t], snap.result->relErrStart[t]) << snap.targets[t];
    EXPECT_GE(snap.trace.size(), 3u);
    gui.frame();
    // the result's lines fit the panel, however long the model's path and the optimizer's word
    testsupport::expectFitsItsWidth(gui, app::PanelId::Fit);
    // until applied, the pencil plot shows the fitted curve beside the model's
    auto fittedCurves = [&] {
        size_t n = 0;
        for (const auto& series : app::plotSeries(wb))
            n += series.label.find("fitted (Fit panel, not applied)") != std::string::npos;
        return n;
    };
    EXPECT_EQ(fittedCurves(), 1u);
    ASSERT_GT(ui.fit.applyButton.width(), 5.0f);
    click(ui.fit.applyButton);
    EXPECT_EQ(fittedCurves(), 0u);
    EXPECT_FLOAT_EQ(wb.library().find(dipole)->values.at("Multiplier")[0],
                    float(snap.result->best[0]));
    // a capture records the fit asked for (run again from the values now) and replays it
    EXPECT_EQ(wb.fitRequest().model, dipole);
    EXPECT_EQ(wb.fitRequest().params, "Multiplier");
    app::recordCapture(wb, "withfit");
    const std::string manifest = core::readFile(root / "captures/withfit/manifest.json");
    EXPECT_NE(manifest.find("\"stage\": \"fit\""), std::string::npos);
    std::string report;
    EXPECT_EQ(app::replayCapture(root / "captures/withfit", root, false, report), 0) << report;
    EXPECT_NE(report.find("fit"), std::string::npos) << report;
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    fs::remove_all(root);
}

// A hot reload of the model during a fit restarts it from its best point; it still ends.
TEST(FitPanel, AReloadDuringAFitRestartsIt) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("fitreload", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    wb.referenceSettings().enabled = true;
    wb.referenceSettings().paths = 20000;
    wb.update();
    wb.finishReference();
    wb.update();
    wb.startFit("materials/dipole.bssrdf", {"Multiplier"});
    ASSERT_TRUE(wb.fit().snapshot().running);
    wb.reloadAll(); // the programs rebuilt: a new generation of the model
    wb.finishFit();
    const app::FitSnapshot snap = wb.fit().snapshot();
    EXPECT_EQ(snap.restarts, 1);
    ASSERT_TRUE(snap.result.has_value()) << snap.problem;
    EXPECT_TRUE(snap.result->converged) << snap.result->status;
    fs::remove_all(root);
}

// Escape closes an open combo's list as it closes a dialog (ImGui 1.86 alone does not, without
// keyboard navigation): the Pencil plot's y-axis combo opened by a click, closed by Escape, its
// value unchanged; a modal dialog still closes itself on its Escape.
TEST(HeadlessGui, EscapeClosesAComboList) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("escapecombo", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui.shared.show(app::PanelId::Pencil);
    testsupport::mapDialogKeys();
    gui.frame();
    gui.frame();
    const ImGuiWindow* panel = testsupport::panelWindow(app::PanelId::Pencil);
    ASSERT_NE(panel, nullptr);
    // the panel's first item: the y-axis scale combo
    const ImVec2 first = panel->ContentRegionRect.Min;
    testsupport::clickAt(gui, first.x + 12, first.y + 6);
    ASSERT_EQ(testsupport::openPopups(), 1);
    const ImGuiWindow* list = ImGui::GetCurrentContext()->OpenPopupStack.back().Window;
    ASSERT_NE(list, nullptr);
    EXPECT_EQ(std::string(list->Name).rfind("##Combo", 0), 0u) << list->Name;
    const auto scale = wb.plotSettings().yScale;
    testsupport::pressKey(gui, GLFW_KEY_ESCAPE);
    EXPECT_EQ(testsupport::openPopups(), 0) << "Escape left the combo's list open";
    EXPECT_EQ(wb.plotSettings().yScale, scale);
    // a dialog: its own Escape (closeOnEscape), not taken twice
    ui.menu.recordPopup = true;
    gui.frame();
    gui.frame();
    ASSERT_EQ(testsupport::openPopups(), 1);
    testsupport::pressKey(gui, GLFW_KEY_ESCAPE);
    EXPECT_EQ(testsupport::openPopups(), 0) << "Escape left the record dialog open";
    fs::remove_all(root);
}
