// The lit-sphere stage in the app: both renderings of the same setup progress, restart on a
// material change, and the panel draws (tabs, difference view, pixel readout).
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "../support/image_agreement.h"
#include "capture/capture.h"
#include "core/statistics.h"
#include "gui/gui.h"
#include "pipeline/image_display.h"

#include <cmath>
#include <cstdlib>

TEST(LitSphereStage, PathTracedAndIntegratedImagesOfTheSameSetup) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("sphere", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    auto& s = wb.litSphereSettings();
    s.enabled = true;
    s.size = 24;
    s.radiusMm = 5;
    s.pathSpp = 4;
    s.integratedSpp = 512;
    wb.update();
    wb.finishLitSpheres();
    EXPECT_TRUE(wb.litSpheres().problem().empty()) << wb.litSpheres().problem();
    auto a = wb.litSpheres().pathTracer().image(), b = wb.litSpheres().integratedImage();
    ASSERT_EQ(a.width, 24);
    ASSERT_EQ(b.width, 24);
    EXPECT_EQ(wb.litSpheres().pathTracer().sppDone(), 4);
    EXPECT_EQ(wb.litSpheres().integratedSppDone(), 512u);
    // the centre pixel is lit in both, a corner (off the sphere) is 0 in both
    auto pa = app::pixelAt(a, 12, 12), pb = app::pixelAt(b, 12, 12);
    EXPECT_GT(pa.mean[0], 0.0f);
    EXPECT_GT(pb.mean[0], 0.0f);
    EXPECT_EQ(app::pixelAt(a, 0, 0).mean[0], 0.0f);
    EXPECT_EQ(app::pixelAt(b, 0, 0).mean[0], 0.0f);
    // the dipole and the path tracer see the same scene: red exitance of the same magnitude
    EXPECT_LT(std::abs(std::log(pa.mean[0] / pb.mean[0])), std::log(3.0));

    // a material change restarts both
    wb.applyPreset(wb.shared(), "Marble");
    wb.update();
    wb.finishLitSpheres();
    EXPECT_EQ(wb.litSpheres().integratedSppDone(), 512u);
    EXPECT_NE(app::pixelAt(wb.litSpheres().integratedImage(), 12, 12).mean[0], pb.mean[0]);

    // the panel draws every view without errors
    app::HeadlessGui gui(wb, 1280, 860);
    gui.ui().shared.show(app::PanelId::LitSpheres);
    gui.ui().litSpheres.pickX = 12;
    gui.ui().litSpheres.pickY = 12;
    gui.frame(); // the tab bar's first frame
    for (int v = 0; v < 4; ++v) {
        gui.ui().litSpheres.view = static_cast<app::SphereView>(v);
        gui.frame();
        EXPECT_NE(testsupport::panelWindow(app::PanelId::LitSpheres), nullptr) << v;
    }
    EXPECT_TRUE(wb.errors().empty());
    std::filesystem::remove_all(root);
}

TEST(LitSphereStage, GpuPathTracerAgreesWithTheCpuOne) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("spheregpu", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    auto& s = wb.litSphereSettings();
    s.enabled = true;
    s.size = 12;
    s.radiusMm = 4;
    s.pathSpp = 64;
    s.integratedSpp = 16;
    s.gpu = true;
    wb.update(); // one frame: a slice
    wb.finishLitSpheres();
    EXPECT_TRUE(wb.errors().empty());
    const auto gpu = wb.litSpheres().pathTracer().image();
    EXPECT_EQ(wb.litSpheres().pathTracer().sppDone(), 64);
    s.gpu = false;
    wb.finishLitSpheres();
    const auto cpu = wb.litSpheres().pathTracer().image();
    ASSERT_EQ(gpu.width, cpu.width);
    // per-pixel z-test with a Bonferroni limit over the covered pixels and channels
    int tested = 0;
    double worst = 0;
    for (size_t i = 0; i < cpu.mean.size(); ++i) {
        const double se = std::sqrt(double(cpu.variance[i]) + double(gpu.variance[i]));
        if (!(se > 0)) continue;
        ++tested;
        worst = std::max(worst, std::abs(double(cpu.mean[i]) - double(gpu.mean[i])) / se);
    }
    EXPECT_GT(tested, 100);
    EXPECT_LT(worst, core::normalUpperQuantile(1e-3 / (2.0 * tested)));
    std::filesystem::remove_all(root);
}

