// The Render panel's texture-space renderer (texspace_stage.h) on the default scene (the bunny,
// no UVs: the atlas): its image covers the frame's pixels and has the point-cloud renderer's
// radiance (same light, Fresnel terms, 1/π and scale: the sums over the lit pixels agree up to
// the two discretisations); bad settings and meshes are problems in Errors while the last good
// image stays; overlapping UVs fall back to the atlas with a note; every stage view of the panel
// draws.
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "gui/gui.h"
#include "pipeline/pencil_series.h"
#include "pipeline/texspace_images.h"
#include "pipeline/workbench.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace {

bool listed(app::Workbench& wb, const std::string& text) {
    for (const auto& e : wb.errors())
        if (e.text.find(text) != std::string::npos) return true;
    return false;
}

} // namespace

TEST(TextureSpaceRender, HasThePointCloudRadianceAndKeepsTheLastImageOnBadInput) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("texspace_app", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    app::SceneSettings& s = wb.scene().settings();
    testsupport::useSmallScene(s);
    s.points.points = 20000;
    s.render.bruteForce = true;
    wb.update();
    wb.finishScene();
    ASSERT_TRUE(wb.scene().hasFrame());
    const render::Readback rb = wb.scene().readback();

    app::TextureSpaceSettings& ts = wb.textureSpaceSettings();
    ts.sampling.textureSize = 512;
    ts.sampling.samples = 2500;
    ts.sampling.sampleSets = 16;
    wb.finishTextureSpace();
    const texspace::Pipeline* p = wb.textureSpace().pipeline();
    ASSERT_NE(p, nullptr);
    EXPECT_FALSE(p->parameterization().fromMesh);
    EXPECT_NE(wb.textureSpace().note().find("no texture coordinates"), std::string::npos)
        << wb.textureSpace().note();
    const litsphere::Image img = wb.textureSpace().radiance();
    ASSERT_EQ(img.width, rb.width);
    ASSERT_EQ(img.height, rb.height);
    double sumTs = 0, sumPc = 0;
    for (size_t i = 0; i < img.mean.size(); ++i) {
        if (rb.position[i / 3].w < 0.5f) {
            ASSERT_EQ(img.mean[i], 0.0f) << "a pixel off the mesh";
            continue;
        }
        sumTs += img.mean[i];
        sumPc += rb.hdr[i / 3][int(i % 3)];
    }
    // Conventions: a missing 1/π, Fresnel factor, E0, area ratio or mm scale would be off by
    // 1.3× or more; the rasterised texels, the 20 000 points and the set noise differ by a few
    // per cent.
    const double ratio = sumTs / sumPc;
    std::printf("texture space / point-cloud brute force, summed over lit pixels: %.4f\n", ratio);
    EXPECT_GT(ratio, 0.93);
    EXPECT_LT(ratio, 1.07);
    EXPECT_TRUE(wb.textureSpace().problems().empty());

    // the hybrid: the same radiance (local part by the light-view filter, global by the sets),
    // with a smaller standard error than texture space alone at the same N and sets
    double seTs = 0, seHy = 0;
    for (size_t i = 0; i < img.variance.size(); ++i)
        seTs += img.variance[i];
    ts.sampling.hybrid = true;
    wb.finishTextureSpace();
    const litsphere::Image hy = wb.textureSpace().radiance();
    double sumHy = 0;
    for (size_t i = 0; i < hy.mean.size(); ++i) {
        seHy += hy.variance[i];
        if (rb.position[i / 3].w > 0.5f) sumHy += hy.mean[i];
    }
    std::printf("hybrid / point-cloud brute force: %.4f; summed variance hybrid / texture space "
                "%.3f; R_p %.3f %.3f %.3f mm\n",
                sumHy / sumPc, seHy / seTs, wb.textureSpace().pipeline()->hybridRp().x,
                wb.textureSpace().pipeline()->hybridRp().y,
                wb.textureSpace().pipeline()->hybridRp().z);
    EXPECT_GT(sumHy / sumPc, 0.93);
    EXPECT_LT(sumHy / sumPc, 1.07);
    EXPECT_LT(seHy, 0.5 * seTs);
    EXPECT_FALSE(wb.textureSpace().pipeline()->localRadiance().mean.empty());
    // the hybrid's local term needs the directional light: another mode is a problem
    s.light.mode = irradiance::LightMode::Ibl;
    wb.update();
    wb.finishScene();
    EXPECT_THROW(wb.finishTextureSpace(), core::Error);
    EXPECT_TRUE(listed(wb, "directional light"));
    EXPECT_TRUE(listed(wb, "the light is image based (IBL)")); // which light it is
    // texture space itself sees every light of the point-cloud pipeline: under the IBL its
    // image sums to the point-cloud render's as under the directional light
    ts.sampling.hybrid = false;
    wb.finishTextureSpace();
    {
        const render::Readback ibl = wb.scene().readback();
        const litsphere::Image t = wb.textureSpace().radiance();
        double a = 0, b = 0;
        for (size_t i = 0; i < t.mean.size(); ++i)
            if (ibl.position[i / 3].w > 0.5f) {
                a += t.mean[i];
                b += ibl.hdr[i / 3][int(i % 3)];
            }
        std::printf("IBL: texture space / point-cloud brute force %.4f\n", a / b);
        EXPECT_GT(a / b, 0.93);
        EXPECT_LT(a / b, 1.07);
    }
    s.light.mode = irradiance::LightMode::Directional;
    wb.update();
    wb.finishScene();
    wb.finishTextureSpace();

    // bad settings: a problem naming the setting, the last good image stays
    ts.sampling.samples = 0;
    EXPECT_THROW(wb.finishTextureSpace(), core::Error);
    EXPECT_TRUE(listed(wb, "samples N")) << "N = 0 is listed in Errors";
    ts.sampling.samples = 2500;
    ts.sampling.textureSize = 4096;
    ts.enabled = true; // as while the Render panel shows it
    wb.update();
    EXPECT_TRUE(listed(wb, "texture_size"));
    EXPECT_EQ(wb.textureSpace().radiance().mean, img.mean);
    ts.sampling.textureSize = 512;
    wb.update();
    EXPECT_FALSE(listed(wb, "texture_size"));

    // the stage images have the texture's size and are not blank
    for (const app::Rgba8Image& im : {app::eprimeImage(*p), app::cdfLevelImage(p->cdf(), 3),
                                      app::atlasImage(*p), app::samplesImage(*p, p->lastSet())}) {
        ASSERT_GT(im.width, 0);
        size_t lit = 0;
        for (size_t k = 0; k < im.rgba.size(); k += 4)
            lit += im.rgba[k] + im.rgba[k + 1] + im.rgba[k + 2] > 150;
        EXPECT_GT(lit, size_t(im.width) * size_t(im.height) / 50);
    }
    std::filesystem::remove_all(root);
}

