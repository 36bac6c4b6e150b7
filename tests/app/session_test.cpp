// The session the window keeps between runs (captures/session.h): the next start has the
// models, parameters and settings the window closed with, a model from outside the project is
// opened again where it is (not from a copy, so its edits still reload), another project's
// session is not used, and a model gone or a session damaged since is an Errors entry with the
// rest (or the defaults) standing.
#include "../support/gl_fixture.h"
#include "captures/manifest.h"
#include "captures/session.h"
#include "captures/settings_json.h"
#include "core/core.h"

#include <gtest/gtest.h>

namespace {
namespace fs = std::filesystem;

struct SessionFixture {
    fs::path root, elsewhere, model, dir;
    SessionFixture() {
        testsupport::context();
        root = testsupport::makeProjectRoot(
            std::string("session_") +
                ::testing::UnitTest::GetInstance()->current_test_info()->name(),
            {"dipole.bssrdf"});
        elsewhere = root.parent_path() / (root.filename().string() + "_elsewhere");
        fs::create_directories(elsewhere);
        testsupport::removeAtExit(elsewhere);
        model = elsewhere / "mine.bssrdf";
        fs::copy_file(testsupport::sourceRoot() / "materials/better_dipole.bssrdf", model,
                      fs::copy_options::overwrite_existing);
        dir = elsewhere / "config" / "sessions" / "this";
    }
    // A workbench with the state a user made: a model opened from elsewhere, a preset, a
    // model's parameter, a hidden model, a setting.
    std::unique_ptr<app::Workbench> edited() {
        auto wb = std::make_unique<app::Workbench>(root, false);
        wb->openModel(model);
        wb->applyPreset(wb->shared(), "Ketchup");
        wb->referenceSettings().paths = 123457;
        auto* dipole = wb->library().find("materials/dipole.bssrdf");
        EXPECT_NE(dipole, nullptr);
        if (dipole) {
            dipole->values["Multiplier"][0] = 2.5f;
            wb->view(dipole->displayPath).visible = false;
        }
        wb->update();
        return wb;
    }
};

std::string settingsOf(app::Workbench& wb) {
    nlohmann::json s = app::settingsJson(wb, -1, -1);
    s.erase("r_max_mm"); // informational, derived by the next update
    return s.dump();
}

bool hasError(const app::Workbench& wb, const std::string& fragment) {
    for (const app::ErrorItem& e : wb.errors())
        if (e.text.find(fragment) != std::string::npos) return true;
    return false;
}

} // namespace

TEST(Session, TheNextStartHasTheStateAndOpensAModelFromElsewhereWhereItIs) {
    SessionFixture fx;
    auto wb = fx.edited();
    app::saveSession(*wb, fx.dir);
    ASSERT_TRUE(fs::exists(fx.dir / "request.json"));
    auto again = app::restoreSession(fx.dir, fx.root, false);
    ASSERT_NE(again, nullptr);
    EXPECT_EQ(app::paramsJson(*again).dump(), app::paramsJson(*wb).dump());
    EXPECT_EQ(settingsOf(*again), settingsOf(*wb));
    EXPECT_TRUE(again->scene().settings().useCache) << "the point cloud comes from the cache";
    ASSERT_EQ(again->library().entries().size(), 2u);
    const bssrdf::ModelEntry* mine = nullptr;
    for (auto& e : again->library().entries())
        if (e.file.filename() == "mine.bssrdf") mine = &e;
    ASSERT_NE(mine, nullptr);
    EXPECT_EQ(fs::absolute(mine->file).lexically_normal(), fx.model.lexically_normal())
        << "opened where it is, not from a copy of its text";
    for (const app::ErrorItem& e : again->errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    // a relative root names the same project
    EXPECT_NE(app::restoreSession(fx.dir, fx.root / "materials" / "..", false), nullptr);
}

TEST(Session, NoneOrAnotherProjectsIsNotUsed) {
    SessionFixture fx;
    EXPECT_EQ(app::restoreSession(fx.dir, fx.root, false), nullptr);
    auto wb = fx.edited();
    app::saveSession(*wb, fx.dir);
    const fs::path other = testsupport::makeProjectRoot("session_other", {"dipole.bssrdf"});
    EXPECT_EQ(app::restoreSession(fx.dir, other, false), nullptr);
    EXPECT_NE(app::sessionDir("/c", fx.root), app::sessionDir("/c", other));
    EXPECT_EQ(app::sessionDir("/c", fx.root), app::sessionDir("/c", fx.root / "."));
}

TEST(Session, AModelGoneSinceIsAnErrorAndTheRestStands) {
    SessionFixture fx;
    auto wb = fx.edited();
    app::saveSession(*wb, fx.dir);
    fs::remove(fx.model);
    auto again = app::restoreSession(fx.dir, fx.root, false);
    ASSERT_NE(again, nullptr);
    EXPECT_TRUE(hasError(*again, "session: " + fx.model.string() + ": no longer there"));
    EXPECT_EQ(again->library().entries().size(), 1u);
    EXPECT_EQ(core::toJson(again->shared()).dump(), core::toJson(wb->shared()).dump());
    EXPECT_EQ(again->referenceSettings().paths, 123457);
}

TEST(Session, ADamagedSessionIsAnErrorAndTheDefaultsStand) {
    SessionFixture fx;
    app::Workbench defaults(fx.root, false);
    {
        auto wb = fx.edited();
        app::saveSession(*wb, fx.dir);
    }
    // a setting of the wrong type: named with its file, the defaults (and the models) stand
    nlohmann::json request = nlohmann::json::parse(core::readFile(fx.dir / "request.json"));
    request["settings"]["reference"]["paths"] = "many";
    core::writeFile(fx.dir / "request.json", request.dump());
    auto again = app::restoreSession(fx.dir, fx.root, false);
    ASSERT_NE(again, nullptr);
    EXPECT_TRUE(hasError(*again, "session: " + (fx.dir / "request.json").string()));
    EXPECT_EQ(again->referenceSettings().paths, defaults.referenceSettings().paths);
    EXPECT_EQ(core::toJson(again->shared()).dump(), core::toJson(defaults.shared()).dump());
    EXPECT_EQ(again->library().entries().size(), 2u) << "the model from elsewhere is kept";
    // session.json not JSON: named, the defaults
    core::writeFile(fx.dir / "session.json", "{ not json");
    again = app::restoreSession(fx.dir, fx.root, false);
    ASSERT_NE(again, nullptr);
    EXPECT_TRUE(hasError(*again, "session: " + (fx.dir / "session.json").string() + ": "));
    EXPECT_EQ(again->library().entries().size(), 1u);
    // request.json gone: named, the models from elsewhere still opened
    core::writeFile(fx.dir / "session.json",
                    nlohmann::json{{"format", 1},
                                   {"root", fs::weakly_canonical(fx.root).string()},
                                   {"external", {{"external/mine.bssrdf", fx.model.string()}}}}
                        .dump());
    fs::remove(fx.dir / "request.json");
    again = app::restoreSession(fx.dir, fx.root, false);
    ASSERT_NE(again, nullptr);
    EXPECT_TRUE(hasError(*again, "session: " + (fx.dir / "request.json").string()));
    EXPECT_EQ(again->library().entries().size(), 2u);
}
