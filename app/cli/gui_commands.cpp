// `gui` (the default command: the interactive workbench in a window, or with no display the
// default capture recorded and replayed headless plus a screenshot) and `screenshot` (the full
// GUI run headless for some frames, saved as PNG).
#include "captures/capture_io.h"
#include "captures/open_capture.h"
#include "captures/session.h"
#include "cli/args.h"
#include "cli/command.h"
#include "cli/interrupt.h"
#include "cli/output.h"
#include "core/core.h"
#include "gl/gl.h"
#include "gui/gui.h"
#include "gui/panels/panels.h"
#include "pipeline/workbench.h"
#include "probe/child_process.h"

#include <GLFW/glfw3.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <tuple>

namespace app {
namespace fs = std::filesystem;

namespace {

// "WxH" of the GUI's default size (GuiOptions).
std::string defaultSizeText() {
    const GuiOptions d;
    return std::to_string(d.width) + "x" + std::to_string(d.height);
}

// Starts the program again after a GPU driver reset (gui.h, kGlResetRestart): the same command
// with --restore-after-reset, on a new context, from the state runGui saved. Returns only when
// it cannot (exit 1 with the reason).
int restartAfterReset(const fs::path& root, std::vector<std::string> args) {
    args.insert(args.begin(), {selfExecutable().string(), "--root", root.string()});
    args.push_back("--restore-after-reset");
    gl::stopSimulatedResetsInChildren();
    std::fflush(nullptr);
    std::vector<char*> argv;
    for (std::string& a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    std::fprintf(stderr,
                 "error: cannot start %s again after the GPU reset: %s (the state is in %s)\n",
                 argv[0], std::strerror(errno), glResetRequest(root).c_str());
    return 1;
}

// --ui-scale: "auto" (0: the display's own) or a factor in [0.5, 4]; throws core::Error.
constexpr const char* kUiScaleHelp =
    "screen pixels per UI unit: auto (the desktop's scaling of the screen; 1 headless) or a "
    "factor from 0.5 to 4 (sizes stay in UI units)";
float parseUiScale(const std::string& text) {
    if (text == "auto") return 0.0f;
    char* end = nullptr;
    const float f = std::strtof(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(f >= 0.5f && f <= 4.0f))
        throw core::Error("--ui-scale", 0,
                          "expected auto or a number from 0.5 to 4, got '" + text + "'");
    return f;
}
// The pixels of `width` x `height` UI units at `scale` stay within what the screenshot holds.
void checkScaledSize(int width, int height, float scale) {
    if (scaledSize(std::max(width, height), scale > 0 ? scale : 1.0f) > 8192)
        throw core::Error(
            "--ui-scale", 0,
            "the image would be over 8192 pixels wide or high: " + std::to_string(width) + "x" +
                std::to_string(height) + " at " + core::formatNumber(scale));
}

std::unique_ptr<Workbench> guiWorkbench(const fs::path& root, bool restore, bool watch) {
    if (restore) return workbenchAfterReset(root, watch);
    return std::make_unique<Workbench>(root, watch);
}

// The window's workbench: the state the last session of this project left (captures/
// session.h) unless `fresh`, then the models given on the command line opened.
std::unique_ptr<Workbench> windowWorkbench(const fs::path& root, bool fresh,
                                           const std::vector<fs::path>& models) {
    std::unique_ptr<Workbench> wb;
    if (!fresh) wb = restoreSession(sessionDir(configDir(), root), root, true);
    if (wb)
        std::fprintf(stderr, "restored the last session of %s (gui --fresh starts without it)\n",
                     root.c_str());
    else
        wb = std::make_unique<Workbench>(root, true);
    for (const fs::path& m : models)
        wb->openModel(m);
    return wb;
}

constexpr const char* kCaptureHelp =
    "open the state a capture recorded (NAME under captures/, or a capture folder): its models, "
    "parameters, settings and traced pixel, to look at and change; the project's session and "
    "layout are left as they were";

// --capture: the capture's folder, its manifest read before any window opens (core::Error).
fs::path checkedCapture(const fs::path& root, const std::string& given) {
    const fs::path dir = findCapture(root, given);
    (void)capture::readManifest(dir);
    return dir;
}

// Shows what the opened capture recorded once the layout is loaded.
std::function<void(UiState&)> showCapture(const OpenedCapture& oc) {
    Workbench* wb = oc.wb.get();
    const int x = oc.traceX, y = oc.traceY;
    const std::string name = oc.name;
    return [wb, x, y, name](UiState& ui) { showCapturedState(*wb, ui, name, x, y); };
}

int runHeadlessDefault(const fs::path& root, const std::string& outDir, int width, int height,
                       float uiScale) {
    fs::path out = outDir.empty() ? fs::path("out") / "default" : fs::path(outDir);
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) throw core::Error(out.string(), 0, "cannot create output folder: " + ec.message());
    auto ctx = gl::createHeadlessContext();
    std::printf("GL: %s | %s\n", ctx->renderer().c_str(), ctx->version().c_str());
    Workbench wb(root, false, {root / "materials" / "dipole.bssrdf"});
    // the mesh pipeline too (a small cloud and image keep the capture quick to replay)
    SceneSettings& scene = wb.scene().settings();
    scene.enabled = true;
    scene.useCache = false;
    scene.points.points = 3000;
    scene.render.width = 160;
    scene.render.height = 90;
    recordCaptureTo(wb, out / "capture", "default", 80, 45);
    std::string text;
    int rc = replayCapture(out / "capture", root, false, text);
    std::printf("%s", text.c_str());
    GuiOptions opt;
    opt.persistLayout = false;
    opt.width = width;
    opt.height = height;
    opt.uiScale = uiScale;
    opt.screenshotPath = (out / "workbench.png").string();
    Workbench full(root, false);
    const int gui = runGui(full, *ctx, opt);
    if (gui == kGlResetRestart)
        throw core::Error("gui", 0,
                          "the GPU driver reset the OpenGL context (state saved in " +
                              glResetRequest(root).string() + ")");
    rc |= gui;
    std::printf("outputs:\n  capture    %s\n  screenshot %s\n",
                fs::absolute(out / "capture").string().c_str(),
                fs::absolute(out / "workbench.png").string().c_str());
    return rc;
}

} // namespace

Command guiCommand() {
    return {
        "gui", "interactive workbench (default)", false, [](CLI::App& cmd) -> CommandRun {
            struct Args {
                bool headless = false, restore = false, fresh = false, leaveSession = false;
                std::string out, size, uiScale = "auto", capture;
                std::vector<std::string> models;
            };
            auto a = std::make_shared<Args>();
            // also the program's own options, since `gui` is what runs without a command
            CLI::App& top = *cmd.get_parent();
            CLI::Option* headlessFlag = top.add_flag(
                "--headless", a->headless,
                "no window: record + replay the default capture and save a screenshot");
            CLI::Option* outDir = top.add_option(
                "--out-dir", a->out,
                "where --headless (or a run without a display) writes (default out/default)");
            // They do nothing for another command, nor --out-dir for the window.
            top.parse_complete_callback([&top, &cmd, a, headlessFlag, outDir] {
                for (const CLI::App* other : top.get_subcommands())
                    if (other != &cmd)
                        for (const CLI::Option* o : {headlessFlag, outDir})
                            if (o->count() > 0)
                                throw CLI::ValidationError(
                                    o->get_name(), "belongs to the GUI (the default command); " +
                                                       other->get_name() + " does not use it");
                if (outDir->count() > 0 && !a->headless && gl::displayAvailable())
                    throw CLI::ValidationError(
                        "--out-dir", "is where a headless run writes, and a display was found: "
                                     "add --headless, or leave --out-dir out for the window");
            });
            cmd.add_flag("--headless", a->headless, "same as the top-level --headless");
            cmd.add_flag("--restore-after-reset", a->restore,
                         "start from the state saved when the GPU driver reset the context")
                ->group(""); // the program passes it to itself
            cmd.add_option("--size", a->size,
                           "window WxH (default: the size it had last time, else " +
                               defaultSizeText() +
                               "; shrunk to fit the screen's work area) in UI units; "
                               "headless: the screenshot's");
            cmd.add_option("--ui-scale", a->uiScale, kUiScaleHelp)->capture_default_str();
            cmd.add_flag("--fresh", a->fresh,
                         "start with the defaults, not with the state the window had when it last "
                         "closed on this project (its models, parameters and settings)");
            cmd.add_option("--capture", a->capture, kCaptureHelp);
            cmd.add_flag("--leave-session", a->leaveSession,
                         "keep neither the session nor the layout on close (a window on a "
                         "capture, started again after a GPU reset)")
                ->group(""); // the program passes it to itself
            cmd.add_option("models", a->models,
                           ".bssrdf models to open besides the project's (as File > Open model)");
            return [a](CommandContext& ctx) {
                int width = GuiOptions{}.width, height = GuiOptions{}.height;
                if (!a->size.empty() && !parseSize(a->size, width, height, 320))
                    throw core::Error("--size", 0,
                                      "expected WxH between 320 and 8192, got '" + a->size + "'");
                const float uiScale = parseUiScale(a->uiScale);
                const fs::path& root = ctx.root();
                const fs::path captureDir =
                    a->capture.empty() ? fs::path() : checkedCapture(root, a->capture);
                if (!a->capture.empty() && a->fresh)
                    throw core::Error("--fresh", 0,
                                      "a window on a capture starts from the capture, never from "
                                      "the last session (leave --fresh out)");
                bool headless = a->headless;
                if (!a->capture.empty() && (headless || !gl::displayAvailable()))
                    throw core::Error(
                        "--capture", 0,
                        "opens a capture in a window, and there is " +
                            std::string(headless ? "none (--headless)" : "no display") +
                            ": `replay " + a->capture +
                            "` compares it headless, `screenshot --capture " + a->capture +
                            " --out FILE.png` draws it");
                if (!headless && !gl::displayAvailable()) {
                    std::printf("no display found (DISPLAY/WAYLAND_DISPLAY unset or "
                                "unreachable): running the default capture headless\n");
                    headless = true;
                }
                if (headless) {
                    for (const auto& [given, flag] :
                         {std::pair{!a->models.empty(), "a model file"}, {a->fresh, "--fresh"}})
                        if (given)
                            throw core::Error(flag, 0,
                                              "belongs to the window; the headless run records "
                                              "the default capture (leave it out)");
                    checkScaledSize(width, height, uiScale);
                    return runHeadlessDefault(root, a->out, width, height, uiScale);
                }
                std::vector<fs::path> models;
                for (const std::string& m : a->models) { // checked before the window opens
                    models.push_back(resolveModel(root, m, "gui"));
                    if (models.back().extension() != ".bssrdf")
                        throw core::Error(models.back().string(), 0,
                                          "not a .bssrdf model file (gui opens models)");
                }
                if (a->size.empty())
                    if (auto last = rememberedWindowSize()) std::tie(width, height) = *last;
                std::fprintf(stderr, "resources: %s\n", root.c_str());
                const std::string title =
                    a->capture.empty() ? "BSSRDF Workbench"
                                       : "BSSRDF Workbench - capture " +
                                             captureDir.lexically_normal().filename().string();
                auto window = gl::createWindowContext(width, height, title.c_str(), true, uiScale);
                GuiOptions opt;
                opt.uiScale = uiScale;
                opt.closeRequest = closeRequestFlag();
                OpenedCapture opened;
                std::unique_ptr<Workbench> wb;
                if (!a->capture.empty()) {
                    opened = openCapture(root, captureDir, true);
                    for (const fs::path& m : models)
                        opened.wb->openModel(m);
                    opt.saveLayout = false;
                    opt.prepare = showCapture(opened);
                } else {
                    opt.saveLayout = !a->leaveSession;
                    wb = a->restore ? guiWorkbench(root, true, true)
                                    : windowWorkbench(root, a->fresh, models);
                }
                Workbench& shown = opened.wb ? *opened.wb : *wb;
                const int rc = runGui(shown, *window, opt);
                if (interrupted())
                    std::fprintf(stderr, "closed the window on %s\n", interruptingSignal().c_str());
                if (rc == 0 && (opened.wb || a->leaveSession)) {
                    std::fprintf(stderr, "the window was on a capture: the project's session and "
                                         "layout are as they were (File > Record capture keeps "
                                         "a state)\n");
                } else if (rc == 0) {
                    // the state for the next start (gui --fresh starts without it)
                    try {
                        saveSession(shown, sessionDir(configDir(), root));
                    } catch (const core::Error& e) {
                        std::fprintf(stderr, "error: the session was not saved: %s\n", e.what());
                        return 1;
                    }
                }
                if (rc != kGlResetRestart) return rc;
                // at the size the window had (in UI units: runGui saved it with the layout)
                const auto [w, h] = rememberedWindowSize().value_or(std::pair{width, height});
                std::vector<std::string> again = {"gui", "--size",
                                                  std::to_string(std::max(w, 320)) + "x" +
                                                      std::to_string(std::max(h, 320)),
                                                  "--ui-scale", a->uiScale};
                if (opened.wb || a->leaveSession) again.push_back("--leave-session");
                return restartAfterReset(root, again);
            };
        }};
}

Command screenshotCommand() {
    return {"screenshot", "run the full GUI headless and save a PNG", false,
            [](CLI::App& cmd) -> CommandRun {
                struct Args {
                    std::string out, size = defaultSizeText(), uiScale = "auto", capture;
                    int frames = GuiOptions{}.frames;
                    bool restore = false;
                };
                auto a = std::make_shared<Args>();
                cmd.add_option("--out", a->out, "PNG file")->required();
                cmd.add_option("--frames", a->frames, "frames to run before saving")
                    ->check(CLI::Range(1, 10000))
                    ->capture_default_str();
                cmd.add_option("--size", a->size, "WxH in UI units (the PNG: times --ui-scale)")
                    ->capture_default_str();
                cmd.add_option("--ui-scale", a->uiScale, kUiScaleHelp)->capture_default_str();
                cmd.add_option("--capture", a->capture,
                               "draw the state a capture recorded (NAME under captures/, or a "
                               "capture folder), as gui --capture opens it");
                cmd.add_flag("--restore-after-reset", a->restore,
                             "start from the state saved when the GPU driver reset the context")
                    ->group("");
                return [a](CommandContext& ctx) {
                    checkOutput(a->out, "--out", ".png"); // before the frames, not after them
                    const fs::path& root = ctx.root();
                    GuiOptions opt;
                    if (!parseSize(a->size, opt.width, opt.height))
                        throw core::Error(
                            "--size", 0, "expected WxH between 64 and 8192, got '" + a->size + "'");
                    opt.uiScale = parseUiScale(a->uiScale);
                    checkScaledSize(opt.width, opt.height, opt.uiScale);
                    opt.frames = a->frames;
                    opt.screenshotPath = a->out;
                    opt.persistLayout = false;
                    const fs::path captureDir =
                        a->capture.empty() ? fs::path() : checkedCapture(root, a->capture);
                    auto gl = gl::createHeadlessContext();
                    OpenedCapture opened;
                    std::unique_ptr<Workbench> wb;
                    if (!a->capture.empty() && !a->restore) {
                        opened = openCapture(root, captureDir, false);
                        opt.prepare = showCapture(opened);
                    } else {
                        wb = guiWorkbench(root, a->restore, false);
                    }
                    const int rc = runGui(opened.wb ? *opened.wb : *wb, *gl, opt);
                    if (rc == kGlResetRestart)
                        return restartAfterReset(root, {"screenshot", "--out", a->out, "--frames",
                                                        std::to_string(a->frames), "--size",
                                                        a->size, "--ui-scale", a->uiScale});
                    if (rc == 0) std::printf("wrote %s\n", a->out.c_str());
                    return rc;
                };
            }};
}

} // namespace app