TEST(TextureSpaceRender, OverlappingUvsFallBackToTheAtlasWithANote) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("texspace_box", {"dipole.bssrdf"});
    // a box whose six faces all use [0, 1]²: the UVs overlap
    mesh::writeObj(root / "box.obj", mesh::makeBox(1.0, 0.6, 0.8));
    app::Workbench wb(root, false);
    app::SceneSettings& s = wb.scene().settings();
    testsupport::useSmallScene(s);
    s.meshFile = (root / "box.obj").string();
    wb.update();
    wb.finishScene();
    app::TextureSpaceSettings& ts = wb.textureSpaceSettings();
    ts.sampling.textureSize = 128;
    ts.sampling.samples = 64;
    ts.sampling.sampleSets = 2;
    wb.finishTextureSpace();
    EXPECT_FALSE(wb.textureSpace().pipeline()->parameterization().fromMesh);
    EXPECT_NE(wb.textureSpace().note().find("overlap"), std::string::npos)
        << wb.textureSpace().note();
    EXPECT_EQ(wb.textureSpace().radiance().samples, 2u);
    std::filesystem::remove_all(root);
}

TEST(TextureSpaceRender, TheRenderPanelShowsItAndEveryStage) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("texspace_gui", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    testsupport::useSmallScene(wb.scene().settings());
    app::HeadlessGui gui(wb, 1280, 860);
    gui.ui().shared.show(app::PanelId::Render);
    gui.ui().render.mode = app::RenderMode::TextureSpace;
    gui.ui().render.tsSamplesOnMesh = true;
    wb.textureSpaceSettings().sampling.textureSize = 256;
    wb.textureSpaceSettings().sampling.sampleSets = 4;
    const texspace::Pipeline* p = nullptr;
    for (int i = 0; i < 400 && !(p && p->done() && p->setsDone() == 4); ++i) {
        gui.frame();
        if (wb.scene().generating()) wb.finishScene();
        p = wb.textureSpace().pipeline();
    }
    EXPECT_TRUE(wb.textureSpaceSettings().enabled);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(p->setsDone(), 4);
    // a set's sum over its N texels per pixel ran in short dispatches, as the scene's frames do,
    // so that no UI frame waited for a whole sum
    const render::Frame& last = p->renderer().currentFrame();
    EXPECT_EQ(last.iterationsPerDispatch, app::SceneStage::kInteractiveIterations);
    EXPECT_GE(size_t(last.dispatches),
              p->lastSet().texel.size() / app::SceneStage::kInteractiveIterations); // distinct
    for (auto v : {app::TextureSpaceView::Render, app::TextureSpaceView::Irradiance,
                   app::TextureSpaceView::CdfLevel, app::TextureSpaceView::Samples,
                   app::TextureSpaceView::Atlas}) {
        gui.ui().render.tsView = v;
        gui.frame();
        EXPECT_NE(testsupport::panelWindow(app::PanelId::Render), nullptr);
        if (const char* dir = std::getenv("BW_TS_PNG_DIR"))
            gl::writePng(std::string(dir) + "/view" + std::to_string(int(v)) + ".png", gui.width(),
                         gui.height(), gui.pixels());
        if (v != app::TextureSpaceView::Render) continue;
        // the render over the frame: the estimate (probe, export), misses in the background
        const app::RenderPanelState::ShownImage& shown = gui.ui().render.shown;
        EXPECT_EQ(shown.what, "texture-space render");
        ASSERT_TRUE(shown.hdr);
        EXPECT_EQ(shown.hdr->mean, wb.textureSpace().radiance().mean);
        const render::Readback rb = wb.scene().readback();
        ASSERT_EQ(shown.rgba.size(), 4 * rb.position.size());
        const glm::vec3 bg = wb.scene().settings().render.background;
        for (size_t q = 0; q < rb.position.size(); ++q) {
            if (rb.position[q].w < 0.5f) {
                ASSERT_EQ(shown.rgba[4 * q + 2], uint8_t(bg.z * 255 + 0.5f));
            }
        }
    }
    EXPECT_TRUE(wb.errors().empty());
    std::filesystem::remove_all(root);
}

