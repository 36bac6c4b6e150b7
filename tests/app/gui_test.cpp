// The full GUI headless: every panel draws, the pencil plot exports a PNG of itself, and the
// window layout and panel visibility persist between runs.
#include "../support/gl_fixture.h"
#include "gui.h"
#include "panels/registry.h"

#include <imgui.h>
#include <imgui_internal.h>

#include <set>

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
    EXPECT_NE(text.find("[Window][Pencil plot]"), std::string::npos) << text;
    EXPECT_NE(text.find("[BssrdfWorkbench][Panels]"), std::string::npos) << text;
    EXPECT_NE(text.find("Timings=1"), std::string::npos) << text;
    // hide Timings and move the pencil plot, as a user would have; the next run keeps both
    text = testsupport::replaced(text, "Timings=1", "Timings=0");
    auto pos = text.find("[Window][Pencil plot]\nPos=");
    ASSERT_NE(pos, std::string::npos);
    auto end = text.find('\n', pos + 22);
    text = text.substr(0, pos) + "[Window][Pencil plot]\nPos=400,300" + text.substr(end);
    core::writeFile(ini, text);
    {
        app::Workbench wb(root, false);
        ASSERT_EQ(app::runGui(wb, ctx, opt), 0);
    }
    std::string after = core::readFile(ini);
    EXPECT_NE(after.find("Timings=0"), std::string::npos) << after;
    EXPECT_NE(after.find("[Window][Pencil plot]\nPos=400,300"), std::string::npos) << after;
    ::unsetenv("XDG_CONFIG_HOME");
    fs::remove_all(root);
}

// The panel registry lists every panel once, in PanelId order, with distinct titles and saved
// keys; a fresh UiState opens the defaults; the scene pipeline runs exactly while a panel that
// needs it is open; closing a panel stops drawing it (its window disappears).
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

    testsupport::context();
    auto root = testsupport::makeProjectRoot("registry", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 860);
    app::UiState& ui = gui.ui();
    for (const auto& p : reg)
        ui.shared.isOpen(p.id) = false;
    gui.frame();
    EXPECT_FALSE(wb.scene().settings().enabled);
    EXPECT_EQ(ImGui::FindWindowByName("Octree"), nullptr);
    ui.shared.isOpen(app::PanelId::Octree) = true;
    gui.frame();
    EXPECT_TRUE(wb.scene().settings().enabled);
    ImGuiWindow* w = ImGui::FindWindowByName("Octree");
    ASSERT_NE(w, nullptr);
    EXPECT_TRUE(w->Active || w->WasActive);
    ui.shared.isOpen(app::PanelId::Octree) = false;
    ui.shared.isOpen(app::PanelId::Pencil) = true;
    gui.frame();
    EXPECT_FALSE(wb.scene().settings().enabled);
    w = ImGui::FindWindowByName("Octree");
    EXPECT_TRUE(w == nullptr || !w->Active);
    std::filesystem::remove_all(root);
}
