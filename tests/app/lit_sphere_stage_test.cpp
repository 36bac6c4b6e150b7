// The lit-sphere stage in the app: both renderings of the same setup progress, restart on a
// material change, and the panel draws (tabs, difference view, pixel readout).
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "capture/capture.h"
#include "core/statistics.h"
#include "gui.h"
#include "image_view.h"

#include <cmath>

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
    EXPECT_TRUE(wb.litSphereProblem().empty()) << wb.litSphereProblem();
    auto a = wb.pathTracedSphere(), b = wb.integratedSphere();
    ASSERT_EQ(a.width, 24);
    ASSERT_EQ(b.width, 24);
    EXPECT_EQ(wb.pathTracer().sppDone(), 4);
    EXPECT_EQ(wb.integratedSppDone(), 512u);
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
    EXPECT_EQ(wb.integratedSppDone(), 512u);
    EXPECT_NE(app::pixelAt(wb.integratedSphere(), 12, 12).mean[0], pb.mean[0]);

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
    const auto gpu = wb.pathTracedSphere();
    EXPECT_EQ(wb.pathTracer().sppDone(), 64);
    s.gpu = false;
    wb.finishLitSpheres();
    const auto cpu = wb.pathTracedSphere();
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
