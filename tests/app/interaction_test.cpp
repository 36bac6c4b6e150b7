// Interactions with injected mouse input on the real GUI headless: a click on the Render image
// traces that pixel in the Traversal debugger with "half resolution while moving" on, also
// right after an orbit left a half-resolution frame on screen; a drag orbits and traces
// nothing; GL debug messages and problems reach Errors once; the Render panel's model choice,
// pixel probe and export.
#include "../support/gl_debug_guard.h"
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "gui/gui.h"
#include "gui/panels/panels.h"
#include "gui/scene_view.h"
#include "pathtrace/image_io.h"

#include <glm/gtc/matrix_transform.hpp>

#include <chrono>
#include <cmath>
#include <thread>
#include <tuple>

namespace {

struct RenderFixture {
    gl::Context& ctx = testsupport::context(); // before anything that uses GL
    std::filesystem::path root = testsupport::makeProjectRoot("interact", {"dipole.bssrdf"});
    app::Workbench wb{root, false};
    std::unique_ptr<app::HeadlessGui> gui;

    RenderFixture() {
        testsupport::useSmallScene(wb.scene().settings());
        gui = std::make_unique<app::HeadlessGui>(wb, 1280, 720);
        gui->ui() = app::UiState{};
        gui->frame();
        wb.finishScene();
        // the frame arrives, then the panel lays out again with its vertical scrollbar: the
        // image's place has settled by the third frame
        for (int i = 0; i < 3; ++i)
            gui->frame();
    }
    ~RenderFixture() { std::filesystem::remove_all(root); }

    // The screen position of a point of the image given as a fraction of it.
    std::pair<float, float> at(float u, float v) {
        const app::Rect& r = gui->ui().render.imageRect;
        return {r.x0 + u * r.width(), r.y0 + v * r.height()};
    }
    void press(float x, float y) {
        gui->mouse(x, y, false);
        gui->frame();
        gui->mouse(x, y, true);
        gui->frame();
    }
    void release(float x, float y) {
        gui->mouse(x, y, false);
        gui->frame();
        gui->noMouse();
    }
    // A click at (u, v) of the image, then frames until it is traced; the pixel it names.
    std::pair<int, int> clickAndTrace(float u, float v) {
        auto [x, y] = at(u, v);
        press(x, y);
        release(x, y);
        settle();
        return {int(u * 96), int(v * 54)};
    }
    // Frames until the pending click is served (or a bound).
    void settle() {
        for (int i = 0; i < 40 && gui->ui().shared.inspect.pendingPick; ++i) {
            wb.finishScene();
            gui->frame();
        }
    }
};

} // namespace

TEST(Interactions, ClickOnTheRenderImageTracesThatPixelWithHalfResolutionOn) {
    RenderFixture fx;
    app::UiState& ui = fx.gui->ui();
    ASSERT_TRUE(fx.wb.scene().settings().halfResolutionWhileChanging);
    ASSERT_TRUE(fx.wb.scene().hasFrame());
    ASSERT_GT(ui.render.imageRect.width(), 50.0f);

    // a plain click
    const auto [px, py] = fx.clickAndTrace(0.52f, 0.55f);
    ASSERT_TRUE(ui.shared.inspect.debug.has_value()) << ui.shared.inspect.debugProblem;
    EXPECT_EQ(ui.shared.inspect.debug->x, px);
    EXPECT_EQ(ui.shared.inspect.debug->y, py);
    fx.gui->frame();
    fx.gui->frame();
    EXPECT_NE(testsupport::panelWindow(app::PanelId::Traversal), nullptr);

    // a drag orbits the camera at half resolution and traces nothing
    ui.shared.inspect.debug.reset();
    const float yaw = fx.wb.scene().settings().render.camera.yaw;
    auto [x, y] = fx.at(0.52f, 0.55f);
    fx.press(x, y);
    // (each step of the drag begins a half-resolution frame; whether one is finished within a
    // UI frame's budget depends on the machine's load, so the frame begun is what is checked)
    bool sawHalf = false;
    for (int i = 1; i <= 8; ++i) {
        fx.gui->mouse(x + 6.0f * float(i), y, true);
        fx.gui->frame();
        const render::Renderer* r = fx.wb.scene().renderer();
        sawHalf |= fx.wb.scene().frame().width == 48 || (r && r->currentFrame().width == 48);
    }
    fx.release(x + 48, y);
    EXPECT_NE(fx.wb.scene().settings().render.camera.yaw, yaw);
    EXPECT_TRUE(sawHalf);
    EXPECT_FALSE(ui.shared.inspect.pendingPick.has_value());

    // a click right after the orbit, with the half-resolution frame still on screen, traces
    // the full-resolution pixel under the cursor once that frame is done
    const auto [qx, qy] = fx.clickAndTrace(0.3f, 0.7f);
    ASSERT_TRUE(ui.shared.inspect.debug.has_value()) << ui.shared.inspect.debugProblem;
    EXPECT_EQ(ui.shared.inspect.debug->x, qx);
    EXPECT_EQ(ui.shared.inspect.debug->y, qy);
    EXPECT_TRUE(fx.wb.errors().empty());
}