// The panel's switch to disk importance sampling: the same sphere, light and camera, an image
// that agrees with the uniform GPU pass (per-pixel z, Bonferroni, over the pixels of at least
// 1e-3 of the brightest: integrate.h says why the far tail is left out) and has far less variance
// at fewer samples; with a mesh both samplings integrate over the mesh.
TEST(LitSphereStage, DiskImportanceSamplingIsSwitchableAndAgreesWithUniform) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("sphere_disk", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    auto& s = wb.litSphereSettings();
    s.enabled = true;
    s.size = 20;
    s.radiusMm = 8;
    s.pathSpp = 1;
    s.integratedSpp = 32768;
    wb.update();
    wb.finishLitSpheres();
    const pathtrace::Image uni = wb.litSpheres().integratedImage();
    s.sampling = integrate::Sampling::Disk;
    s.axes = sampling::AxisScheme::Pbrt;
    s.integratedSpp = 2048;
    wb.update();
    wb.finishLitSpheres();
    EXPECT_TRUE(wb.litSpheres().problem().empty()) << wb.litSpheres().problem();
    EXPECT_EQ(wb.litSpheres().integratedSppDone(), 2048u);
    const pathtrace::Image disk = wb.litSpheres().integratedImage();
    ASSERT_EQ(disk.mean.size(), uni.mean.size());
    const testsupport::Agreement g = testsupport::agreePerPixel(disk, uni);
    ASSERT_GT(g.tested, 300u);
    EXPECT_LT(g.maxZ, g.threshold);
    double varDisk = 0, varUni = 0; // per-sample variances over the lit pixels
    for (size_t i = 0; i < uni.mean.size(); ++i)
        if (uni.mean[i] > 0) {
            varDisk += double(disk.variance[i]) * 2048;
            varUni += double(uni.variance[i]) * 32768;
        }
    EXPECT_GT(varUni / varDisk, 10.0);
    // a mesh: the integration runs over it, whichever sampling
    s.mesh = "third_party/bunny/bunny.obj";
    s.integratedSpp = 16;
    for (integrate::Sampling m : {integrate::Sampling::Uniform, integrate::Sampling::Disk}) {
        s.sampling = m;
        wb.update();
        wb.finishLitSpheres();
        EXPECT_TRUE(wb.litSpheres().problem().empty()) << wb.litSpheres().problem();
        const pathtrace::Image b = wb.litSpheres().integratedImage();
        EXPECT_EQ(app::pixelAt(b, 0, 0).mean[0], 0.0f);
        double sum = 0;
        for (float v : b.mean)
            sum += v;
        EXPECT_GT(sum, 0.0);
    }
    // a model whose own sampler fails its checks: an Errors entry naming the file and the
    // section's line, and the last good integration stays (same image, no more samples)
    const pathtrace::Image good = wb.litSpheres().integratedImage();
    const uint64_t goodSpp = wb.litSpheres().integratedSppDone();
    const std::string dipole = testsupport::readText(root / "materials" / "dipole.bssrdf");
    const std::string withSampler = dipole +
                                    "\n::begin sample\n"
                                    "float MaxRadius(int channel) { return 10.0; }\n"
                                    "float PdfRadius(float r, int channel) { return 1.0; }\n"
                                    "float SampleRadius(float xi, int channel) {\n"
                                    "    return 10.0*xi;\n}\n::end sample\n";
    core::writeFile(root / "materials" / "dipole.bssrdf", withSampler);
    wb.reloadAll();
    wb.update();
    wb.update();
    const std::string where = "materials/dipole.bssrdf:" +
                              std::to_string(testsupport::lineOf(withSampler, "::begin sample"));
    EXPECT_NE(wb.litSpheres().problem().find(where + ": channel R: PdfRadius is the density of the "
                                                     "radius"),
              std::string::npos)
        << wb.litSpheres().problem();
    bool listed = false;
    for (const app::ErrorItem& e : wb.errors())
        listed |= e.text.find(where) != std::string::npos;
    EXPECT_TRUE(listed);
    EXPECT_EQ(wb.litSpheres().integratedSppDone(), goodSpp);
    EXPECT_EQ(wb.litSpheres().integratedImage().mean, good.mean);
    // a model whose profile cannot be sampled is a problem of the stage, not a crash
    core::writeFile(root / "materials" / "dipole.bssrdf",
                    "analytic radial no_wi no_wo\n::begin shader\n"
                    "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n    return vec3(1.0);\n}\n"
                    "::end shader\n");
    wb.reloadAll();
    wb.update();
    EXPECT_NE(wb.litSpheres().problem().find("converge"), std::string::npos)
        << wb.litSpheres().problem();
    std::filesystem::remove_all(root);
}

