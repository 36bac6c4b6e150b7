// A new model to edit (pipeline/new_model.h): `new-model` and File → New model write
// materials/NAME.bssrdf from another model's text (the dipole by default), never over a model,
// refuse a name that is not a file name, and the model made loads and evaluates as its source.
#include "../support/cli_runner.h"
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "core/core.h"
#include "gui/gui.h"
#include "gui/panels/panels.h"
#include "pipeline/new_model.h"

#include <GLFW/glfw3.h>

namespace {
namespace fs = std::filesystem;

// The text after the first line (the comment naming where the model came from).
std::string afterFirstLine(const std::string& text) {
    const size_t nl = text.find('\n');
    return nl == std::string::npos ? "" : text.substr(nl + 1);
}

} // namespace

TEST(NewModel, TheCommandLineMakesOneFromAnotherAndNeverOverwrites) {
    testsupport::context();
    auto root =
        testsupport::makeProjectRoot("newmodelcli", {"dipole.bssrdf", "better_dipole.bssrdf"});
    auto run = [&](std::vector<std::string> args) {
        args.insert(args.begin(), {BW_EXE, "--root", root.string(), "new-model"});
        return clitest::runCommand(args, root);
    };
    const std::string dipole = testsupport::readText(root / "materials/dipole.bssrdf");
    clitest::RunResult r = run({"--name", "mine"});
    ASSERT_EQ(r.code, 0) << r.output;
    const fs::path mine = root / "materials/mine.bssrdf";
    EXPECT_NE(r.output.find("wrote " + mine.string()), std::string::npos) << r.output;
    const std::string text = testsupport::readText(mine);
    EXPECT_EQ(text.rfind("# mine: made from materials/dipole.bssrdf on 20", 0), 0u) << text;
    EXPECT_EQ(afterFirstLine(text), dipole);

    // never over a model; names that are not file names; a source that is not there
    const auto refused = [&](std::vector<std::string> args, const std::string& why) {
        const clitest::RunResult bad = run(args);
        EXPECT_EQ(bad.code, 1) << bad.output;
        EXPECT_NE(bad.output.find(why), std::string::npos) << bad.output;
    };
    core::writeFile(mine, "# mine, edited\n" + dipole);
    refused({"--name", "mine"}, "materials/mine.bssrdf exists");
    EXPECT_EQ(testsupport::readText(mine), "# mine, edited\n" + dipole) << "overwritten";
    refused({"--name", ".hidden"}, "starts with '.'");
    refused({"--name", "-x"}, "starts with '-'");
    refused({"--name", "a/b"}, "letters, digits");
    refused({"--name", "x", "--from", "materials/nope.bssrdf"}, "--from");
    EXPECT_FALSE(fs::exists(root / "materials/x.bssrdf"));

    // from another model; a name given with its extension
    r = run({"--name", "other.bssrdf", "--from", "materials/better_dipole.bssrdf"});
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(afterFirstLine(testsupport::readText(root / "materials/other.bssrdf")),
              testsupport::readText(root / "materials/better_dipole.bssrdf"));
    EXPECT_FALSE(fs::exists(root / "materials/other.bssrdf.bssrdf"));

    // the name alone, as a user types it; one name only
    r = run({"third"});
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(afterFirstLine(testsupport::readText(root / "materials/third.bssrdf")), dipole);
    r = run({"fourth", "fifth"}); // a usage error (exit 2)
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("not expected: fifth"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(root / "materials/fourth.bssrdf"));

    // the models made load and evaluate as their sources do
    app::Workbench wb(root, false);
    for (const auto& [made, source] :
         {std::pair{"materials/mine.bssrdf", "materials/dipole.bssrdf"},
          {"materials/other.bssrdf", "materials/better_dipole.bssrdf"}}) {
        SCOPED_TRACE(made);
        const auto* e = wb.library().find(made);
        ASSERT_NE(e, nullptr);
        EXPECT_FALSE(e->problem) << e->problem->text();
        const auto &a = wb.view(made).profile, &b = wb.view(source).profile;
        ASSERT_FALSE(a.r.empty());
        ASSERT_EQ(a.r, b.r);
        for (size_t i = 0; i < a.r.size(); i += 31)
            EXPECT_EQ(a.value[i], b.value[i]) << "r " << a.r[i];
    }
    fs::remove_all(root);
}