namespace {
// The (node, depth, decision) of every step: what two traversals are compared by.
std::vector<std::tuple<uint32_t, uint32_t, int>> stepsOf(const app::PixelDebug& d) {
    std::vector<std::tuple<uint32_t, uint32_t, int>> out;
    for (const auto& s : d.trace.steps)
        out.emplace_back(s.node, s.depth, int(s.decision));
    return out;
}
} // namespace

// The traced pixel follows the render: a change of ε re-traces it on the new full-resolution
// frame and keeps the trace it replaced to compare with; Pin keeps a baseline instead (ε set
// back gives its steps again); with follow off the trace stays; Unpin forgets the baseline.
TEST(Interactions, TheTracedPixelFollowsTheRenderAndComparesWithTheTraceBefore) {
    RenderFixture fx;
    app::UiState& ui = fx.gui->ui();
    app::SceneInspect& in = ui.shared.inspect;
    const auto [px, py] = fx.clickAndTrace(0.52f, 0.55f);
    ASSERT_TRUE(in.debug && in.debug->hit) << in.debugProblem;
    EXPECT_FALSE(in.previous);
    const auto first = stepsOf(*in.debug);
    fx.gui->frame();
    ASSERT_GT(ui.traversal.pin.width(), 0) << "no Pin button";
    testsupport::click(*fx.gui, ui.traversal.pin);
    ASSERT_TRUE(in.pinned);
    EXPECT_EQ(stepsOf(*in.pinned), first);

    // ε changed: traced again at the same pixel, the trace before kept
    float& eps = fx.wb.scene().settings().render.eps;
    const float eps0 = eps;
    const auto changeEps = [&](float to) {
        const long long before = in.tracedFrame;
        eps = to;
        for (int i = 0; i < 40 && in.tracedFrame == before; ++i) {
            fx.wb.finishScene();
            fx.gui->frame();
        }
        return in.tracedFrame != before;
    };
    ASSERT_TRUE(changeEps(eps0 * 16)) << "not traced again";
    ASSERT_TRUE(in.debug && in.previous);
    EXPECT_EQ(in.debug->x, px);
    EXPECT_EQ(in.debug->y, py);
    EXPECT_EQ(stepsOf(*in.previous), first);
    EXPECT_NE(stepsOf(*in.debug), first) << "eps x16 left the traversal as it was";
    EXPECT_EQ(stepsOf(*in.pinned), first) << "the pinned baseline changed";

    // ε back: the pinned steps again
    ASSERT_TRUE(changeEps(eps0));
    EXPECT_EQ(stepsOf(*in.debug), first);
    fx.gui->frame();

    // follow off: a new frame leaves the trace as it is
    ASSERT_GT(ui.traversal.followBox.width(), 0);
    testsupport::click(*fx.gui, ui.traversal.followBox);
    ASSERT_FALSE(in.follow);
    EXPECT_FALSE(changeEps(eps0 * 16));
    EXPECT_EQ(stepsOf(*in.debug), first);
    testsupport::click(*fx.gui, ui.traversal.pin); // Unpin
    EXPECT_FALSE(in.pinned);
    EXPECT_TRUE(fx.wb.errors().empty());
}

