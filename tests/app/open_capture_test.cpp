// A capture's state opened in the window (captures/open_capture.h, `gui --capture`,
// `screenshot --capture`, the Captures panel's "Open in a window"): the recorded parameters,
// settings and traced pixel; a model edited or gone since opened beside from its recorded text;
// bad captures and arguments as clear messages.
#include "../support/cli_runner.h"
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "capture/capture.h"
#include "captures/manifest.h"
#include "captures/open_capture.h"
#include "captures/settings_json.h"
#include "core/core.h"
#include "gui/gui.h"
#include "gui/panels/panels.h"
#include "pipeline/pencil_series.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>

namespace {
namespace fs = std::filesystem;
using nlohmann::json;

json manifestJson(const fs::path& dir) {
    return json::parse(core::readFile(dir / capture::kManifestFileName));
}

// Every value `recorded` holds is in `now` (which may hold settings added since).
void expectRecordedIn(const json& recorded, const json& now, const std::string& path) {
    if (recorded.is_object()) {
        ASSERT_TRUE(now.is_object()) << path;
        for (auto it = recorded.begin(); it != recorded.end(); ++it) {
            ASSERT_TRUE(now.contains(it.key())) << path << "." << it.key();
            expectRecordedIn(*it, now[it.key()], path + "." + it.key());
        }
    } else {
        EXPECT_EQ(recorded, now) << path;
    }
}

std::string errorsText(const app::Workbench& wb) {
    std::string all;
    for (const auto& e : wb.errors())
        all += e.text + "\n";
    return all;
}

const capture::Table* tableOf(const app::CaptureEntries& c, const std::string& stage) {
    for (const auto& e : c.entries)
        if (e.stage == stage) return &e.table;
    return nullptr;
}

} // namespace

// The scene capture opens with its parameters and settings as recorded, the Render panel in
// front and its traced pixel traced again in the Traversal debugger.
TEST(OpenCapture, ShowsTheRecordedStateAndTracesItsPixel) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("opencap", {"dipole.bssrdf"});
    const fs::path dir = testsupport::copyCapture(root, "dipole_bunny_scene", "scene");
    EXPECT_EQ(app::findCapture(root, "scene"), root / "captures" / "scene");
    EXPECT_EQ(app::findCapture(root, dir.string()), dir); // a folder anywhere
    EXPECT_EQ(app::findCapture(root, "scene/"),
              root / "captures" / "scene"); // as a shell completes
    EXPECT_EQ(app::findCapture(root, dir.string() + "/"), dir);
    app::OpenedCapture oc = app::openCapture(root, dir, false);
    ASSERT_TRUE(oc.wb);
    app::Workbench& wb = *oc.wb;
    const json m = manifestJson(dir);
    EXPECT_EQ(oc.name, m["name"]);
    EXPECT_EQ(app::paramsJson(wb), m["params"]);
    const json settings = app::settingsJson(wb, oc.traceX, oc.traceY);
    for (auto it = m["settings"].begin(); it != m["settings"].end(); ++it)
        if (it.key() != "seed") expectRecordedIn(*it, settings[it.key()], "settings." + it.key());
    ASSERT_EQ(m["settings"]["scene"]["trace_pixel"], json::array({oc.traceX, oc.traceY}));
    ASSERT_GE(oc.traceX, 0);
    EXPECT_TRUE(wb.errors().empty()) << errorsText(wb);
    const std::vector<std::string> about = app::describeCapture(root, dir);
    const std::string traced =
        "traced pixel (" + std::to_string(oc.traceX) + ", " + std::to_string(oc.traceY) + ")";
    EXPECT_NE(std::find(about.begin(), about.end(), traced), about.end()) << traced;

    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    app::showCapturedState(wb, ui, oc.name, oc.traceX, oc.traceY);
    core::Stopwatch clock;
    while (!ui.shared.inspect.debug && clock.ms() < 120000) {
        gui.frame();
        if (wb.scene().settings().enabled) wb.finishScene();
    }
    ASSERT_TRUE(ui.shared.inspect.debug) << ui.shared.inspect.debugProblem;
    EXPECT_EQ(ui.shared.inspect.debug->x, oc.traceX);
    EXPECT_EQ(ui.shared.inspect.debug->y, oc.traceY);
    gui.frame();
    gui.frame();
    EXPECT_NE(testsupport::panelWindow(app::PanelId::Render), nullptr);
    EXPECT_NE(testsupport::panelWindow(app::PanelId::Traversal), nullptr);
    EXPECT_NE(ui.shared.status.find(oc.name), std::string::npos) << ui.shared.status;
    EXPECT_TRUE(wb.errors().empty()) << errorsText(wb);
    fs::remove_all(root);
}