// A model made by name is used by name: `--model NAME` (and `--from NAME`) stands for
// materials/NAME.bssrdf of the root when no such file is given; a name that is no model is an
// error listing the root's models.
TEST(NewModel, TheCommandsTakeAModelByItsName) {
    testsupport::context();
    auto root =
        testsupport::makeProjectRoot("newmodelname", {"dipole.bssrdf", "better_dipole.bssrdf"});
    auto run = [&](std::vector<std::string> args) {
        args.insert(args.begin(), {BW_EXE, "--root", root.string()});
        return clitest::runCommand(args, root);
    };
    clitest::RunResult r = run({"new-model", "mine", "--from", "better_dipole"});
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(afterFirstLine(testsupport::readText(root / "materials/mine.bssrdf")),
              testsupport::readText(root / "materials/better_dipole.bssrdf"));
    for (const char* name : {"mine", "mine.bssrdf", "materials/mine.bssrdf"}) {
        SCOPED_TRACE(name);
        r = run({"profile", "--model", name, "--preset", "Skin1", "--out", "p.csv"});
        ASSERT_EQ(r.code, 0) << r.output;
        EXPECT_NE(testsupport::readText(root / "p.csv").find("# model materials/mine.bssrdf"),
                  std::string::npos);
    }
    r = run({"profile", "--model", "mnie", "--preset", "Skin1", "--out", "q.csv"});
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("mnie: --model: no such file; the models in " +
                            (root / "materials").string() + ": better_dipole, dipole, mine"),
              std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(root / "q.csv"));
    // only a bare name is looked up in materials/: a path stays the path it is
    r = run({"profile", "--model", "other/mine", "--preset", "Skin1", "--out", "q.csv"});
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_NE(r.output.find("other/mine: --model: no such file"), std::string::npos) << r.output;
    fs::remove_all(root);
}

// File → New model (Ctrl+N): the name takes what is typed, a refused name is said and creates
// nothing, Enter writes the model from the one chosen and opens it at once; Escape closes.
TEST(NewModel, TheDialogCreatesAndOpensIt) {
    testsupport::context();
    auto root =
        testsupport::makeProjectRoot("newmodelgui", {"dipole.bssrdf", "better_dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::HeadlessGui gui(wb, 1280, 720);
    app::UiState& ui = gui.ui();
    testsupport::mapDialogKeys();
    const auto type = [&](const std::string& text) { testsupport::typeText(gui, text); };
    const auto press = [&](int key) { testsupport::pressKey(gui, key); };
    const auto popups = testsupport::openPopups;
    const auto open = [&] {
        ui.menu.newModelPopup = true;
        gui.frame();
        gui.frame();
        ASSERT_EQ(popups(), 1);
    };
    gui.frame();

    open();
    type("dipole");
    EXPECT_STREQ(ui.menu.newModelName, "dipole") << "typed over the proposed name";
    press(GLFW_KEY_ENTER);
    EXPECT_EQ(popups(), 1) << "a name in use closed the dialog";
    press(GLFW_KEY_ESCAPE);
    EXPECT_EQ(popups(), 0) << "Escape left the dialog open";

    const size_t models = wb.library().entries().size();
    ui.menu.newModelFrom = "materials/better_dipole.bssrdf";
    open();
    type("fresh");
    press(GLFW_KEY_ENTER);
    EXPECT_EQ(popups(), 0);
    const fs::path fresh = root / "materials/fresh.bssrdf";
    ASSERT_TRUE(fs::exists(fresh));
    EXPECT_EQ(afterFirstLine(testsupport::readText(fresh)),
              testsupport::readText(root / "materials/better_dipole.bssrdf"));
    EXPECT_EQ(wb.library().entries().size(), models + 1) << "not opened";
    EXPECT_NE(wb.library().find("materials/fresh.bssrdf"), nullptr);
    EXPECT_EQ(ui.shared.status, "created materials/fresh.bssrdf");
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    fs::remove_all(root);
}