// The pencil plot marks R_p of the hybrid for the selected model: the soloed model's three
// channels, from the plotted profile; the hybrid renderer finds the same R_p from its own
// profile table (another grid of radii on another GPU pass).
TEST(TextureSpaceRender, PencilPlotMarksRpOfTheSelectedModel) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("texspace_rp", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    wb.plotSettings().solo = "materials/dipole.bssrdf";
    testsupport::useSmallScene(wb.scene().settings());
    wb.update();
    wb.finishScene();
    const std::vector<app::RpMarker> marks = hybridRpMarkers(wb);
    ASSERT_EQ(marks.size(), 3u);
    app::TextureSpaceSettings& ts = wb.textureSpaceSettings();
    ts.sampling.textureSize = 64;
    ts.sampling.samples = 16;
    ts.sampling.sampleSets = 1;
    ts.sampling.hybrid = true;
    wb.finishTextureSpace();
    const glm::vec3 rp = wb.textureSpace().pipeline()->hybridRp();
    for (int c = 0; c < 3; ++c) {
        std::printf("R_p channel %d: pencil plot %.4f mm, render table %.4f mm\n", c,
                    marks[size_t(c)].rMm, rp[c]);
        EXPECT_NEAR(marks[size_t(c)].rMm / rp[c], 1.0, 0.01);
    }
    app::HeadlessGui gui(wb, 1280, 860);
    gui.ui().shared.show(app::PanelId::Pencil);
    gui.frame();
    gui.frame();
    EXPECT_NE(testsupport::panelWindow(app::PanelId::Pencil), nullptr);
    if (const char* png = std::getenv("BW_RP_PNG"))
        gl::writePng(png, gui.width(), gui.height(), gui.pixels());
    std::filesystem::remove_all(root);
}