// The integration's sampling, or the model's own parameter values, change only the integrated
// image: the path tracer sees the medium and the scene, and keeps its run (it restarted, and
// its paths/s changed, on a switch from uniform to disk sampling). The medium restarts both.
TEST(LitSphereStage, TheIntegrationsSettingsLeaveThePathTracerRunning) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("sphere_keys", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    auto& s = wb.litSphereSettings();
    s.enabled = true;
    s.size = 16;
    s.pathSpp = 2;
    s.integratedSpp = 64;
    s.sampling = integrate::Sampling::Uniform;
    wb.update();
    const long long runs = wb.litSpheres().pathTracer().runs();
    ASSERT_GE(runs, 1);
    s.sampling = integrate::Sampling::Disk;
    wb.update();
    EXPECT_EQ(wb.litSpheres().pathTracer().runs(), runs) << "sampling restarted the path tracer";
    wb.library().find("materials/dipole.bssrdf")->values["Multiplier"] = {2.0f, 0, 0};
    wb.update();
    EXPECT_EQ(wb.litSpheres().pathTracer().runs(), runs) << "a model value restarted it";
    wb.finishLitSpheres(); // a capture's deterministic run: both restart
    EXPECT_EQ(wb.litSpheres().pathTracer().runs(), runs + 1);
    EXPECT_EQ(wb.litSpheres().integratedSppDone(), 64u);
    wb.applyPreset(wb.shared(), "Marble"); // the medium: the path tracer restarts
    wb.update();
    EXPECT_EQ(wb.litSpheres().pathTracer().runs(), runs + 2);
    std::filesystem::remove_all(root);
}

// The panel states each image's relative standard error, and the difference view switches to
// the z-score map with a click.
TEST(LitSpherePanel, StatesTheNoiseAndShowsTheDifferenceInStandardErrors) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("sphere_panel_z", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    auto& s = wb.litSphereSettings();
    s.enabled = true;
    s.size = 16;
    s.pathSpp = 4;
    s.integratedSpp = 64;
    app::HeadlessGui gui(wb, 1280, 720);
    gui.ui().shared.show(app::PanelId::LitSpheres);
    gui.ui().litSpheres.view = app::SphereView::Difference;
    gui.frame();
    wb.finishLitSpheres();
    gui.frame();
    gui.frame();
    app::LitSpherePanelState& ps = gui.ui().litSpheres;
    const pathtrace::Image a = wb.litSpheres().pathTracer().image(),
                           b = wb.litSpheres().integratedImage();
    EXPECT_DOUBLE_EQ(ps.relSe[0], app::relativeStandardError(a));
    EXPECT_DOUBLE_EQ(ps.relSe[1], app::relativeStandardError(b));
    EXPECT_GT(ps.relSe[0], 0.0); // a few paths per pixel: noisy
    ASSERT_GT(ps.zRadio.width(), 5.0f);
    EXPECT_FALSE(ps.diffZ);
    testsupport::click(gui, ps.zRadio);
    EXPECT_TRUE(ps.diffZ);
    if (const char* dir = std::getenv("BW_PANEL_PNG_DIR"))
        gl::writePng((std::filesystem::path(dir) / "LitSpheres-z-1280x720.png").string(), 1280, 720,
                     gui.pixels());
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    std::filesystem::remove_all(root);
}
