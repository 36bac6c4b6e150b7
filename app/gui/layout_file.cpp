// The layout file (layout_file.h).
#include "gui/layout_file.h"

#include "gui/panels/registry.h"

#include <imgui.h>
#include <imgui_internal.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

namespace app {
namespace fs = std::filesystem;

namespace {

UiState* g_layoutUi = nullptr; // where the handler reads and writes (addLayoutHandler)

// The panels' view choices kept in the layout file, each by name: the Render panel's renderer
// family (brute force and hybrid are settings, in the session) and what it shows, the lit
// spheres' view, what the point splats are coloured by, the Log panel's least level.
constexpr const char* kRendererNames[] = {"point_cloud", "monte_carlo", "texture_space"};
static_assert(std::size(kRendererNames) == size_t(RenderMode::TextureSpace) + 1);
constexpr const char* kHeatmapNames[] = {"image", "steps", "stack_depth", "relative_error"};
static_assert(std::size(kHeatmapNames) == size_t(Heatmap::RelativeError) + 1);
constexpr const char* kSphereViewNames[] = {"path_traced", "integrated", "side_by_side",
                                            "difference"};
static_assert(std::size(kSphereViewNames) == size_t(SphereView::Difference) + 1);
constexpr const char* kPointColorNames[] = {"normal", "area", "irradiance", "radiance"};
static_assert(std::size(kPointColorNames) == size_t(PointColor::Radiance) + 1);
// core::LogLevel's order
constexpr const char* kLogLevelNames[] = {"debug", "info", "warning", "error"};
// The panels' view numbers kept in the layout file, each within its slider's range: the lit
// spheres' exposure (EV) and gamma, the slice's colour-scale decades.
struct ViewNumber {
    const char* key;
    float& (*at)(UiState&);
    float lo, hi;
};
constexpr ViewNumber kViewNumbers[] = {
    {"LitSpheres.exposure", [](UiState& ui) -> float& { return ui.litSpheres.exposure; }, -10, 10},
    {"LitSpheres.gamma", [](UiState& ui) -> float& { return ui.litSpheres.gamma; }, 0.5f, 4},
    {"Slice.decades", [](UiState& ui) -> float& { return ui.slice.decades; }, 1, 8},
};

// "KEY=NAME" with NAME one of `names`: sets `value` and returns true.
template <class E, size_t N>
bool readChoice(const char* line, const char* key, const char* const (&names)[N], E& value) {
    for (size_t i = 0; i < N; ++i)
        if (std::string(key) + "=" + names[i] == line) {
            value = static_cast<E>(i);
            return true;
        }
    return false;
}
template <class E, size_t N>
void writeChoice(ImGuiTextBuffer* buf, const char* key, const char* const (&names)[N], E value) {
    buf->appendf("%s=%s\n", key, names[static_cast<size_t>(value)]);
}

void* panelsReadOpen(ImGuiContext*, ImGuiSettingsHandler*, const char* name) {
    return std::strcmp(name, "Panels") == 0 ? static_cast<void*>(g_layoutUi) : nullptr;
}
// The saved layout, one "key=value" line each: Models=1 (open), Splits=l,r,b,c (splitter
// fractions), Float.Render=x0,y0,x1,y1 (a floating panel's window), Tab.centre=Render (the tab
// an area shows), Renderer=monte_carlo, Render.show=steps, LitSpheres.view=difference,
// Points.colour=area, Log.level=warning (the view choices above), LitSpheres.exposure=1.5,
// LitSpheres.gamma=2.2, Slice.decades=5 (the view numbers), Recent=FILE, Window=W,H. Unknown or
// malformed lines, and numbers outside their slider's range, are ignored: the defaults stand.
void panelsReadLine(ImGuiContext*, ImGuiSettingsHandler*, void* entry, const char* line) {
    auto* ui = static_cast<UiState*>(entry);
    WorkspaceState& ws = ui->shared.workspace;
    auto fraction = [](float f, float fallback) {
        return std::isfinite(f) && f >= 0.05f && f <= 0.95f ? f : fallback;
    };
    if (readChoice(line, "Renderer", kRendererNames, ui->render.mode) ||
        readChoice(line, "Render.show", kHeatmapNames, ui->render.heatmap) ||
        readChoice(line, "LitSpheres.view", kSphereViewNames, ui->litSpheres.view) ||
        readChoice(line, "Points.colour", kPointColorNames, ui->shared.inspect.colorBy) ||
        readChoice(line, "Log.level", kLogLevelNames, ui->errors.logMinLevel))
        return;
    for (const ViewNumber& n : kViewNumbers) {
        float v = 0;
        char end = 0;
        if (std::sscanf(line, (std::string(n.key) + "=%f%c").c_str(), &v, &end) == 1 &&
            std::isfinite(v) && v >= n.lo && v <= n.hi) {
            n.at(*ui) = v;
            return;
        }
    }
    if (std::strncmp(line, "Recent=", 7) == 0 && line[7] && ui->shared.recent.size() < 8) {
        ui->shared.recent.push_back(line + 7);
        return;
    }
    float v[4];
    if (std::sscanf(line, "Splits=%f,%f,%f,%f", &v[0], &v[1], &v[2], &v[3]) == 4) {
        const WorkspaceSplits d;
        ws.splits = {fraction(v[0], d.left), fraction(v[1], d.right), fraction(v[2], d.bottom),
                     fraction(v[3], d.leftColumn)};
        return;
    }
    for (const PanelEntry& p : panelRegistry()) {
        const size_t i = static_cast<size_t>(p.id);
        const std::string key = p.iniKey;
        if (std::strncmp(line, (key + "=").c_str(), key.size() + 1) == 0)
            ui->shared.isOpen(p.id) = line[key.size() + 1] == '1';
        const std::string fl = "Float." + key + "=";
        if (std::strncmp(line, fl.c_str(), fl.size()) == 0 &&
            std::sscanf(line + fl.size(), "%f,%f,%f,%f", &v[0], &v[1], &v[2], &v[3]) == 4 &&
            std::isfinite(v[0] + v[1] + v[2] + v[3]) && v[2] > v[0] && v[3] > v[1]) {
            ws.floating[i] = true;
            ws.floatRect[i] = {v[0], v[1], v[2], v[3]};
        }
        const std::string tab = std::string("Tab.") + areaName(p.area) + "=" + key;
        if (tab == line) ws.selected[static_cast<size_t>(p.area)] = static_cast<int>(p.id);
    }
}
void panelsWriteAll(ImGuiContext*, ImGuiSettingsHandler* handler, ImGuiTextBuffer* buf) {
    if (!g_layoutUi) return;
    const WorkspaceState& ws = g_layoutUi->shared.workspace;
    buf->appendf("[%s][Panels]\n", handler->TypeName);
    for (const PanelEntry& p : panelRegistry())
        buf->appendf("%s=%d\n", p.iniKey, g_layoutUi->shared.isOpen(p.id) ? 1 : 0);
    buf->appendf("Splits=%.4f,%.4f,%.4f,%.4f\n", ws.splits.left, ws.splits.right, ws.splits.bottom,
                 ws.splits.leftColumn);
    for (const PanelEntry& p : panelRegistry()) {
        const size_t i = static_cast<size_t>(p.id);
        const Rect& r = ws.floatRect[i];
        if (ws.floating[i])
            buf->appendf("Float.%s=%.0f,%.0f,%.0f,%.0f\n", p.iniKey, r.x0, r.y0, r.x1, r.y1);
        if (ws.selected[static_cast<size_t>(p.area)] == static_cast<int>(p.id))
            buf->appendf("Tab.%s=%s\n", areaName(p.area), p.iniKey);
    }
    writeChoice(buf, "Renderer", kRendererNames, g_layoutUi->render.mode);
    writeChoice(buf, "Render.show", kHeatmapNames, g_layoutUi->render.heatmap);
    writeChoice(buf, "LitSpheres.view", kSphereViewNames, g_layoutUi->litSpheres.view);
    writeChoice(buf, "Points.colour", kPointColorNames, g_layoutUi->shared.inspect.colorBy);
    if (g_layoutUi->errors.logMinLevel >= 0 && g_layoutUi->errors.logMinLevel < 4)
        writeChoice(buf, "Log.level", kLogLevelNames, g_layoutUi->errors.logMinLevel);
    for (const ViewNumber& n : kViewNumbers)
        buf->appendf("%s=%g\n", n.key, double(n.at(*g_layoutUi)));
    for (const std::string& r : g_layoutUi->shared.recent)
        buf->appendf("Recent=%s\n", r.c_str());
    if (g_layoutUi->shared.windowWidth > 0 && g_layoutUi->shared.windowHeight > 0)
        buf->appendf("Window=%d,%d\n", g_layoutUi->shared.windowWidth,
                     g_layoutUi->shared.windowHeight);
    buf->append("\n");
}

} // namespace

fs::path configDir() {
    const char* xdg = std::getenv("XDG_CONFIG_HOME");
    const char* home = std::getenv("HOME");
    const fs::path dir = xdg && *xdg ? fs::path(xdg) : fs::path(home ? home : ".") / ".config";
    return dir / "bssrdf-workbench";
}

fs::path layoutFilePath() {
    const fs::path dir = configDir();
    std::error_code ec;
    fs::create_directories(dir, ec);
    return dir / "imgui.ini";
}

void addLayoutHandler(UiState& ui) {
    g_layoutUi = &ui;
    ImGuiSettingsHandler handler;
    handler.TypeName = "BssrdfWorkbench";
    handler.TypeHash = ImHashStr("BssrdfWorkbench");
    handler.ReadOpenFn = panelsReadOpen;
    handler.ReadLineFn = panelsReadLine;
    handler.WriteAllFn = panelsWriteAll;
    ImGui::GetCurrentContext()->SettingsHandlers.push_back(handler);
}

std::optional<std::pair<int, int>> rememberedWindowSize() {
    std::ifstream in(layoutFilePath());
    std::string line;
    bool ours = false;
    while (std::getline(in, line)) {
        if (!line.empty() && line[0] == '[') ours = line.rfind("[BssrdfWorkbench]", 0) == 0;
        int w = 0, h = 0;
        char end = 0;
        if (ours && std::sscanf(line.c_str(), "Window=%d,%d%c", &w, &h, &end) == 2 && w >= 320 &&
            h >= 320 && w <= 16384 && h <= 16384)
            return std::pair{w, h};
    }
    return std::nullopt;
}

} // namespace app
