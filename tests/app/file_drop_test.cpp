// Files dropped on the window (gui/file_drop.h): each kind opens as what it is, with its panel to
// the front and the panel's field showing it; anything else, or a path that is no file, is an
// Errors entry naming it.
#include "../support/gl_fixture.h"
#include "gui/file_drop.h"
#include "gui/gui.h"
#include "pathtrace/mco.h"
#include "pathtrace/pathtrace.h"

#include <gtest/gtest.h>

#include <cstring>

namespace fs = std::filesystem;

TEST(FileDrop, EachKindOpensAsWhatItIsAndItsFieldShowsIt) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("drop", {"dipole.bssrdf"});
    const fs::path elsewhere = root / "elsewhere";
    fs::create_directories(elsewhere);
    const fs::path model = elsewhere / "mine.bssrdf", mesh = elsewhere / "bunny.obj",
                   env = elsewhere / "sky.exr", mco = elsewhere / "sample.mco";
    fs::copy_file(testsupport::sourceRoot() / "materials/better_dipole.bssrdf", model);
    fs::copy_file(testsupport::sourceRoot() / "third_party/bunny/bunny.obj", mesh);
    fs::copy_file(testsupport::sourceRoot() / "materials/env/default_sky.exr", env);
    { // an MCML-format run of the semi-infinite slab (as `slab --out sample.mco` writes)
        pathtrace::SlabSettings s;
        s.paths = 2000;
        s.bins = 20;
        const pathtrace::Medium m;
        core::writeFile(mco, pathtrace::formatMco(pathtrace::mcoFromSlab(
                                 m, s, pathtrace::runSlab(m, s), "sample.mco")));
    }
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 800);
    app::UiState& ui = gui.ui();
    gui.frame();

    app::openDroppedFiles(wb, ui, {model});
    EXPECT_EQ(wb.library().entries().size(), 2u) << "the model opened";
    app::openDroppedFiles(wb, ui, {mesh, env});
    EXPECT_EQ(wb.scene().settings().meshFile, mesh.string());
    EXPECT_EQ(wb.scene().settings().environmentFile, env.string());
    EXPECT_EQ(wb.scene().settings().light.mode, irradiance::LightMode::Ibl)
        << "an environment is for image-based light";
    // the point-cloud and irradiance panels' fields show the dropped files
    for (app::PanelId id : {app::PanelId::PointCloud, app::PanelId::Irradiance}) {
        ui.shared.show(id);
        gui.frame();
        gui.frame();
    }
    EXPECT_STREQ(ui.pointCloud.meshBuffer, mesh.c_str());
    EXPECT_STREQ(ui.irradiance.envBuffer, env.c_str());
    app::openDroppedFiles(wb, ui, {mco});
    ASSERT_TRUE(wb.mcmlReference().has_value());
    EXPECT_EQ(wb.mcmlReference()->name, "sample.mco");
    EXPECT_TRUE(wb.errors().empty());

    const fs::path text = elsewhere / "notes.txt", layers = elsewhere / "three_layers.mco";
    core::writeFile(text, "not a model");
    fs::copy_file(testsupport::sourceRoot() / "tests/data/mcml/sample_kaseykwong.mco", layers);
    app::openDroppedFiles(wb, ui, {text, elsewhere, elsewhere / "gone.bssrdf", layers});
    const auto errors = wb.errors();
    ASSERT_EQ(errors.size(), 4u);
    EXPECT_EQ(errors[0].text, "dropped " + text.string() +
                                  ": not a file the workbench opens (a .bssrdf model, an .obj "
                                  "mesh, an .exr environment or an .mco MCML output)");
    EXPECT_EQ(errors[1].text, "dropped " + elsewhere.string() + ": not a file");
    EXPECT_EQ(errors[2].text, "dropped " + (elsewhere / "gone.bssrdf").string() + ": not a file");
    EXPECT_EQ(errors[3].text, "open MCML reference: " + layers.string() +
                                  ": a reference profile needs one layer (the semi-infinite "
                                  "slab); the file has 3");
    EXPECT_EQ(wb.scene().settings().meshFile, mesh.string()) << "the last good state stays";
    EXPECT_EQ(wb.mcmlReference()->name, "sample.mco");
}

// A path field follows its setting when the setting changes elsewhere (a restored session, a
// replayed capture), and a commit in the field sets the setting.
TEST(FileDrop, APathFieldShowsItsSettingWhenItChangesElsewhere) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("pathfield", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 800);
    app::UiState& ui = gui.ui();
    ui.shared.show(app::PanelId::LitSpheres);
    gui.frame();
    EXPECT_STREQ(ui.litSpheres.meshBuffer, "");
    wb.litSphereSettings().mesh = "third_party/bunny/bunny.obj";
    gui.frame();
    EXPECT_STREQ(ui.litSpheres.meshBuffer, "third_party/bunny/bunny.obj");
    // an edit in progress is not overwritten while the setting stays
    std::strcpy(ui.litSpheres.meshBuffer, "third_party/bunny/bun");
    gui.frame();
    EXPECT_STREQ(ui.litSpheres.meshBuffer, "third_party/bunny/bun");
    wb.litSphereSettings().mesh.clear();
    gui.frame();
    EXPECT_STREQ(ui.litSpheres.meshBuffer, "");
}