// GL debug messages of medium/high severity reach the Errors panel, one entry per problem
// with its count and first message; Dismiss forgets them.
TEST(Interactions, GlDebugMessagesAreOneErrorsEntryPerProblem) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("gldebug", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.clearActionErrors();
    ASSERT_TRUE(wb.errors().empty());
    {
        bwtest::ExpectedGlErrors expected;
        for (GLuint bogus : {987654u, 987655u, 987656u}) // never generated: GL_INVALID_OPERATION
            glBindTexture(GL_TEXTURE_2D, bogus);
        glBindTexture(GL_TEXTURE_2D, 0);
        EXPECT_EQ(expected.count(), 3);
    }
    const auto errors = wb.errors();
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_EQ(errors[0].source, "GL");
    EXPECT_NE(errors[0].text.find("(3 times)"), std::string::npos) << errors[0].text;
    // the driver's words: Mesa names the call ("GL_INVALID_OPERATION in glBindTexture(non-gen
    // name)"), NVIDIA the error and the object ("GL_INVALID_OPERATION error generated. Texture
    // name does not refer to a texture object generated by OpenGL.")
    EXPECT_NE(errors[0].text.find("GL_INVALID_OPERATION"), std::string::npos) << errors[0].text;
    wb.clearActionErrors();
    EXPECT_TRUE(wb.errors().empty());
    std::filesystem::remove_all(root);
}

// A GL debug message describes the moment it came, not the state: its Errors entry (and the
// status bar's count) stays while the message keeps coming and leaves kGlProblemSeconds after
// its cause is gone; before, a message from a rejected model stayed after the fix.
TEST(Interactions, AGlErrorEntryLeavesWhenItsCauseIsGone) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("glstale", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.clearActionErrors();
    const auto wait = [](double fraction) {
        std::this_thread::sleep_for(
            std::chrono::duration<double>(fraction * app::Workbench::kGlProblemSeconds));
    };
    bwtest::ExpectedGlErrors expected;     // provoked on purpose below
    glBindTexture(GL_TEXTURE_2D, 987654u); // never generated: GL_INVALID_OPERATION, one message
    glBindTexture(GL_TEXTURE_2D, 0);       // on every driver (NVIDIA says glUseProgram's twice)
    wb.update();
    ASSERT_EQ(wb.errors().size(), 1u);
    EXPECT_EQ(wb.errors()[0].source, "GL");
    for (int i = 0; i < 3; ++i) { // the cause keeps coming: the entry stays
        wait(0.4);
        glBindTexture(GL_TEXTURE_2D, 987654u);
        glBindTexture(GL_TEXTURE_2D, 0);
        wb.update();
        EXPECT_EQ(wb.errors().size(), 1u) << "while the message keeps coming";
    }
    EXPECT_EQ(expected.count(), 4);
    wait(1.2); // the cause is gone: the entry leaves
    wb.update();
    EXPECT_TRUE(wb.errors().empty()) << wb.errors()[0].text;
    std::filesystem::remove_all(root);
}

