// `gui` (the default command: the interactive workbench in a window, or with no display the
// default capture recorded and replayed headless plus a screenshot) and `screenshot` (the full
// GUI run headless for some frames, saved as PNG).
#include "captures/capture_io.h"
#include "cli/args.h"
#include "cli/command.h"
#include "core/core.h"
#include "gl/gl.h"
#include "gui/gui.h"
#include "pipeline/workbench.h"

#include <cstdio>
#include <memory>
#include <tuple>

namespace app {
namespace fs = std::filesystem;

namespace {

int runHeadlessDefault(const fs::path& root, const std::string& outDir) {
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
    opt.screenshotPath = (out / "workbench.png").string();
    Workbench full(root, false);
    rc |= runGui(full, *ctx, opt);
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
                bool headless = false;
                std::string out, size;
            };
            auto a = std::make_shared<Args>();
            // also the program's own options, since `gui` is what runs without a command
            CLI::App& top = *cmd.get_parent();
            top.add_flag("--headless", a->headless,
                         "no window: record + replay the default capture and save a screenshot");
            top.add_option("--out-dir", a->out, "where --headless writes (default out/default)");
            cmd.add_flag("--headless", a->headless, "same as the top-level --headless");
            cmd.add_option("--size", a->size,
                           "window WxH (default: the size it had last time, else 1600x1000; "
                           "shrunk to fit the screen's work area)");
            return [a](CommandContext& ctx) {
                int width = 1600, height = 1000;
                if (!a->size.empty() && !parseSize(a->size, width, height, 320))
                    throw core::Error("--size", 0,
                                      "expected WxH between 320 and 8192, got '" + a->size + "'");
                if (a->size.empty())
                    if (auto last = rememberedWindowSize()) std::tie(width, height) = *last;
                const fs::path& root = ctx.root();
                bool headless = a->headless;
                if (!headless && !gl::displayAvailable()) {
                    std::printf("no display found (DISPLAY/WAYLAND_DISPLAY unset or "
                                "unreachable): running the default capture headless\n");
                    headless = true;
                }
                if (headless) return runHeadlessDefault(root, a->out);
                std::fprintf(stderr, "resources: %s\n", root.c_str());
                auto window = gl::createWindowContext(width, height, "BSSRDF Workbench");
                Workbench wb(root, true);
                GuiOptions opt;
                return runGui(wb, *window, opt);
            };
        }};
}

Command screenshotCommand() {
    return {"screenshot", "run the full GUI headless and save a PNG", false,
            [](CLI::App& cmd) -> CommandRun {
                struct Args {
                    std::string out, size = "1600x1000";
                    int frames = 3;
                };
                auto a = std::make_shared<Args>();
                cmd.add_option("--out", a->out, "PNG file")->required();
                cmd.add_option("--frames", a->frames, "frames to run before saving")
                    ->check(CLI::Range(1, 10000));
                cmd.add_option("--size", a->size, "WxH in pixels");
                return [a](CommandContext& ctx) {
                    const fs::path& root = ctx.root();
                    GuiOptions opt;
                    if (!parseSize(a->size, opt.width, opt.height))
                        throw core::Error(
                            "--size", 0, "expected WxH between 64 and 8192, got '" + a->size + "'");
                    opt.frames = a->frames;
                    opt.screenshotPath = a->out;
                    opt.persistLayout = false;
                    auto gl = gl::createHeadlessContext();
                    Workbench wb(root, false);
                    int rc = runGui(wb, *gl, opt);
                    if (rc == 0) std::printf("wrote %s\n", a->out.c_str());
                    return rc;
                };
            }};
}

} // namespace app
