// Hot reload end to end with real files, inotify and GL: write a model, see the new output;
// write a broken one, keep the old output and get the error; fix it, recover. Parameter
// values survive; models appear and disappear with their files; shaders reload too.
#include "../support/gl_fixture.h"
#include "../support/gui_windows.h"
#include "../support/workbench_values.h"
#include "gui/gui.h"
#include "pipeline/pencil_series.h"
#include "pipeline/workbench.h"

#include <algorithm>
#include <fstream>
#include <map>
#include <set>
#include <thread>

using testsupport::lineOf;
using testsupport::replaced;

namespace {
namespace fs = std::filesystem;
using testsupport::valueAt0;

using testsupport::waitFor;

// Editor-style save: write a temporary next to the file and rename it over the original.
void saveLikeAnEditor(const fs::path& file, const std::string& text) {
    std::string name = ".";
    name += file.filename().string();
    name += ".swp";
    const fs::path tmp = file.parent_path() / name;
    {
        std::ofstream out(tmp, std::ios::binary);
        out << text;
    }
    fs::rename(tmp, file);
}
} // namespace

TEST(HotReload, EditBreakRecover) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("hot", {"dipole.bssrdf"});
    const fs::path file = root / "materials/dipole.bssrdf";
    const std::string path = "materials/dipole.bssrdf";
    const std::string good = testsupport::readText(file);
    app::Workbench wb(root, true);
    ASSERT_TRUE(wb.watching());
    const double base = valueAt0(wb, path);
    ASSERT_GT(base, 0.0);

    // 1. a good edit of the GLSL shows up as new output
    std::string doubled =
        replaced(good, "return Multiplier/(4.0*PI)", "return 2.0*Multiplier/(4.0*PI)");
    saveLikeAnEditor(file, doubled);
    ASSERT_TRUE(waitFor(wb, [&] { return std::abs(valueAt0(wb, path) - 2 * base) < 1e-6 * base; }));

    // 2. a user-set value survives a reload when name and type persist
    wb.library().find(path)->values["Multiplier"] = {1.5f, 0, 0};
    wb.update();
    ASSERT_NEAR(valueAt0(wb, path), 3 * base, 1e-5 * base);
    saveLikeAnEditor(file, doubled + "\n# a comment\n");
    ASSERT_TRUE(waitFor(wb, [&] { return wb.library().find(path)->generation >= 3; }));
    EXPECT_FLOAT_EQ(wb.library().find(path)->values["Multiplier"][0], 1.5f);
    EXPECT_NEAR(valueAt0(wb, path), 3 * base, 1e-5 * base);

    // 3. a broken save keeps the last good program and output, and names file:line
    std::string broken = replaced(doubled, "    vec3 Zr = Lu;", "    vec3 Zr = Lu +* ;");
    saveLikeAnEditor(file, broken);
    ASSERT_TRUE(waitFor(wb, [&] { return wb.library().find(path)->problem.has_value(); }));
    auto* e = wb.library().find(path);
    EXPECT_EQ(e->problem->file, path);
    EXPECT_EQ(e->problem->line, lineOf(broken, "Lu +* ;"));
    EXPECT_TRUE(e->usable());
    EXPECT_NEAR(valueAt0(wb, path), 3 * base, 1e-5 * base);
    bool listed = false;
    for (const auto& err : wb.errors())
        listed |= err.text.find(path + ":" + std::to_string(e->problem->line)) != std::string::npos;
    EXPECT_TRUE(listed);

    // 4. the next good save recovers by itself
    std::string tripled =
        replaced(good, "return Multiplier/(4.0*PI)", "return 3.0*Multiplier/(4.0*PI)");
    saveLikeAnEditor(file, tripled);
    ASSERT_TRUE(waitFor(wb, [&] { return !wb.library().find(path)->problem.has_value(); }));
    wb.library().find(path)->values["Multiplier"] = {1.0f, 0, 0};
    ASSERT_TRUE(waitFor(wb, [&] { return std::abs(valueAt0(wb, path) - 3 * base) < 1e-5 * base; }));
    EXPECT_TRUE(wb.errors().empty());
    fs::remove_all(root);
}

TEST(HotReload, ModelsAppearAndDisappearWithTheirFiles) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("appear", {"dipole.bssrdf"});
    app::Workbench wb(root, true);
    ASSERT_EQ(wb.library().entries().size(), 1u);
    fs::copy_file(testsupport::sourceRoot() / "materials/better_dipole.bssrdf",
                  root / "materials/better_dipole.bssrdf");
    ASSERT_TRUE(waitFor(wb, [&] { return wb.library().entries().size() == 2; }));
    EXPECT_TRUE(waitFor(wb, [&] { return valueAt0(wb, "materials/better_dipole.bssrdf") > 0; }));
    fs::remove(root / "materials/dipole.bssrdf"); // deleted while watched
    ASSERT_TRUE(waitFor(wb, [&] { return wb.library().entries().size() == 1; }));
    EXPECT_EQ(wb.library().entries()[0].displayPath, "materials/better_dipole.bssrdf");
    EXPECT_EQ(plotSeries(wb).size(), 1u);
    EXPECT_TRUE(wb.errors().empty());
    fs::remove_all(root);
}

