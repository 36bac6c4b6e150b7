// Settings descriptions (core/fields.h) of every workbench settings struct: each member is
// described (or skipped on purpose), JSON round-trips every described member, the cache key
// covers every member, bad JSON names its path, the CLI's defaults are the GUI's, and the
// README's defaults table is the program's.
#include "cli_options.h"
#include "cli_pointcloud.h"
#include "cli_render.h"
#include "cli_slab.h"
#include "settings_json.h"
#include "workbench.h"

#include "core/fields.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace {

// Changes the leaf members of a settings struct to values other than their defaults: every
// one (only = -1) or only the one with that index (in forEachField order).
template <class T> size_t perturb(T& s, long only = -1) {
    size_t index = 0;
    core::forEachField(s, [&](const std::string&, auto& m, const char*) {
        using M = std::remove_reference_t<decltype(m)>;
        if (only >= 0 && long(index++) != only) return;
        if (only < 0) ++index;
        if constexpr (std::is_same_v<M, bool>) {
            m = !m;
        } else if constexpr (core::NamedEnum<M>) {
            const auto names = enumNames(M{});
            for (size_t k = 0; k < names.size(); ++k)
                if (names[k].first == m) {
                    m = names[(k + 1) % names.size()].first;
                    break;
                }
        } else if constexpr (std::is_arithmetic_v<M>) {
            m = M(m + M(1));
        } else if constexpr (std::is_same_v<M, std::string>) {
            m += "x";
        } else {
            m += M(0.5f, 1.5f, 2.5f);
        }
    });
    return index;
}

template <class T> void expectDescribed(const char* name) {
    SCOPED_TRACE(name);
    // a member added to the struct but not to its description fails here
    EXPECT_EQ(core::describedCount<T>(), core::fieldCount<T>());
    // JSON round trip with every member changed
    T changed{};
    const size_t leaves = perturb(changed);
    ASSERT_GT(leaves, 0u);
    const nlohmann::json j = core::toJson(changed);
    T back{};
    core::fromJson(j, back, "test", "s");
    EXPECT_EQ(core::toJson(back).dump(), j.dump());
    // every leaf changed, and the cache key sees each one alone
    const std::string defaultKey = core::keyOf(T{});
    for (size_t i = 0; i < leaves; ++i) {
        T one{};
        perturb(one, long(i));
        EXPECT_NE(core::toJson(one).dump(), core::toJson(T{}).dump()) << "leaf " << i;
        EXPECT_NE(core::keyOf(one), defaultKey) << "leaf " << i;
    }
}

TEST(Settings, EveryStructIsDescribedAndRoundTrips) {
    expectDescribed<render::Camera>("render::Camera");
    expectDescribed<render::Settings>("render::Settings");
    expectDescribed<irradiance::Settings>("irradiance::Settings");
    expectDescribed<pointcloud::GenerateOptions>("pointcloud::GenerateOptions");
    expectDescribed<pathtrace::Termination>("pathtrace::Termination");
    expectDescribed<pathtrace::SlabSettings>("pathtrace::SlabSettings");
    expectDescribed<material::MaterialParams>("material::MaterialParams");
    expectDescribed<bssrdf::Builtins>("bssrdf::Builtins");
    expectDescribed<app::MaterialSettings>("app::MaterialSettings");
    expectDescribed<app::PlotSettings>("app::PlotSettings");
    expectDescribed<app::ReferenceSettings>("app::ReferenceSettings");
    expectDescribed<app::LitSphereSettings>("app::LitSphereSettings");
    expectDescribed<app::SliceSettings>("app::SliceSettings");
    expectDescribed<app::SceneSettings>("app::SceneSettings");
}

TEST(Settings, RenderKeySeesTheBackground) {
    render::Settings a, b;
    b.background.x += 0.25f;
    EXPECT_NE(core::keyOf(a), core::keyOf(b));
    EXPECT_EQ(core::keyOf(a), core::keyOf(render::Settings{}));
}