// The hybrid under the IBL: the Render panel names the light it cannot use and says that what
// it shows is the hierarchical render (nothing is in progress); once the stage has an image, a
// bad setting keeps it, and the panel says the image shown was made before the problem.
TEST(TextureSpaceRender, TheRenderPanelSaysWhatItShowsWhenTheHybridCannotRun) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("texspace_gui_stopped", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    testsupport::useSmallScene(wb.scene().settings());
    app::HeadlessGui gui(wb, 1280, 860);
    gui.ui().shared.show(app::PanelId::Render);
    gui.ui().render.mode = app::RenderMode::TextureSpace;
    wb.textureSpaceSettings().sampling.hybrid = true;
    wb.textureSpaceSettings().sampling.textureSize = 256;
    wb.textureSpaceSettings().sampling.sampleSets = 2;
    wb.scene().settings().light.mode = irradiance::LightMode::Ibl;
    std::string text;
    for (int i = 0; i < 200 && wb.textureSpace().problems().empty(); ++i) {
        gui.frame();
        if (wb.scene().generating()) wb.finishScene();
    }
    ASSERT_FALSE(wb.textureSpace().problems().empty());
    text = testsupport::panelText(gui, app::PanelId::Render);
    EXPECT_NE(text.find("the light is image based (IBL)"), std::string::npos) << text;
    EXPECT_NE(text.find("no texture-space image of this view (the problem above); shown: the "
                        "hierarchical render"),
              std::string::npos)
        << text;
    EXPECT_EQ(text.find("in progress"), std::string::npos) << text;

    // the directional light: the hybrid runs, its image is shown
    wb.scene().settings().light.mode = irradiance::LightMode::Directional;
    const texspace::Pipeline* p = nullptr;
    for (int i = 0; i < 400 && !(p && p->done() && p->setsDone() == 2); ++i) {
        gui.frame();
        if (wb.scene().generating()) wb.finishScene();
        p = wb.textureSpace().pipeline();
    }
    ASSERT_TRUE(p && p->setsDone() == 2);
    EXPECT_TRUE(wb.textureSpace().problems().empty());
    text = testsupport::panelText(gui, app::PanelId::Render);
    EXPECT_EQ(text.find("the problem above"), std::string::npos) << text;

    // a bad setting: the last good image stays and the panel says it predates the problem
    wb.textureSpaceSettings().sampling.samples = 0;
    for (int i = 0; i < 200 && wb.textureSpace().problems().empty(); ++i) {
        gui.frame();
        if (wb.scene().generating()) wb.finishScene();
    }
    ASSERT_FALSE(wb.textureSpace().problems().empty());
    text = testsupport::panelText(gui, app::PanelId::Render);
    EXPECT_NE(text.find("shown: the last texture-space image, made before the problem above"),
              std::string::npos)
        << text;
    std::filesystem::remove_all(root);
}
