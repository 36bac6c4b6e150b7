// Hot reload by dependency: a changed file rebuilds exactly the programs whose recorded files
// (shader::Record) list it — templates, #include'd files, shaders/common/* — counted per
// program through Workbench::shaderPrograms(). Adding an include makes the new file a
// dependency; renaming an include leaves the old name out.
#include "../support/gl_fixture.h"
#include "../support/small_scene.h"
#include "pipeline/workbench.h"

#include <fstream>
#include <thread>

using testsupport::replaced;

namespace {
namespace fs = std::filesystem;

std::map<std::string, long long> builds(const app::Workbench& wb) {
    std::map<std::string, long long> out;
    for (const auto& [name, record] : wb.shaderPrograms())
        out[name] = record.builds;
    return out;
}

// The programs whose count went up, with how much.
std::map<std::string, long long> rebuilt(const std::map<std::string, long long>& before,
                                         const std::map<std::string, long long>& after) {
    std::map<std::string, long long> out;
    for (const auto& [name, n] : after) {
        auto it = before.find(name);
        const long long was = it == before.end() ? 0 : it->second;
        if (n != was) out[name] = n - was;
    }
    return out;
}

// Editor-style save: a temporary renamed over the file.
void save(const fs::path& file, const std::string& text) {
    const fs::path tmp = file.parent_path() / ("." + file.filename().string() + ".swp");
    std::ofstream(tmp, std::ios::binary) << text;
    fs::rename(tmp, file);
}

// Updates until the build counts change and then stay put for 300 ms (debounce 40 ms), or
// for 1.5 s when nothing changes.
std::map<std::string, long long> settleBuilds(app::Workbench& wb) {
    const auto start = builds(wb);
    auto last = start;
    core::Stopwatch total, quiet;
    while (total.ms() < 8000) {
        wb.update();
        const auto now = builds(wb);
        if (now != last) {
            last = now;
            quiet.reset();
        }
        if (last != start && quiet.ms() > 300) break;
        if (last == start && total.ms() > 1500) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return rebuilt(start, last);
}

std::set<std::string> dependents(const app::Workbench& wb, const fs::path& file) {
    std::set<std::string> out;
    for (const auto& [name, record] : wb.shaderPrograms())
        if (record.dependencies.contains(file)) out.insert(name);
    return out;
}

std::map<std::string, long long> once(const std::set<std::string>& names) {
    std::map<std::string, long long> out;
    for (const auto& n : names)
        out[n] = 1;
    return out;
}
} // namespace

TEST(HotReloadDependencies, ExactlyTheProgramsThatReadAFileRebuild) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("deps", {"dipole.bssrdf"});
    app::Workbench wb(root, true);
    ASSERT_TRUE(wb.watching());
    app::SceneSettings& s = wb.scene().settings();
    s.enabled = true;
    testsupport::useSmallScene(s);
    wb.finishScene();
    wb.update();
    const auto programs = wb.shaderPrograms();
    const std::string model = "model:materials/dipole.bssrdf:";
    for (const char* p : {"pencil_profile.comp", "invert_rdr.comp", "sphere_bssrdf.comp"})
        ASSERT_TRUE(programs.count(model + p)) << p;
    for (const char* p : {"render:render_gbuffer", "render:render_tonemap.comp",
                          "render:octree_render.comp", "irradiance:irradiance_direct.comp"})
        ASSERT_TRUE(programs.count(p)) << p;

    // 1. a common file: its includers, and only they, rebuild once each
    const fs::path prelude = root / "shaders/common/bssrdf_prelude.glsl";
    const auto users = dependents(wb, prelude);
    EXPECT_TRUE(users.count(model + "pencil_profile.comp"));
    EXPECT_TRUE(users.count("render:octree_render.comp"));
    EXPECT_FALSE(users.count("render:render_tonemap.comp"));
    EXPECT_LT(users.size(), programs.size());
    save(prelude, testsupport::readText(prelude) + "// edited\n");
    EXPECT_EQ(settleBuilds(wb), once(users));

