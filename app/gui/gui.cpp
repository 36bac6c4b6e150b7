// ImGui frame loop, windowed or headless; the layout it loads and saves is layout_file.h's.
#include "gui/gui.h"
#include "gui/imgui_render.h"

#include "gui/file_dialog.h"
#include "gui/file_drop.h"
#include "gui/fonts.h"
#include "gui/key_taps.h"
#include "gui/layout_file.h"
#include "gui/mouse_clicks.h"

#include "capture/capture.h"
#include "captures/capture_io.h"
#include "captures/session.h"
#include "core/core.h"
#include "gui/panels/panels.h"
#include "gui/panels/registry.h"
#include "probe/output_wake.h"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <tuple>

namespace app {
namespace fs = std::filesystem;

namespace {
UiState* g_ui = nullptr; // the UI state of the frame loop (HeadlessGui::ui())
// Files dropped on the window since the last frame (GLFW calls back while it polls events,
// on this thread; the next frame opens them: file_drop.h).
std::vector<fs::path> g_dropped;

void drawPanels(Workbench& wb, UiState& ui) {
    closeTopPopupOnEscape(); // a combo's list, a context menu (file_dialog.h)
    drawMenuBar(wb, ui);
    // The scene pipeline runs while one of its panels is shown (its tab or floating window).
    bool scene = false;
    const auto shown = shownPanels(ui.shared);
    for (const PanelEntry& p : panelRegistry())
        scene |= p.needsScene && shown[static_cast<size_t>(p.id)];
    wb.scene().settings().enabled = scene;
    wb.sliceSettings().enabled = shown[static_cast<size_t>(PanelId::Slice)];
    wb.setScoreboardEnabled(shown[static_cast<size_t>(PanelId::Scoreboard)]);
    wb.monteCarloSettings().enabled =
        shown[static_cast<size_t>(PanelId::Render)] && ui.render.mode == RenderMode::MonteCarlo;
    wb.textureSpaceSettings().enabled =
        shown[static_cast<size_t>(PanelId::Render)] && ui.render.mode == RenderMode::TextureSpace;
    wb.setInteracting(false); // the Render panel sets it while the user drags
    drawWorkspace(wb, ui);
}

// Opaque windows (text never shows through), the same look headless and windowed.
void applyStyle() {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 0.0f;
    style.Colors[ImGuiCol_WindowBg].w = 1.0f;
    style.Colors[ImGuiCol_ChildBg].w = 0.0f; // children show their window's opaque background
    style.Colors[ImGuiCol_PopupBg].w = 1.0f;
}

// Reads back the region a panel asked for (PNG export, in UI units) from `fbo` after rendering,
// in the framebuffer's pixels (`scale` per unit).
void servicePngExport(Workbench& wb, UiState& ui, GLuint fbo, int fbHeight, float scale) {
    if (ui.shared.pngExportPath.empty()) return;
    const auto px = [scale](float units) { return int(std::lround(units * scale)); };
    int x0 = px(ui.shared.pngRect[0]), y0 = px(ui.shared.pngRect[1]);
    int w = px(ui.shared.pngRect[2]) - x0, h = px(ui.shared.pngRect[3]) - y0;
    std::string path = ui.shared.pngExportPath;
    ui.shared.pngExportPath.clear();
    if (w <= 0 || h <= 0) return;
    try {
        auto px = gl::readPixelsRGBA8(fbo, x0, fbHeight - (y0 + h), w, h);
        gl::writePng(path, w, h, px);
        ui.shared.status = "wrote " + path;
        core::logInfo("exported " + path);
    } catch (const core::Error& e) {
        wb.reportActionError(std::string("export PNG: ") + e.what());
    }
}
// The fonts rasterised again for another UI scale (the window moved to a screen that scales
// differently): the atlas and its texture made anew between frames.
void reloadFonts(float scale) {
    ImGui_ImplOpenGL3_DestroyFontsTexture();
    ImGui::GetIO().Fonts->Clear();
    loadFonts(scale);
    ImGui_ImplOpenGL3_CreateFontsTexture();
}

// After the GLFW backend's NewFrame, which sizes the UI in the window's screen coordinates:
// the UI in units of `scale` framebuffer pixels, and the mouse in those units. Returns the
// window's size in UI units (what the layout file keeps; 0 x 0 while minimised) and the UI units
// per screen coordinate.
struct UiUnits {
    int width = 0, height = 0;
    float perCoordinate = 1.0f;
};
UiUnits applyUiScale(GLFWwindow* win, float scale) {
    ImGuiIO& io = ImGui::GetIO();
    int ww = 0, wh = 0, fw = 0, fh = 0;
    glfwGetWindowSize(win, &ww, &wh);
    glfwGetFramebufferSize(win, &fw, &fh);
    if (ww <= 0 || wh <= 0 || fw <= 0 || fh <= 0)
        return {0, 0, 1.0f / scale}; // minimised: as the backend left it
    // framebuffer pixels per screen coordinate, over framebuffer pixels per UI unit
    const float perCoordinate = float(fw) / float(ww) / scale;
    io.DisplaySize = ImVec2(float(fw) / scale, float(fh) / scale);
    io.DisplayFramebufferScale = ImVec2(scale, scale);
    if (io.MousePos.x > -FLT_MAX / 2 && io.MousePos.y > -FLT_MAX / 2)
        io.MousePos = ImVec2(io.MousePos.x * perCoordinate, io.MousePos.y * perCoordinate);
    return {int(std::lround(fw / scale)), int(std::lround(fh / scale)), perCoordinate};
}
} // namespace

int scaledSize(int units, float uiScale) {
    return std::max(1, int(std::lround(units * uiScale)));
}

HeadlessGui::HeadlessGui(Workbench& wb, int width, int height, float uiScale)
    : m_wb(wb), m_width(width), m_height(height), m_scale(uiScale > 0 ? uiScale : 1.0f) {
    if (!ImGui::GetCurrentContext()) {
        static UiState ownUi;
        ownUi = UiState{};
        g_ui = &ownUi;
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;
        applyStyle();
        loadFonts(m_scale);
        m_ownsContext = true;
    }
    m_target.resize(pixelWidth(), pixelHeight());
    ImGui_ImplOpenGL3_Init("#version 450");
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(width), float(height));
    io.DisplayFramebufferScale = ImVec2(m_scale, m_scale);
}