// Dragging a Render control restarts the frame at half resolution (holding a button does not:
// RenderExportAsksWhereAndLogsTheFullPath); the image on screen must never be a texture the
// renderer already deleted (GL_INVALID_OPERATION in glBindTexture).
TEST(Interactions, DraggingARenderControlLeavesNoGlProblem) {
    RenderFixture fx;
    gl::clearDebugProblems();
    ImGuiWindow* w = testsupport::panelWindow(app::PanelId::Render);
    ASSERT_NE(w, nullptr);
    const float eps = fx.wb.scene().settings().render.eps;
    bool interacting = false;
    // on the eps slider: the second row, under the model choice
    const float x = w->Pos.x + 60, y = w->Pos.y + 10 + ImGui::GetFrameHeightWithSpacing();
    fx.press(x, y);
    for (int i = 0; i < 5; ++i) {
        fx.gui->mouse(x + 5.0f * float(i), y, true);
        fx.gui->frame();
        interacting |= fx.wb.interacting();
    }
    EXPECT_TRUE(interacting) << "dragging a control is an interaction (half resolution)";
    fx.release(x + 25, y);
    for (int i = 0; i < 5; ++i) {
        fx.wb.finishScene();
        fx.gui->frame();
    }
    EXPECT_NE(fx.wb.scene().settings().render.eps, eps);
    for (const auto& e : fx.wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
}

// A model deleted while the GUI runs leaves no GL problem behind (its programs are not used
// after they are gone).
TEST(Interactions, DeletingAModelLeavesNoGlProblem) {
    RenderFixture fx;
    gl::clearDebugProblems();
    std::filesystem::copy_file(fx.root / "materials/dipole.bssrdf",
                               fx.root / "materials/second.bssrdf");
    fx.wb.reloadAll();
    fx.gui->ui().shared.show(app::PanelId::Pencil);
    for (int i = 0; i < 3; ++i) {
        fx.wb.finishScene();
        fx.gui->frame();
    }
    ASSERT_EQ(fx.wb.library().entries().size(), 2u);
    std::filesystem::remove(fx.root / "materials/dipole.bssrdf");
    fx.wb.reloadAll();
    for (int i = 0; i < 5; ++i) {
        fx.gui->ui().shared.show(i % 2 ? app::PanelId::Render : app::PanelId::Pencil);
        fx.wb.finishScene();
        fx.gui->frame();
    }
    EXPECT_EQ(fx.wb.library().entries().size(), 1u);
    for (const auto& e : fx.wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
}

// The Render panel renders the model chosen in it (a name that is not a usable model falls
// back to the first visible one); hovering the image shows the pixel probe; the shown frame
// exports as EXR (the HDR values read back) and PNG, and a bad export path is an Errors-style
// message naming it.
TEST(Interactions, RenderPanelModelChoiceProbeAndExport) {
    RenderFixture fx;
    std::filesystem::copy_file(fx.root / "materials/dipole.bssrdf",
                               fx.root / "materials/other.bssrdf");
    fx.wb.reloadAll();
    app::SceneSettings& s = fx.wb.scene().settings();
    EXPECT_EQ(fx.wb.sceneModelInput().entry->displayPath, "materials/dipole.bssrdf");
    s.model = "materials/other.bssrdf";
    EXPECT_EQ(fx.wb.sceneModelInput().entry->displayPath, "materials/other.bssrdf");
    s.model = "materials/none.bssrdf";
    EXPECT_EQ(fx.wb.sceneModelInput().entry->displayPath, "materials/dipole.bssrdf");
    s.model.clear();
    fx.wb.finishScene();
    fx.gui->frame();

    // hover: the probe reads the shown frame back and draws a tooltip
    auto [x, y] = fx.at(0.5f, 0.5f);
    fx.gui->mouse(x, y, false);
    fx.gui->frame();
    fx.gui->frame();
    EXPECT_EQ(fx.gui->ui().render.readback.width, 96);
    bool tooltip = false;
    for (ImGuiWindow* w : ImGui::GetCurrentContext()->Windows)
        tooltip |= w->Active && (w->Flags & ImGuiWindowFlags_Tooltip);
    EXPECT_TRUE(tooltip);
    fx.gui->noMouse();

    const auto exr = fx.root / "view.exr", png = fx.root / "view.png";
    app::exportRenderView(fx.wb, fx.gui->ui().render, exr);
    app::exportRenderView(fx.wb, fx.gui->ui().render, png);
    const pathtrace::Image img = pathtrace::readExr(exr);
    const render::Readback rb = fx.wb.scene().readback();
    ASSERT_EQ(img.width, rb.width);
    ASSERT_EQ(img.height, rb.height);
    for (size_t p = 0; p < size_t(rb.width * rb.height); p += 97)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(img.mean[3 * p + size_t(c)], rb.hdr[p][c]);
    EXPECT_GT(std::filesystem::file_size(png), 100u);
    for (const char* bad : {"/proc/no/such/dir/v.exr", "view.tiff"}) {
        try {
            app::exportRenderView(fx.wb, fx.gui->ui().render, bad);
            ADD_FAILURE() << bad;
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
        }
    }
}

// Export asks where: a click on Export PNG opens the file dialog in the current folder with the
// name proposed; a path typed there and a click on Save write the file, and the status line and
// the log give its full path.
TEST(Interactions, RenderExportAsksWhereAndLogsTheFullPath) {
    RenderFixture fx;
    app::RenderPanelState& ps = fx.gui->ui().render;
    auto click = [&](const app::Rect& r) {
        const float x = 0.5f * (r.x0 + r.x1), y = 0.5f * (r.y0 + r.y1);
        fx.press(x, y);
        fx.release(x, y);
        fx.gui->frame();
    };
    // the export row is under the image: scroll the panel down to it, as a user would
    ImGuiWindow* panel = testsupport::panelWindow(app::PanelId::Render);
    ASSERT_NE(panel, nullptr);
    ImGui::SetScrollY(panel, 1e6f); // clamped to the bottom
    fx.gui->frame();
    fx.gui->frame();
    ASSERT_GT(ps.exportButtons[1].width(), 10.0f);
    ASSERT_LE(ps.exportButtons[1].y1, panel->InnerClipRect.Max.y) << "Export PNG not on screen";
    // Clicking a button is not an interaction: the frame is not rendered again (at half
    // resolution while the button is held, then again in full, which left nothing finished to
    // export on a slow machine when the click on Save came).
    ASSERT_FALSE(fx.wb.scene().rendering());
    const auto frames = [&] { return fx.wb.scene().stats().at("scene.render").runs; };
    const long long shown = frames();
    { // click(), looking in between
        const app::Rect& b = ps.exportButtons[1];
        const float x = 0.5f * (b.x0 + b.x1), y = 0.5f * (b.y0 + b.y1);
        fx.press(x, y);
        fx.gui->mouse(x, y, true); // held for another frame
        fx.gui->frame();
        EXPECT_FALSE(fx.wb.interacting()) << "holding a button is not an interaction";
        fx.release(x, y);
        fx.gui->frame();
    }
    EXPECT_EQ(std::string(ps.exporter.dialog.path),
              (std::filesystem::current_path() / "render.png").lexically_normal().string());
    ASSERT_GT(ps.exporter.dialog.actionRect[2], ps.exporter.dialog.actionRect[0]) << "no dialog";
    const std::filesystem::path target = fx.root / "exports" / "bunny";
    std::filesystem::create_directories(target.parent_path());
    ImGui::GetIO().AddInputCharactersUTF8(target.c_str()); // typed over the proposed path
    fx.gui->frame();
    const float* a = ps.exporter.dialog.actionRect;
    click({a[0], a[1], a[2], a[3]});
    EXPECT_EQ(frames(), shown) << "a click on a button rendered the frame again";
    EXPECT_FALSE(fx.wb.scene().rendering());
    const std::filesystem::path written = target.string() + ".png"; // the extension added
    ASSERT_TRUE(std::filesystem::exists(written)) << fx.gui->ui().shared.status;
    EXPECT_GT(std::filesystem::file_size(written), 100u);
    EXPECT_EQ(fx.gui->ui().shared.status, "wrote " + written.string());
    bool logged = false;
    for (const auto& line : core::logSnapshot())
        logged |= line.text.find("render: wrote " + written.string()) != std::string::npos;
    EXPECT_TRUE(logged);
    EXPECT_EQ(std::string(ps.exportName), "bunny");
    for (const auto& e : fx.wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
}

// A/B: brute force of the same view right of the divider (requested by the view itself), the
// divider dragged with the mouse on the strip under the image; then another model as B.
TEST(Interactions, RenderPanelAbSplitShowsBruteForceOrAnotherModel) {
    RenderFixture fx;
    app::UiState& ui = fx.gui->ui();
    ui.render.abSplit = true;
    for (int i = 0; i < 60 && !fx.wb.scene().comparison().image(); ++i)
        fx.gui->frame(); // the view requests the brute-force pass; update() advances it
    ASSERT_NE(fx.wb.scene().comparison().image(), nullptr);
    fx.gui->frame();
    EXPECT_NE(ui.render.abTex.id(), 0u);
    EXPECT_EQ(fx.wb.scene().comparison().image()->size(), size_t(96 * 54 * 4));
    // drag the divider from the middle to a quarter of the image
    const app::Rect r = ui.render.imageRect;
    const float y = r.y1 + 6;
    fx.press(r.x0 + 0.5f * r.width(), y);
    for (int i = 1; i <= 5; ++i) {
        fx.gui->mouse(r.x0 + (0.5f - 0.05f * float(i)) * r.width(), y, true);
        fx.gui->frame();
    }
    fx.release(r.x0 + 0.25f * r.width(), y);
    EXPECT_NEAR(ui.render.split, 0.25f, 0.02f);
    // moving the divider rendered nothing new: the brute-force image is still the current one
    EXPECT_NE(fx.wb.scene().comparison().image(), nullptr);
    EXPECT_EQ(fx.wb.scene().frame().width, 96);
    EXPECT_EQ(fx.wb.scene().comparison().name(), "brute force");

    // B: another model (a copy of the dipole at twice the Multiplier), same view
    std::string text = testsupport::readText(fx.root / "materials/dipole.bssrdf");
    core::writeFile(fx.root / "materials/twice.bssrdf", text);
    fx.wb.reloadAll();
    fx.wb.library().find("materials/twice.bssrdf")->values["Multiplier"] = {2.0f, 0, 0};
    fx.wb.update();
    fx.wb.finishScene();
    ui.render.abWith = "materials/twice.bssrdf";
    for (int i = 0; i < 60 && fx.wb.scene().comparison().name() != "twice"; ++i)
        fx.gui->frame();
    for (int i = 0; i < 60 && !fx.wb.scene().comparison().image(); ++i)
        fx.gui->frame();
    ASSERT_NE(fx.wb.scene().comparison().image(), nullptr);
    EXPECT_EQ(fx.wb.scene().comparison().name(), "twice");
    // not brute force: the relative-error heatmap does not take it for brute force
    EXPECT_EQ(fx.wb.scene().comparison().bruteForceResult(), nullptr);
    // twice the exitance: B is brighter than A wherever the surface is lit
    const render::Readback a = fx.wb.scene().readback();
    const std::vector<unsigned char>& b = *fx.wb.scene().comparison().image();
    long brighter = 0, compared = 0;
    for (size_t p = 0; p < a.ldr.size() / 4; ++p) {
        if (a.position[p].w < 0.5f || a.ldr[4 * p] < 20 || a.ldr[4 * p] > 235) continue;
        ++compared;
        brighter += b[4 * p] > a.ldr[4 * p] ? 1 : 0;
    }
    EXPECT_GT(compared, 100);
    EXPECT_GT(brighter, compared * 9 / 10);
    EXPECT_TRUE(fx.wb.errors().empty());
}

namespace {
// The Point cloud panel in front with its scene built; where its 3D view is.
app::Rect showPointCloud(app::HeadlessGui& gui, app::Workbench& wb) {
    gui.ui().shared.show(app::PanelId::PointCloud);
    gui.frame();
    wb.finishScene();
    for (int i = 0; i < 3; ++i)
        gui.frame();
    return gui.ui().pointCloud.imageRect;
}
} // namespace

// A click on the point cloud's 3D view picks the point drawn under it, at UI scale 1 and at 2 (the
// view drawn at twice the pixels, the click in UI units): the picked point projects to within
// a few units of the click.
TEST(Interactions, AClickOnThePointCloudPicksThePointUnderItAtEveryUiScale) {
    gl::Context& ctx = testsupport::context();
    (void)ctx;
    auto root = testsupport::makeProjectRoot("pickscale", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    testsupport::useSmallScene(wb.scene().settings());
    for (float scale : {1.0f, 2.0f}) {
        SCOPED_TRACE("UI scale " + std::to_string(scale));
        app::HeadlessGui gui(wb, 1280, 720, scale);
        app::UiState& ui = gui.ui();
        ui = app::UiState{};
        const app::Rect r = showPointCloud(gui, wb);
        ASSERT_GT(r.width(), 100.0f);
        // the middle of the view, where the mesh is (the inspector camera frames it)
        const float x = r.x0 + 0.5f * r.width(), y = r.y0 + 0.5f * r.height();
        testsupport::clickAt(gui, x, y);
        const int picked = ui.pointCloud.picked;
        const auto& cloud = wb.scene().cloud().points;
        ASSERT_GE(picked, 0);
        ASSERT_LT(size_t(picked), cloud.size());
        const auto& p = cloud[size_t(picked)].p;
        const glm::vec4 c = ui.shared.inspect.camera.projection() *
                            ui.shared.inspect.camera.view() * glm::vec4(p[0], p[1], p[2], 1.0f);
        const float sx = r.x0 + (c.x / c.w * 0.5f + 0.5f) * r.width();
        const float sy = r.y0 + (0.5f - c.y / c.w * 0.5f) * r.height();
        EXPECT_LT(std::hypot(sx - x, sy - y), 8.0f) << sx << "," << sy << " for " << x << "," << y;
    }
}

// The picked point is ringed in the view where the camera projects it, yellow while it faces
// the camera; after an orbit to the far side the ring follows the point and turns grey (the
// point faces away, seen through the mesh). Read from the frame's pixels.
TEST(Interactions, ThePickedPointIsRingedAndTheRingFollowsAnOrbit) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("pickring", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    testsupport::useSmallScene(wb.scene().settings());
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    const app::Rect r = showPointCloud(gui, wb);
    ASSERT_GT(r.width(), 100.0f);
    EXPECT_LT(ui.pointCloud.pickedMarker.x, 0.0f) << "a ring before any pick";
    const float x = r.x0 + 0.5f * r.width(), y = r.y0 + 0.5f * r.height();
    testsupport::clickAt(gui, x, y);
    ASSERT_GE(ui.pointCloud.picked, 0);
    gui.frame();
    // pixels of the ring's colour in the 20 × 20 box around `at`
    const auto ringPixels = [&](glm::vec2 at, bool yellow) {
        const std::vector<unsigned char> px = gui.pixels();
        int n = 0;
        for (int j = int(at.y) - 10; j <= int(at.y) + 10; ++j)
            for (int i = int(at.x) - 10; i <= int(at.x) + 10; ++i) {
                if (i < 0 || j < 0 || i >= gui.width() || j >= gui.height()) continue;
                const unsigned char* c = &px[(size_t(j) * size_t(gui.width()) + size_t(i)) * 4];
                n += yellow ? (c[0] > 230 && c[1] > 200 && c[2] < 60)
                            : (std::abs(int(c[0]) - 170) < 8 && std::abs(int(c[1]) - 170) < 8 &&
                               std::abs(int(c[2]) - 170) < 8);
            }
        return n;
    };
    const glm::vec2 front = ui.pointCloud.pickedMarker;
    EXPECT_LT(std::hypot(front.x - x, front.y - y), 8.0f);
    EXPECT_TRUE(ui.pointCloud.pickedFacing);
    EXPECT_GT(ringPixels(front, true), 20);
    // half way round: the same point, now on the far side
    ui.shared.inspect.camera.yaw += 3.14159265f;
    gui.frame();
    gui.frame();
    const glm::vec2 back = ui.pointCloud.pickedMarker;
    ASSERT_GE(back.x, 0.0f) << "the point left the view";
    EXPECT_FALSE(ui.pointCloud.pickedFacing);
    EXPECT_GT(std::hypot(back.x - front.x, back.y - front.y), 3.0f) << "the ring did not move";
    EXPECT_GT(ringPixels(back, false), 20);
    EXPECT_EQ(ringPixels(back, true), 0);
    EXPECT_TRUE(wb.errors().empty());
}

// The pick is the point drawn at the pixel: of two points whose splats cover it, the one nearer
// the camera (the depth test draws it on top), even where the far one projects closer to the
// click (a click on the bunny picked a point on its far side, facing away); with no splat over
// the pixel, the nearest projection within reach; none beyond it.
TEST(Interactions, APickIsThePointDrawnAtThePixel) {
    const glm::mat4 viewProj = glm::perspective(0.7f, 1.0f, 0.1f, 10.0f) *
                               glm::lookAt(glm::vec3(0, 0, 3), glm::vec3(0), glm::vec3(0, 1, 0));
    const int side = 400;
    const auto project = [&](glm::vec3 p) {
        const glm::vec4 c = viewProj * glm::vec4(p, 1.0f);
        return glm::vec2((c.x / c.w * 0.5f + 0.5f) * side, (0.5f - c.y / c.w * 0.5f) * side);
    };
    const glm::vec3 back(0.0f, 0.0f, -0.5f); // projects onto the click exactly
    const glm::vec2 at = project(back);
    // a point nearer the camera, 1.4 pixels to the right of the click on screen
    const float shift = 1.4f * 2.0f * 2.5f * std::tan(0.35f) / float(side);
    const glm::vec3 front(shift, 0.0f, 0.5f);
    ASSERT_NEAR(project(front).x - at.x, 1.4f, 0.05f);
    const std::vector<glm::vec3> both{back, front};
    EXPECT_EQ(app::pickPoint(both, viewProj, side, side, at.x, at.y, 3.0f), 1);
    // a splat of one pixel does not reach 1.4 pixels: the nearest projection
    EXPECT_EQ(app::pickPoint(both, viewProj, side, side, at.x, at.y, 1.0f), 0);
    // nothing within reach
    EXPECT_EQ(app::pickPoint(both, viewProj, side, side, at.x + 40, at.y, 3.0f), -1);
    EXPECT_EQ(app::pickPoint(both, viewProj, side, side, at.x + 5, at.y, 3.0f, 6.0f), 1);
}