std::string errorOf(const nlohmann::json& j) {
    try {
        app::SceneSettings s;
        core::fromJson(j, s, "manifest.json", "settings.scene");
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}

TEST(Settings, BadJsonNamesItsPath) {
    using nlohmann::json;
    EXPECT_NE(errorOf(json::parse(R"({"render": {"eps": "x"}})"))
                  .find("settings.scene.render.eps: expected a number"),
              std::string::npos);
    EXPECT_NE(errorOf(json::parse(R"({"render": {"camera": {"fovy": 1}}})"))
                  .find("settings.scene.render.camera.fovy: unknown key"),
              std::string::npos);
    const std::string e = errorOf(json::parse(R"({"light": {"mode": "sun"}})"));
    EXPECT_NE(e.find("settings.scene.light.mode: unknown name 'sun'"), std::string::npos) << e;
    EXPECT_NE(e.find("occluded-ibl"), std::string::npos) << e;
    EXPECT_NE(errorOf(json::parse(R"({"points": {"count": -3}})"))
                  .find("settings.scene.points.count: integer -3 out of range"),
              std::string::npos);
    EXPECT_NE(errorOf(json::parse(R"({"light": {"direction": [1, 2]}})"))
                  .find("settings.scene.light.direction: expected an array of 3 numbers"),
              std::string::npos);
    EXPECT_NE(errorOf(json::parse(R"({"enabled": 1})")).find("settings.scene.enabled: expected"),
              std::string::npos);
    EXPECT_NE(errorOf(json::parse(R"([])")).find("settings.scene: expected an object"),
              std::string::npos);
    EXPECT_EQ(errorOf(json::parse(R"({"render": {"eps": 2}})")), "");
}

TEST(Settings, OlderManifestsStillRead) {
    // format-1 captures: light mode and shadow filter as integers, later members absent
    app::SceneSettings s;
    core::fromJson(nlohmann::json::parse(R"({"light": {"mode": 2, "filter": 1}})"), s, "m",
                   "settings.scene");
    EXPECT_EQ(s.light.mode, irradiance::LightMode::Ibl);
    EXPECT_EQ(s.light.filter, irradiance::ShadowFilter::Offset);
    EXPECT_EQ(core::toJson(s.render).dump(), core::toJson(app::SceneSettings{}.render).dump());
    EXPECT_NE(errorOf(nlohmann::json::parse(R"({"light": {"mode": 7}})")).find("unknown value 7"),
              std::string::npos);
}

TEST(Settings, CliDefaultsAreTheGuiDefaults) {
    {
        CLI::App cli;
        app::RenderArgs a;
        app::addRenderOptions(&cli, a);
        cli.parse("--mesh m.obj --model m.bssrdf --out o.exr", false);
        EXPECT_EQ(core::toJson(a.scene).dump(), core::toJson(app::SceneSettings{}).dump());
        EXPECT_TRUE(a.light.empty());
        EXPECT_FALSE(a.irradiance.has_value());
        EXPECT_TRUE(a.useCache);
    }
    {
        CLI::App cli;
        app::PointCloudArgs a;
        app::addPointCloudOptions(&cli, a);
        cli.parse("--mesh m.obj --out o.ply", false);
        EXPECT_EQ(core::toJson(a.options).dump(), core::toJson(app::SceneSettings{}.points).dump());
    }
    {
        // slab: the medium's and the slab settings' own defaults, options reach them
        CLI::App cli;
        app::SlabArgs a;
        app::addSlabOptions(&cli, a);
        cli.parse("--out o.csv", false);
        EXPECT_EQ(core::toJson(a.medium).dump(), core::toJson(pathtrace::Medium{}).dump());
        EXPECT_EQ(core::toJson(a.settings).dump(), core::toJson(pathtrace::SlabSettings{}).dump());
        CLI::App cli2;
        app::SlabArgs b;
        app::addSlabOptions(&cli2, b);
        cli2.parse("--out o.csv --sigma-a 0.5 --eta 1.5 --max-events 77 --estimator analog "
                   "--roulette-survival 0.25",
                   false);
        EXPECT_EQ(b.medium.sigmaA, 0.5);
        EXPECT_EQ(b.medium.eta, 1.5);
        EXPECT_EQ(b.settings.termination.maxEvents, 77u);
        EXPECT_EQ(b.settings.termination.rouletteSurvival, 0.25);
        EXPECT_EQ(b.settings.estimator, pathtrace::Estimator::Analog);
    }
    // and the options reach the settings
    CLI::App cli;
    app::RenderArgs a;
    app::addRenderOptions(&cli, a);
    cli.parse("--mesh m.obj --model m.bssrdf --out o.exr --eps 0.5 --first-order "
              "--no-bbox-criterion --method uniform --width 64 --yaw 1.25 --no-cache",
              false);
    EXPECT_EQ(a.scene.render.eps, 0.5f);
    EXPECT_FALSE(a.scene.render.secondOrder);
    EXPECT_FALSE(a.scene.render.boundingBoxCriterion);
    EXPECT_EQ(a.scene.points.method, pointcloud::Method::Uniform);
    EXPECT_EQ(a.scene.render.width, 64);
    EXPECT_EQ(a.scene.render.camera.yaw, 1.25f);
    EXPECT_FALSE(a.useCache);
    CLI::App bad;
    app::RenderArgs b;
    app::addRenderOptions(&bad, b);
    try {
        bad.parse("--mesh m.obj --model m.bssrdf --out o.exr --method poisson", false);
        ADD_FAILURE() << "--method poisson was accepted";
    } catch (const CLI::ParseError& e) {
        EXPECT_NE(std::string(e.what()).find("poisson"), std::string::npos) << e.what();
    }
}

TEST(Settings, EpsDefaultFollowsTheCriterion) {
    EXPECT_EQ(app::SceneSettings{}.render.eps,
              octree::defaultEps(app::SceneSettings{}.render.boundingBoxCriterion));
    EXPECT_EQ(render::Settings{}.eps, octree::defaultEps(render::Settings{}.boundingBoxCriterion));
    EXPECT_EQ(octree::Criterion{}.eps, octree::defaultEps(octree::Criterion{}.boundingBox));
}

TEST(Settings, ReadmeStatesTheDefaults) {
    std::ifstream in(std::string(BW_SOURCE_ROOT) + "/README.md");
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_NE(text.str().find(app::defaultsTable()), std::string::npos)
        << "README.md's defaults table differs from `bssrdf-workbench defaults`:\n"
        << app::defaultsTable();
}

} // namespace