// Each capture opens on the stage it recorded: the lit spheres side by side, the BSSRDF slice,
// else the pencil plot.
TEST(OpenCapture, OpensOnTheStageItRecorded) {
    testsupport::context();
    auto root =
        testsupport::makeProjectRoot("opencapstage", {"dipole.bssrdf", "better_dipole.bssrdf"});
    const std::pair<const char*, app::PanelId> cases[] = {
        {"dipole_skin1_spheres", app::PanelId::LitSpheres},
        {"dipoles_slice_60deg", app::PanelId::Slice},
        {"dipole_marble", app::PanelId::Pencil}};
    for (const auto& [name, panel] : cases) {
        SCOPED_TRACE(name);
        const fs::path dir = testsupport::copyCapture(root, name, name);
        app::OpenedCapture oc = app::openCapture(root, dir, false);
        app::HeadlessGui gui(*oc.wb, 1280, 720);
        app::UiState& ui = gui.ui();
        app::showCapturedState(*oc.wb, ui, oc.name, oc.traceX, oc.traceY);
        gui.frame();
        gui.frame();
        EXPECT_NE(testsupport::panelWindow(panel), nullptr);
        if (panel == app::PanelId::LitSpheres) {
            EXPECT_EQ(ui.litSpheres.view, app::SphereView::SideBySide);
        }
    }
    fs::remove_all(root);
}