// Each model keeps its colour and line style in the pencil plot while it stays loaded: adding a
// model that sorts before the others, or removing one, changes no other model's curve.
TEST(HotReload, AModelKeepsItsColourWhenOthersComeAndGo) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("colours", {"dipole.bssrdf", "multipole.bssrdf"});
    app::Workbench wb(root, true);
    wb.referenceSettings().enabled = false;
    auto styles = [&] { // model name → (colour, dashed)
        std::map<std::string, std::pair<uint32_t, bool>> out;
        for (const plot::Series& s : plotSeries(wb))
            out[s.label.substr(0, s.label.find("  "))] = {s.color, s.dashed};
        return out;
    };
    ASSERT_TRUE(waitFor(wb, [&] { return styles().size() == 2; }));
    const auto before = styles();
    fs::copy_file(testsupport::sourceRoot() / "materials/better_dipole.bssrdf",
                  root / "materials/better_dipole.bssrdf");
    ASSERT_TRUE(waitFor(wb, [&] { return styles().size() == 3; }));
    auto after = styles();
    for (const auto& [name, style] : before)
        EXPECT_EQ(after.at(name), style) << name << " changed when a model was added";
    std::set<uint32_t> colours;
    for (const auto& [name, style] : after)
        colours.insert(style.first);
    EXPECT_EQ(colours.size(), 3u) << "every present model has its own colour";

    const std::string removed = wb.library().find("materials/dipole.bssrdf")->model->name;
    fs::remove(root / "materials/dipole.bssrdf");
    ASSERT_TRUE(waitFor(wb, [&] { return styles().size() == 2; }));
    for (const auto& [name, style] : styles())
        EXPECT_EQ(after.at(name), style) << name << " changed when " << removed << " was removed";
    fs::remove_all(root);
}

// A parameter's value survives a reload, so a default edited in the file changes nothing on
// screen by itself: the model says which values are off the file's defaults, and resetting to
// them brings the edited default into the profile.
TEST(HotReload, AnEditedDefaultIsReportedAndResetBringsIt) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("defaults", {"dipole.bssrdf"});
    const fs::path file = root / "materials/dipole.bssrdf";
    const std::string path = "materials/dipole.bssrdf";
    app::Workbench wb(root, true);
    const double before = valueAt0(wb, path);
    ASSERT_GT(before, 0);
    EXPECT_TRUE(bssrdf::valuesOffTheDefaults(*wb.library().find(path)->model,
                                             wb.library().find(path)->values)
                    .empty());
    const std::string text = testsupport::readText(file);
    saveLikeAnEditor(
        file, replaced(text, "float Multiplier 0.0 10.0 1.0", "float Multiplier 0.0 10.0 2.0"));
    ASSERT_TRUE(waitFor(wb, [&] {
        const auto* e = wb.library().find(path);
        return e && e->model && e->model->findParam("Multiplier") &&
               e->model->findParam("Multiplier")->value[0] == 2.0f;
    }));
    const auto* e = wb.library().find(path);
    EXPECT_EQ(e->values.at("Multiplier")[0], 1.0f) << "the value in use survived the reload";
    EXPECT_EQ(bssrdf::valuesOffTheDefaults(*e->model, e->values),
              std::vector<std::string>{"Multiplier"});
    // the Models panel says so and its button, clicked, brings the file's default
    app::HeadlessGui gui(wb, 1280, 720);
    gui.ui().shared.show(app::PanelId::Models);
    gui.frame();
    gui.frame();
    const app::Rect r = gui.ui().shared.resetDefaults;
    ASSERT_GT(r.width(), 10.0f) << "no reset button";
    testsupport::click(gui, r);
    EXPECT_EQ(e->values.at("Multiplier")[0], 2.0f);
    ASSERT_TRUE(waitFor(wb, [&] { return valueAt0(wb, path) > 1.5 * before; }));
    EXPECT_NEAR(valueAt0(wb, path), 2.0 * before, 1e-3 * before);
    EXPECT_TRUE(bssrdf::valuesOffTheDefaults(*e->model, e->values).empty());
    fs::remove_all(root);
}

