// Settings descriptions (core/fields.h) of every workbench settings struct: each member is
// described (or skipped on purpose), JSON round-trips every described member, the cache key
// covers every member, bad JSON names its path, the CLI's defaults are the GUI's, and the
// README's defaults table is the program's.
#include "captures/settings_json.h"
#include "cli/defaults_command.h"
#include "cli/options.h"
#include "cli/pointcloud_command.h"
#include "cli/render_command.h"
#include "cli/slab_command.h"
#include "pipeline/workbench.h"

#include "core/fields.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace {

// Changes the leaf members of a settings struct to values other than their defaults: every
// one (only = -1) or only the one with that index (in forEachField order).
template <class T> size_t perturb(T& s, long only = -1) {
    size_t index = 0;
    core::forEachField(s, [&](const std::string&, auto& m, const char*, core::Limits lim) {
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
            // a change that stays inside the member's limits
            if constexpr (std::is_integral_v<M>)
                m = double(m) + 1 <= lim.hi ? M(m + 1) : M(m - 1);
            else
                m = lim.hi > m ? M(m + std::min(1.0, (lim.hi - m) / 2))
                               : M(m - std::min(1.0, (m - lim.lo) / 2));
        } else if constexpr (std::is_same_v<M, std::string>) {
            m += "x";
        } else {
            for (int c = 0; c < 3; ++c) { // distinct changes inside the limits
                const double step = 0.5 + c;
                m[c] = lim.hi > m[c] ? m[c] + std::min(step, (lim.hi - m[c]) / (2 + c))
                                     : m[c] - std::min(step, (m[c] - lim.lo) / (2 + c));
            }
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

std::string errorOf(const nlohmann::json& j) {
    try {
        app::SceneSettings s;
        core::fromJson(j, s, "manifest.json", "settings.scene");
    } catch (const core::Error& e) {
        return e.what();
    }
    return "";
}

// Every default lies inside its own limits (one range per setting, shared by the GUI, the CLI
// and captures), and the JSON reader refuses a value outside them naming the path and range.
template <class T> void expectDefaultsWithinLimits(const char* name) {
    SCOPED_TRACE(name);
    T s{};
    core::forEachField(s, [&](const std::string& path, auto& m, const char*, core::Limits lim) {
        EXPECT_EQ(core::limitProblem(m, lim), "") << path;
    });
    // and the description survives a JSON round trip through the checking reader
    T back{};
    EXPECT_NO_THROW(core::fromJson(core::toJson(s), back, "test", "s"));
}

TEST(Settings, DefaultsLieWithinTheirLimits) {
    expectDefaultsWithinLimits<render::Camera>("render::Camera");
    expectDefaultsWithinLimits<render::Settings>("render::Settings");
    expectDefaultsWithinLimits<irradiance::Settings>("irradiance::Settings");
    expectDefaultsWithinLimits<pointcloud::GenerateOptions>("pointcloud::GenerateOptions");
    expectDefaultsWithinLimits<pathtrace::Termination>("pathtrace::Termination");
    expectDefaultsWithinLimits<pathtrace::SlabSettings>("pathtrace::SlabSettings");
    expectDefaultsWithinLimits<pathtrace::EstimateSettings>("pathtrace::EstimateSettings");
    expectDefaultsWithinLimits<material::MaterialParams>("material::MaterialParams");
    expectDefaultsWithinLimits<app::MaterialSettings>("app::MaterialSettings");
    expectDefaultsWithinLimits<app::PlotSettings>("app::PlotSettings");
    expectDefaultsWithinLimits<app::ReferenceSettings>("app::ReferenceSettings");
    expectDefaultsWithinLimits<app::LitSphereSettings>("app::LitSphereSettings");
    expectDefaultsWithinLimits<app::SliceSettings>("app::SliceSettings");
    expectDefaultsWithinLimits<app::SceneSettings>("app::SceneSettings");
}

TEST(Settings, LimitsAreCheckedWhenReadAndNamed) {
    EXPECT_EQ(core::limitProblem(5, core::Limits{1, 10}), "");
    EXPECT_EQ(core::limitProblem(0, core::Limits{1, 10}), "must be between 1 and 10, got 0");
    EXPECT_EQ(core::limitProblem(-2.5, core::Limits{0}), "must be at least 0, got -2.5");
    EXPECT_NE(core::limitProblem(std::nan(""), core::Limits{}).find("finite"), std::string::npos);
    EXPECT_NE(core::limitProblem(float(INFINITY), core::Limits{}).find("finite"),
              std::string::npos);
    EXPECT_NE(core::limitProblem(glm::vec3(1, -1, 1), core::Limits{0, 2}).find("component 1"),
              std::string::npos);
    EXPECT_EQ(core::limitsOf<app::PlotSettings>("samples").lo, 2.0);
    EXPECT_EQ(core::limitsOf<app::SceneSettings>("render.width").hi, 8192.0);

    using nlohmann::json;
    std::string e = errorOf(json::parse(R"({"render": {"width": 0}})"));
    EXPECT_NE(e.find("settings.scene.render.width: must be between 1 and 8192, got 0"),
              std::string::npos)
        << e;
    e = errorOf(json::parse(R"({"points": {"count": 100000000}})"));
    EXPECT_NE(e.find("settings.scene.points.count: must be between 1 and 16777216"),
              std::string::npos)
        << e;
    // a number beyond float's range is refused, not read as infinity
    e = errorOf(json::parse(R"({"render": {"camera": {"yaw": 1e300}}})"));
    EXPECT_NE(e.find("settings.scene.render.camera.yaw: number 1e+300 out of range"),
              std::string::npos)
        << e;
    e = errorOf(json::parse(R"({"light": {"irradiance": [1, -1, 1]}})"));
    EXPECT_NE(e.find("settings.scene.light.irradiance: component 1 must be between 0"),
              std::string::npos)
        << e;
    // the plot's samples: the CLI's and the GUI's range, checked for captures too
    app::PlotSettings p;
    EXPECT_THROW(core::fromJson(json::parse(R"({"samples": 1})"), p, "m", "settings.plot"),
                 core::Error);
    EXPECT_THROW(core::fromJson(json::parse(R"({"samples": 2000000000})"), p, "m", "s"),
                 core::Error);
    EXPECT_NO_THROW(core::fromJson(json::parse(R"({"samples": 2})"), p, "m", "s"));
}

TEST(Settings, RenderKeySeesTheBackground) {
    render::Settings a, b;
    b.background.x += 0.25f;
    EXPECT_NE(core::keyOf(a), core::keyOf(b));
    EXPECT_EQ(core::keyOf(a), core::keyOf(render::Settings{}));
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
                   "--roulette-survival 0.25 --exit-samples 5 --exit-depth 0.5",
                   false);
        EXPECT_EQ(b.settings.exits.samples, 5);
        EXPECT_EQ(b.settings.exits.depthMfp, 0.5);
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