HeadlessGui::~HeadlessGui() {
    if (!m_ownsContext) return;
    ImGui_ImplOpenGL3_Shutdown();
    ImGui::DestroyContext();
    g_ui = nullptr;
}

bool HeadlessGui::frame() {
    ImGuiIO& io = ImGui::GetIO();
    io.DeltaTime = 1.0f / 60.0f;
    io.MousePos = m_hasMouse ? ImVec2(m_mouseX, m_mouseY) : ImVec2(-FLT_MAX, -FLT_MAX);
    io.MouseDown[0] = m_hasMouse && m_mouseDown;
    const bool changed = m_wb.update();
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    drawPanels(m_wb, *g_ui);
    ImGui::Render();
    m_target.bind();
    glClearColor(0.08f, 0.08f, 0.09f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    renderImGuiDrawData();
    servicePngExport(m_wb, *g_ui, m_target.framebuffer(), pixelHeight(), m_scale);
    // A headless frame is "presented" when its pixels exist: finish like a swap would, so
    // software rasterisers (llvmpipe) do not pile frames up until the next readback.
    glFinish();
    if (changed) m_wb.framePresented();
    gl::collectTimings(true);
    return changed;
}

void HeadlessGui::resize(int width, int height) {
    m_width = width;
    m_height = height;
    m_target.resize(pixelWidth(), pixelHeight());
    ImGui::GetIO().DisplaySize = ImVec2(float(width), float(height));
}

void HeadlessGui::mouse(float x, float y, bool down) {
    m_hasMouse = true;
    m_mouseX = x;
    m_mouseY = y;
    m_mouseDown = down;
}

void HeadlessGui::setUiScale(float uiScale) {
    m_scale = uiScale > 0 ? uiScale : 1.0f;
    reloadFonts(m_scale);
    m_target.resize(pixelWidth(), pixelHeight());
    ImGui::GetIO().DisplayFramebufferScale = ImVec2(m_scale, m_scale);
}

UiState& HeadlessGui::ui() {
    return *g_ui;
}

std::vector<unsigned char> HeadlessGui::pixels() const {
    auto px = gl::readPixelsRGBA8(m_target.framebuffer(), 0, 0, pixelWidth(), pixelHeight());
    for (size_t i = 3; i < px.size(); i += 4)
        px[i] = 255; // the UI has no meaningful alpha
    return px;
}

namespace {

constexpr const char* kGlResetName = "gl-reset";

// After a driver reset nothing on this context works any more: the state goes to
// glResetRequest(root) with the reason, for the restarted program to rebuild (runGui's caller).
int saveStateAfterReset(Workbench& wb, gl::ResetStatus reset) {
    const std::string reason = gl::describe(reset);
    core::logError(reason + ": the workbench starts again on a new context with its state");
    const fs::path dir = glResetRequest(wb.root()).parent_path();
    saveSession(wb, dir); // (models from elsewhere are opened where they are, not copied)
    core::writeFile(dir / "reason.txt", reason);
    return kGlResetRestart;
}

// Runs one frame; true when the driver reset the context during or after it, the state then
// saved and rc set. A GPU wait inside the frame that met the reset throws (gl/fence.cpp): that
// error is the reset's, and the frame is closed for ImGui.
bool frameMetReset(Workbench& wb, const std::function<void()>& frame, int& rc) {
    try {
        frame();
    } catch (const core::Error&) {
        if (gl::graphicsResetStatus() == gl::ResetStatus::None) throw;
        if (ImGui::GetCurrentContext()->WithinFrameScope) ImGui::EndFrame();
    }
    const gl::ResetStatus reset = gl::graphicsResetStatus();
    if (reset == gl::ResetStatus::None) return false;
    rc = saveStateAfterReset(wb, reset);
    return true;
}

} // namespace

std::filesystem::path glResetRequest(const std::filesystem::path& root) {
    return recordRequestPath(root, kGlResetName);
}

std::unique_ptr<Workbench> workbenchAfterReset(const std::filesystem::path& root, bool watch) {
    const fs::path dir = glResetRequest(root).parent_path();
    std::string reason = "the GPU driver reset the OpenGL context";
    std::error_code ec;
    if (std::filesystem::exists(dir / "reason.txt", ec))
        reason = core::readFile(dir / "reason.txt");
    std::unique_ptr<Workbench> wb = restoreSession(dir, root, watch);
    if (!wb) wb = std::make_unique<Workbench>(root, watch);
    std::filesystem::remove_all(dir, ec);
    wb->reportActionError("GPU: " + reason +
                          "; the workbench started again on a new OpenGL context with the state "
                          "it had (models, parameters, settings)");
    return wb;
}

int runGui(Workbench& wb, gl::Context& ctx, const GuiOptions& opt) {
    UiState ui;
    g_ui = &ui;
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    applyStyle();
    // the UI scale: asked for, else the window's content scale (followed while it runs), else 1
    float scale = opt.uiScale > 0 ? opt.uiScale : 1.0f;
    if (!ctx.headless() && opt.uiScale <= 0) scale = gl::contentScale(ctx.window());
    loadFonts(scale);
    static std::string ini; // must outlive the context
    ini = layoutFilePath().string();
    io.IniFilename = opt.persistLayout && opt.saveLayout ? ini.c_str() : nullptr;
    addLayoutHandler(ui);
    if (opt.persistLayout) ImGui::LoadIniSettingsFromDisk(ini.c_str());
    if (opt.prepare) opt.prepare(ui);

    int rc = 0;
    if (!ctx.headless()) {
        GLFWwindow* win = ctx.window();
        ImGui_ImplGlfw_InitForOpenGL(win, true);
        installKeyTaps(win);     // a shortcut tapped within one frame is seen (key_taps.h)
        installMouseClicks(win); // a double click is timed by its events (mouse_clicks.h)
        ImGui_ImplOpenGL3_Init("#version 450");
        // a save, and a child's output (a model check's verdict, a replay's progress), wake the
        // loop at once instead of at the end of its wait; stopped before the window goes,
        // however this loop ends
        wb.wakeOnFileChanges([] { glfwPostEmptyEvent(); });
        wakeOnChildOutput([] { glfwPostEmptyEvent(); });
        glfwSetDropCallback(win, [](GLFWwindow*, int count, const char** paths) {
            for (int i = 0; i < count; ++i)
                g_dropped.emplace_back(paths[i]);
        });
        struct StopWake {
            Workbench& wb;
            GLFWwindow* win;
            ~StopWake() {
                removeKeyTaps();
                removeMouseClicks();
                wb.wakeOnFileChanges({});
                wakeOnChildOutput({});
                glfwSetDropCallback(win, nullptr);
                g_dropped.clear();
            }
        } stopWake{wb, win};
        const auto closeRequested = [&] { return opt.closeRequest && opt.closeRequest->load(); };
        FramePacing pacing; // full rate while anything moves, else a frame now and then
        while (!glfwWindowShouldClose(win) && !ui.shared.quit && !closeRequested()) {
            // idle without spinning; the watcher is polled below
            const double asked = pacing.nextWait();
            const double waitStart = glfwGetTime();
            glfwWaitEventsTimeout(asked);
            const double waitEnd = glfwGetTime();
            pacing.waited(asked, waitEnd - waitStart, waitEnd);
            if (opt.uiScale <= 0) // the window went to a screen that scales differently
                if (const float now = gl::contentScale(win); now != scale) {
                    scale = now;
                    reloadFonts(scale);
                }
            const auto frame = [&] {
                if (!g_dropped.empty()) {
                    const std::vector<fs::path> dropped = std::move(g_dropped);
                    g_dropped.clear();
                    openDroppedFiles(wb, ui, dropped);
                }
                const bool changed = wb.update();
                ImGui_ImplOpenGL3_NewFrame();
                ImGui_ImplGlfw_NewFrame();
                applyKeyTaps(win);
                const UiUnits units = applyUiScale(win, scale);
                if (units.width > 0) {
                    ui.shared.windowWidth = units.width;
                    ui.shared.windowHeight = units.height;
                }
                applyMouseClicks(win, units.perCoordinate);
                ImGui::NewFrame();
                drawPanels(wb, ui);
                ImGui::Render();
                int w = 0, h = 0;
                glfwGetFramebufferSize(win, &w, &h);
                glBindFramebuffer(GL_FRAMEBUFFER, 0);
                glViewport(0, 0, w, h);
                glClearColor(0.08f, 0.08f, 0.09f, 1.0f);
                glClear(GL_COLOR_BUFFER_BIT);
                renderImGuiDrawData();
                servicePngExport(wb, ui, 0, h, scale);
                glfwSwapBuffers(win);
                if (changed) wb.framePresented();
                gl::collectTimings();
                pacing.framed(changed || wb.working() || ImGui::GetIO().WantTextInput,
                              glfwGetTime());
            };
            if (frameMetReset(wb, frame, rc)) break;
        }
        removeKeyTaps(); // the backend's callbacks back, which its shutdown replaces
        removeMouseClicks();
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
    } else {
        {
            HeadlessGui gui(wb, opt.width, opt.height, scale);
            ui.shared.windowWidth = opt.width;
            ui.shared.windowHeight = opt.height;
            for (int f = 0; f < std::max(1, opt.frames) && !ui.shared.quit; ++f) {
                if (frameMetReset(
                        wb, [&] { gui.frame(); }, rc))
                    break;
                // The first frame enables the scene when its panels are open; headless runs
                // wait for it (point cloud, occluded IBL) so the image shows the result.
                if (f == 0 && wb.scene().settings().enabled) wb.finishScene();
            }
            if (rc == 0 && !opt.screenshotPath.empty()) {
                try {
                    gl::writePng(opt.screenshotPath, gui.pixelWidth(), gui.pixelHeight(),
                                 gui.pixels());
                } catch (const core::Error& e) {
                    core::logError(e.what());
                    rc = 1;
                }
            }
        }
        ImGui_ImplOpenGL3_Shutdown();
    }
    if (opt.persistLayout && opt.saveLayout) ImGui::SaveIniSettingsToDisk(ini.c_str());
    ImGui::DestroyContext();
    g_ui = nullptr;
    return rc;
}

} // namespace app