TEST(HotReload, BrokenShaderTemplateKeepsProgramsAndRecovers) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("shader", {"dipole.bssrdf"});
    app::Workbench wb(root, true);
    const std::string path = "materials/dipole.bssrdf";
    const double base = valueAt0(wb, path);
    const fs::path tplFile = root / "shaders/pencil_profile.comp";
    const std::string tpl = testsupport::readText(tplFile);
    saveLikeAnEditor(tplFile, replaced(tpl, "    init();", "    init(;"));
    ASSERT_TRUE(waitFor(wb, [&] { return wb.library().find(path)->problem.has_value(); }));
    EXPECT_EQ(wb.library().find(path)->problem->file, "shaders/pencil_profile.comp");
    EXPECT_TRUE(wb.library().find(path)->usable());
    // a changed template that still works doubles the output
    saveLikeAnEditor(tplFile, replaced(tpl, "vec3 v = Bssrdf(vec3(0.0), n, vec3(r, 0.0, 0.0), n);",
                                       "vec3 v = 2.0*Bssrdf(vec3(0.0), n, vec3(r, 0.0, 0.0), n);"));
    ASSERT_TRUE(waitFor(wb, [&] { return std::abs(valueAt0(wb, path) - 2 * base) < 1e-6 * base; }));
    EXPECT_FALSE(wb.library().find(path)->problem.has_value());
    fs::remove_all(root);
}

TEST(HotReload, NonUtf8AndEmptySavesAreErrorsNotCrashes) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("binary", {"dipole.bssrdf"});
    app::Workbench wb(root, true);
    const std::string path = "materials/dipole.bssrdf";
    const double base = valueAt0(wb, path);
    saveLikeAnEditor(root / "materials/dipole.bssrdf", std::string("\x7f"
                                                                   "ELF\x02\x01\x01\0\0\0",
                                                                   10));
    ASSERT_TRUE(waitFor(wb, [&] { return wb.library().find(path)->problem.has_value(); }));
    EXPECT_NE(wb.library().find(path)->problem->message.find("UTF-8"), std::string::npos);
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base);
    saveLikeAnEditor(root / "materials/dipole.bssrdf", "");
    ASSERT_TRUE(waitFor(wb, [&] {
        auto* e = wb.library().find(path);
        return e->problem && e->problem->message.find("empty") != std::string::npos;
    }));
    EXPECT_NEAR(valueAt0(wb, path), base, 1e-6 * base);
    fs::remove_all(root);
}

// One Errors entry per problem: a broken shader template that every model includes is one
// entry naming the models it affects, not one per model; the log says it once.
TEST(HotReload, BrokenTemplateIsOneErrorsEntryListingTheModels) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("oneentry", {"dipole.bssrdf", "better_dipole.bssrdf"});
    app::Workbench wb(root, true);
    wb.update();
    const fs::path tplFile = root / "shaders/pencil_profile.comp";
    const std::string tpl = testsupport::readText(tplFile);
    saveLikeAnEditor(tplFile, replaced(tpl, "    init();", "    init(;"));
    ASSERT_TRUE(waitFor(wb, [&] {
        return wb.library().find("materials/dipole.bssrdf")->problem.has_value() &&
               wb.library().find("materials/better_dipole.bssrdf")->problem.has_value();
    }));
    for (int i = 0; i < 5; ++i)
        wb.update();
    const auto errors = wb.errors();
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_EQ(errors[0].source, "shader");
    // the line of the edit in the template
    const std::string before = tpl.substr(0, tpl.find("    init();"));
    const std::string line = std::to_string(std::count(before.begin(), before.end(), '\n') + 1);
    EXPECT_NE(errors[0].text.find("shaders/pencil_profile.comp:" + line + ":"), std::string::npos)
        << errors[0].text;
    EXPECT_NE(errors[0].text.find("(affects better_dipole, dipole)"), std::string::npos)
        << errors[0].text;
    fs::remove_all(root);
}

// A model opened from outside the project is watched like those in materials/: an edit there
// reloads it.
TEST(HotReload, ModelOpenedFromAnywhereIsWatched) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("anywhere", {});
    const fs::path outside =
        fs::temp_directory_path() / ("bw_outside_" + std::to_string(::getpid()));
    fs::create_directories(outside);
    testsupport::removeAtExit(outside);
    const fs::path file = outside / "mine.bssrdf";
    const std::string good =
        testsupport::readText(testsupport::sourceRoot() / "materials/dipole.bssrdf");
    saveLikeAnEditor(file, good);
    app::Workbench wb(root, true);
    wb.openModel(file);
    const std::string path = wb.library().entries().at(0).displayPath;
    ASSERT_TRUE(waitFor(wb, [&] { return valueAt0(wb, path) > 0; }));
    const double base = valueAt0(wb, path);
    saveLikeAnEditor(
        file, replaced(good, "return Multiplier/(4.0*PI)", "return 2.0*Multiplier/(4.0*PI)"));
    EXPECT_TRUE(waitFor(wb, [&] { return std::abs(valueAt0(wb, path) - 2 * base) < 1e-6 * base; }))
        << valueAt0(wb, path) << " vs " << base;
    fs::remove_all(outside);
    fs::remove_all(root);
}