    // 2. an #include added to a template: the template's program rebuilds, and the new file
    //    becomes its dependency (editing it rebuilds that program alone)
    const fs::path extra = root / "shaders/common/extra_test.glsl";
    const fs::path tonemap = root / "shaders/render_tonemap.comp";
    const std::string tonemapText = testsupport::readText(tonemap);
    std::ofstream(extra, std::ios::binary) << "const float kExtraTest = 1.0;\n";
    EXPECT_TRUE(settleBuilds(wb).empty()); // nobody reads it yet
    const std::string withInclude =
        replaced(tonemapText, "\n", "\n#include \"common/extra_test.glsl\"\n");
    save(tonemap, withInclude);
    EXPECT_EQ(settleBuilds(wb), once({"render:render_tonemap.comp"}));
    EXPECT_EQ(dependents(wb, extra), std::set<std::string>{"render:render_tonemap.comp"});
    save(extra, "const float kExtraTest = 2.0;\n");
    EXPECT_EQ(settleBuilds(wb), once({"render:render_tonemap.comp"}));
    EXPECT_TRUE(wb.scene().problems().empty());

    // 3. the include renamed: the old name is no longer a dependency of anything
    const fs::path renamed = root / "shaders/common/extra_renamed.glsl";
    fs::rename(extra, renamed);
    save(tonemap, replaced(withInclude, "extra_test.glsl", "extra_renamed.glsl"));
    const auto afterRename = settleBuilds(wb);
    EXPECT_EQ(afterRename.count("render:render_tonemap.comp"), 1u);
    EXPECT_TRUE(dependents(wb, extra).empty());
    EXPECT_EQ(dependents(wb, renamed), std::set<std::string>{"render:render_tonemap.comp"});
    std::ofstream(extra, std::ios::binary) << "const float kExtraTest = 3.0;\n";
    EXPECT_TRUE(settleBuilds(wb).empty());
    save(renamed, "const float kExtraTest = 4.0;\n");
    EXPECT_EQ(settleBuilds(wb), once({"render:render_tonemap.comp"}));
    EXPECT_TRUE(wb.scene().problems().empty());
    fs::remove_all(root);
}

// The GL path tracers take part too: a common file both read rebuilds the reference's and the
// GPU lit sphere's programs once each and nothing else; the sphere tracer's own template
// rebuilds only its program.
TEST(HotReloadDependencies, GpuTracersRebuildForTheirOwnFiles) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("depsgpu", {"dipole.bssrdf"});
    app::Workbench wb(root, true);
    ASSERT_TRUE(wb.watching());
    auto& rs = wb.referenceSettings();
    rs.enabled = true;
    rs.device = app::TracerDevice::Gpu;
    rs.paths = 2000;
    rs.bins = 10;
    auto& ls = wb.litSphereSettings();
    ls.enabled = true;
    ls.gpu = true;
    ls.size = 8;
    ls.pathSpp = 1;
    ls.integratedSpp = 1;
    wb.update();
    wb.finishReference();
    wb.finishLitSpheres();
    wb.update();
    auto startsWith = [](const std::string& s, const char* p) { return s.rfind(p, 0) == 0; };
    const fs::path scatter = root / "shaders/common/pathtrace_scatter.glsl";
    const auto users = dependents(wb, scatter);
    int reference = 0, sphere = 0;
    for (const auto& n : users) {
        reference += startsWith(n, "reference:");
        sphere += startsWith(n, "lit sphere:");
        EXPECT_TRUE(startsWith(n, "reference:") || startsWith(n, "lit sphere:")) << n;
    }
    EXPECT_GE(reference, 1);
    EXPECT_EQ(sphere, 1);
    save(scatter, testsupport::readText(scatter) + "// edited\n");
    EXPECT_EQ(settleBuilds(wb), once(users));

    const fs::path sphereShader = root / "shaders/pathtrace_sphere.comp";
    const auto own = dependents(wb, sphereShader);
    ASSERT_EQ(own.size(), 1u);
    EXPECT_TRUE(startsWith(*own.begin(), "lit sphere:"));
    save(sphereShader, testsupport::readText(sphereShader) + "// edited\n");
    EXPECT_EQ(settleBuilds(wb), once(own));
    for (const auto& e : wb.errors())
        ADD_FAILURE() << e.source << ": " << e.text;
    fs::remove_all(root);
}