// A project model edited since the recording: the window shows today's file and its recorded
// text beside it (NAME.recorded, with the recorded parameters), and the Errors panel says so; a
// model gone: the recorded text alone; a change in comments only: nothing to say.
TEST(OpenCapture, AModelEditedOrGoneSinceIsOpenedBesideFromItsRecordedText) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("opencapedit", {"dipole.bssrdf"});
    const fs::path dir = testsupport::copyCapture(root, "dipole_marble", "marble");
    const fs::path model = root / "materials" / "dipole.bssrdf";
    const std::string recordedText = testsupport::readText(model);
    const std::string doubled = testsupport::replaced(recordedText, "return Multiplier/(4.0*PI)",
                                                      "return 2.0*Multiplier/(4.0*PI)");
    ASSERT_NE(doubled, recordedText);

    // what the Captures panel says of it, as recorded and after each change
    const auto about = [&] {
        std::string all;
        for (const std::string& line : app::describeCapture(root, dir))
            all += line + "\n";
        return all;
    };
    std::string text = about();
    EXPECT_EQ(text.rfind("recorded 20", 0), 0u) << text;
    EXPECT_NE(text.find("\nmodel materials/dipole.bssrdf: as recorded\n"), std::string::npos)
        << text;
    EXPECT_NE(text.find("\npreset Marble\n"), std::string::npos) << text;
    EXPECT_NE(text.find("\n2 stage outputs (2 csv)\n"), std::string::npos) << text;

    // comments only: the same program, no entry, no copy
    core::writeFile(model, "# a comment added since\n" + recordedText);
    text = about();
    EXPECT_NE(text.find("model materials/dipole.bssrdf: only comments or whitespace changed"),
              std::string::npos)
        << text;
    {
        app::OpenedCapture oc = app::openCapture(root, dir, false);
        EXPECT_EQ(oc.wb->library().entries().size(), 1u);
        EXPECT_TRUE(oc.wb->errors().empty()) << errorsText(*oc.wb);
    }

    core::writeFile(model, doubled);
    text = about();
    EXPECT_NE(text.find("model materials/dipole.bssrdf: content hash changed"), std::string::npos)
        << text;
    {
        app::OpenedCapture oc = app::openCapture(root, dir, false);
        app::Workbench& wb = *oc.wb;
        ASSERT_EQ(wb.library().entries().size(), 2u);
        const bssrdf::ModelEntry* recorded = nullptr;
        for (const auto& e : wb.library().entries())
            if (app::capturePathOf(e) == "external/dipole.recorded.bssrdf") recorded = &e;
        ASSERT_NE(recorded, nullptr);
        EXPECT_EQ(testsupport::readText(recorded->file), recordedText);
        const std::string errors = errorsText(wb);
        EXPECT_NE(errors.find("materials/dipole.bssrdf: content hash changed"), std::string::npos)
            << errors;
        EXPECT_NE(errors.find("today's file and, beside it, the recorded text as dipole.recorded"),
                  std::string::npos)
            << errors;
        // a capture of the pencil plot alone: every curve as its ratio to the recorded model's
        EXPECT_EQ(wb.plotSettings().relation, plot::Relation::Ratio);
        EXPECT_EQ(wb.plotSettings().compareWith, recorded->displayPath);
        EXPECT_TRUE(app::comparesWithModel(wb));
        EXPECT_NE(errors.find("the pencil plot shows every curve as its ratio to the recorded one"),
                  std::string::npos)
            << errors;
        // the recorded parameters on the copy too: both evaluate the recorded Marble
        EXPECT_EQ(app::paramsJson(wb)["models"]["external/dipole.recorded.bssrdf"],
                  manifestJson(dir)["params"]["models"]["materials/dipole.bssrdf"]);
        app::CaptureEntries c;
        wb.capture(c);
        const capture::Table* today = tableOf(c, "pencil_plot.dipole");
        const capture::Table* then = tableOf(c, "pencil_plot.dipole.recorded");
        ASSERT_TRUE(today && then);
        ASSERT_EQ(today->rows.size(), then->rows.size());
        const capture::Table asRecorded = capture::readCsv(dir / "pencil_plot_dipole.csv");
        ASSERT_EQ(asRecorded.rows.size(), then->rows.size());
        for (size_t i = 0; i < then->rows.size(); i += 37)
            for (size_t k = 1; k < 4; ++k) {
                EXPECT_NEAR(then->rows[i][k], asRecorded.rows[i][k],
                            1e-5 * std::abs(asRecorded.rows[i][k]) + 1e-30)
                    << "row " << i;
                EXPECT_NEAR(today->rows[i][k], 2.0 * then->rows[i][k],
                            1e-5 * std::abs(today->rows[i][k]) + 1e-30)
                    << "row " << i;
            }
    }

    fs::remove(model);
    text = about();
    EXPECT_NE(text.find("model materials/dipole.bssrdf: missing"), std::string::npos) << text;
    {
        app::OpenedCapture oc = app::openCapture(root, dir, false);
        ASSERT_EQ(oc.wb->library().entries().size(), 1u);
        EXPECT_EQ(app::capturePathOf(oc.wb->library().entries()[0]),
                  "external/dipole.recorded.bssrdf");
        const std::string errors = errorsText(*oc.wb);
        EXPECT_NE(errors.find("materials/dipole.bssrdf: missing"), std::string::npos) << errors;
        EXPECT_EQ(errors.find("today's file"), std::string::npos) << errors;
        EXPECT_EQ(oc.wb->plotSettings().relation, plot::Relation::Values); // nothing to compare
        EXPECT_NE(errors.find("the window shows the recorded text as dipole.recorded"),
                  std::string::npos)
            << errors;
    }
    fs::remove_all(root);
}

// Bad captures: not there (the captures that are, sorted), an unreadable manifest, settings that
// name a file outside the capture and the project.
TEST(OpenCapture, BadCapturesAreClearMessages) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("opencapbad", {"dipole.bssrdf"});
    testsupport::copyCapture(root, "dipole_marble", "zeta");
    const fs::path dir = testsupport::copyCapture(root, "dipole_marble", "alpha");
    try {
        app::findCapture(root, "nope");
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("nope"), std::string::npos) << what;
        EXPECT_NE(what.find("no such capture"), std::string::npos) << what;
        EXPECT_NE(what.find("(there: alpha, zeta)"), std::string::npos) << what;
    }
    EXPECT_THROW(app::findCapture(root, ""), core::Error);

    json m = manifestJson(dir);
    m["settings"]["lit_spheres"] = {{"mesh", "/etc/passwd"}};
    core::writeFile(dir / capture::kManifestFileName, m.dump(1));
    try {
        app::openCapture(root, dir, false);
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("manifest.json"), std::string::npos) << what;
        EXPECT_NE(what.find("settings.lit_spheres.mesh"), std::string::npos) << what;
    }

    core::writeFile(dir / capture::kManifestFileName, "{ \"format\": ");
    EXPECT_THROW(app::describeCapture(root, dir), core::Error);
    try {
        app::openCapture(root, dir, false);
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("manifest.json"), std::string::npos) << e.what();
    }
    fs::remove_all(root);
}

// The command line: gui --capture refuses, before any window, a capture that is not there, a
// --fresh it cannot honour and a machine without a display (naming what does work there);
// screenshot --capture draws the capture's state.
TEST(OpenCapture, TheCommandLineOpensOrSaysWhy) {
    ::unsetenv("DISPLAY");
    ::unsetenv("WAYLAND_DISPLAY");
    clitest::TempDir tmp("opencapcli");
    const std::string root = testsupport::sourceRoot().string();
    auto run = [&](std::vector<std::string> args) {
        args.insert(args.begin(), {BW_EXE, "--root", root});
        return clitest::runCommand(args, tmp.path());
    };
    clitest::RunResult r = run({"gui", "--capture", "nope"});
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("nope: no such capture"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("dipole_marble"), std::string::npos) << r.output;

    r = run({"gui", "--capture", "dipole_marble", "--fresh"});
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("--fresh"), std::string::npos) << r.output;

    r = run({"gui", "--capture", "dipole_marble"});
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("screenshot --capture dipole_marble"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("running the default capture headless"), std::string::npos) << r.output;

    const fs::path png = tmp.path() / "marble.png";
    r = run(
        {"screenshot", "--capture", "dipole_marble", "--size", "800x600", "--out", png.string()});
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_TRUE(fs::exists(png));
    r = run({"screenshot", "--capture", "nope", "--out", png.string()});
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("no such capture"), std::string::npos) << r.output;
}

// The Captures panel: "Open in a window" starts `gui --capture NAME` in a child (this window's
// state stays); a child that fails (here: no display) is an Errors entry with its reason. A
// double click on a capture replays it.
TEST(CapturesPanel, OpenInAWindowStartsAChildAndAFailureIsAnErrorsEntry) {
    ::unsetenv("DISPLAY");
    ::unsetenv("WAYLAND_DISPLAY");
    testsupport::context();
    auto root = testsupport::makeProjectRoot("opencappanel", {"dipole.bssrdf"});
    testsupport::copyCapture(root, "dipole_marble", "marble");
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    ui.captures.exe = BW_EXE;
    ui.shared.show(app::PanelId::Captures);
    gui.frame();
    gui.frame();
    ASSERT_EQ(ui.captures.names, std::vector<std::string>{"marble"});
    EXPECT_EQ(ui.captures.openWindow.width(), 0) << "a button with nothing selected";
    ASSERT_EQ(ui.captures.nameRects.size(), 1u);
    testsupport::click(gui, ui.captures.nameRects[0]);
    EXPECT_EQ(ui.captures.selected, "marble");
    EXPECT_FALSE(ui.captures.proc) << "a single click replays nothing";
    ASSERT_FALSE(ui.captures.about.empty()); // what it holds, shown under the buttons
    EXPECT_EQ(ui.captures.about[0].rfind("recorded ", 0), 0u) << ui.captures.about[0];
    ASSERT_GT(ui.captures.openWindow.width(), 0);
    ASSERT_TRUE(wb.errors().empty()) << errorsText(wb);
    testsupport::click(gui, ui.captures.openWindow); // the child may have ended within it
    core::Stopwatch clock;
    while (wb.errors().empty() && clock.ms() < 60000)
        gui.frame();
    EXPECT_TRUE(ui.captures.windows.empty());
    const std::string errors = errorsText(wb); // what the child said
    EXPECT_NE(errors.find("window on capture marble"), std::string::npos) << errors;
    EXPECT_NE(errors.find("no display"), std::string::npos) << errors;

    // a double click: press, release, press, release within ImGui's double-click time
    const app::Rect r = ui.captures.nameRects[0];
    const float x = 0.5f * (r.x0 + r.x1), y = 0.5f * (r.y0 + r.y1);
    for (bool down : {false, true, false, true, false}) {
        gui.mouse(x, y, down);
        gui.frame();
    }
    gui.noMouse();
    gui.frame();
    ASSERT_TRUE(ui.captures.proc) << "a double click did not replay";
    EXPECT_EQ(ui.captures.replaying, "marble");
    ui.captures.proc->cancel();
    fs::remove_all(root);
}
