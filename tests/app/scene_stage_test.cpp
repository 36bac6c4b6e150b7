// The mesh rendering stage graph of app::SceneStage driven through app::Workbench (thesis 3.3):
// mesh → point cloud → octree → irradiance → progressive render. Each test builds a Workbench on
// a throwaway project root (materials/dipole.bssrdf), enables the scene at small sizes (a few
// thousand points, 64×48 pixels, 256² shadow map) and checks, with the per-stage run counters
// of SceneStage::stats(), which stages re-run for which edit (camera → render only; light →
// irradiance + render; material / model parameters → render only; point count or mesh →
// everything; nothing changed → nothing), hot reload of the model (new pixels on a good save,
// the last good frame and an Errors entry on a broken one), that every bad input keeps the
// previous scene and names the file, the traversal debugger against the GPU frame, and the
// half-resolution frames while interacting.
#include "../support/gl_fixture.h"
#include "../support/raw_exr.h"
#include "core/core.h"
#include "mesh/mesh.h"
#include "pipeline/workbench.h"
#include "pointcloud/pointcloud.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace {
namespace fs = std::filesystem;

constexpr int kWidth = 64, kHeight = 48;
constexpr size_t kPoints = 2500;

// A Workbench with the scene enabled at test sizes on a fresh project root.
struct SceneBench {
    fs::path root;
    std::unique_ptr<app::Workbench> wb;

    explicit SceneBench(const std::string& tag) {
        testsupport::context();
        root = testsupport::makeProjectRoot("scene_" + tag, {"dipole.bssrdf"});
        wb = std::make_unique<app::Workbench>(root, false);
        app::SceneSettings& s = wb->scene().settings();
        s.enabled = true;
        s.useCache = false; // never touch the user's point-cloud cache
        s.points.points = kPoints;
        s.light.shadowMapSize = 256;
        s.render.width = kWidth;
        s.render.height = kHeight;
    }
    ~SceneBench() {
        wb.reset();
        std::error_code ec;
        fs::remove_all(root, ec);
    }
    app::SceneStage& scene() { return wb->scene(); }
    app::SceneSettings& settings() { return wb->scene().settings(); }
    bssrdf::ModelEntry& entry() {
        auto* e = wb->library().find("materials/dipole.bssrdf");
        EXPECT_NE(e, nullptr);
        return *e;
    }
    // update() until the point cloud, the occluded IBL and the progressive render are done.
    void settle() {
        for (int i = 0; i < 200000; ++i) {
            wb->update();
            const app::SceneStage& sc = wb->scene();
            if (!sc.generating() && !sc.rendering() && !sc.occludedRunning()) return;
            if (sc.generating()) std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        ADD_FAILURE() << "the scene did not settle";
    }
};

// Run counters of the five stages.
struct Runs {
    long long mesh = 0, cloud = 0, octree = 0, irradiance = 0, render = 0;
};

Runs runsOf(const app::SceneStage& s) {
    auto get = [&](const char* name) -> long long {
        auto it = s.stats().find(name);
        return it == s.stats().end() ? 0 : it->second.runs;
    };
    return {get("scene.mesh"), get("scene.pointcloud"), get("scene.octree"),
            get("scene.irradiance"), get("scene.render")};
}

// Expects `after` − `before` to equal the given per-stage increments.
void expectDelta(const Runs& before, const Runs& after, long long mesh, long long cloud,
                 long long octree, long long irradiance, long long render,
                 const std::string& what) {
    EXPECT_EQ(after.mesh - before.mesh, mesh) << what << ": scene.mesh";
    EXPECT_EQ(after.cloud - before.cloud, cloud) << what << ": scene.pointcloud";
    EXPECT_EQ(after.octree - before.octree, octree) << what << ": scene.octree";
    EXPECT_EQ(after.irradiance - before.irradiance, irradiance) << what << ": scene.irradiance";
    EXPECT_EQ(after.render - before.render, render) << what << ": scene.render";
}

std::vector<size_t> hitPixels(const render::Readback& rb) {
    std::vector<size_t> out;
    for (size_t p = 0; p < rb.position.size(); ++p)
        if (rb.position[p].w > 0.5f) out.push_back(p);
    return out;
}

// Σ over hit pixels of the radiant exitance (all channels): a frame's total.
double totalExitance(const render::Readback& rb) {
    double sum = 0;
    for (size_t p : hitPixels(rb))
        sum += double(rb.exitance[p].r) + rb.exitance[p].g + rb.exitance[p].b;
    return sum;
}

bool sameFrame(const render::Readback& a, const render::Readback& b) {
    return a.width == b.width && a.height == b.height && a.hdr == b.hdr &&
           a.exitance == b.exitance && a.ldr == b.ldr;
}

bool sameIrradiance(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin());
}

// The scene problems of wb.errors() (source "scene") joined, for messages and searches.
std::string sceneErrors(const app::Workbench& wb) {
    std::string out;
    for (const auto& e : wb.errors())
        if (e.source == "scene") out += e.text + "\n";
    return out;
}

std::string allErrors(const app::Workbench& wb) {
    std::string out;
    for (const auto& e : wb.errors())
        out += e.source + ": " + e.text + "\n";
    return out;
}

bool contains(const std::string& hay, const std::string& needle) {
    return hay.find(needle) != std::string::npos;
}

void writeText(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
}

// An OpenEXR file with the given FLOAT channels, interleaved data (w·h·channels values).

// ---- (a)–(e): which stages re-run ---------------------------------------------------------

TEST(SceneStage, EachEditReRunsOnlyTheStagesThatDependOnIt) {
    SceneBench b("graph");
    app::Workbench& wb = *b.wb;
    // Disabled (the Workbench default): update() runs no scene stage.
    b.settings().enabled = false;
    wb.update();
    EXPECT_TRUE(b.scene().stats().empty());
    EXPECT_FALSE(b.scene().hasMesh());
    EXPECT_FALSE(b.scene().hasFrame());
    b.settings().enabled = true;
    wb.finishScene();
    ASSERT_TRUE(b.scene().hasFrame()) << allErrors(wb);
    ASSERT_EQ(sceneErrors(wb), "");
    Runs r0 = runsOf(b.scene());
    expectDelta(Runs{}, r0, 1, 1, 1, 1, 1, "first finishScene");
    EXPECT_EQ(b.scene().cloud().points.size(), kPoints);
    EXPECT_EQ(b.scene().frame().width, kWidth);
    EXPECT_EQ(b.scene().frame().height, kHeight);
    const render::Readback first = b.scene().readback();
    ASSERT_GT(hitPixels(first).size(), 100u) << "the bunny should cover part of the frame";
    const std::vector<glm::vec3> irr0 = b.scene().irradiance();
    ASSERT_EQ(irr0.size(), kPoints);

    // (e) nothing changed: neither finishScene nor update re-runs anything
    wb.finishScene();
    for (int i = 0; i < 3; ++i)
        wb.update();
    expectDelta(r0, runsOf(b.scene()), 0, 0, 0, 0, 0, "nothing changed");
    EXPECT_TRUE(sameFrame(first, b.scene().readback()));

    // (a) camera motion (through update(), the interactive path): the render only — camera
    // motion never recomputes irradiance, octree or point cloud
    Runs r = runsOf(b.scene());
    b.settings().render.camera.yaw += 0.4f;
    b.settle();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "camera yaw (update)");
    const render::Readback turned = b.scene().readback();
    EXPECT_FALSE(sameFrame(first, turned)) << "a new view should give new pixels";
    EXPECT_TRUE(sameIrradiance(irr0, b.scene().irradiance()));
    r = runsOf(b.scene());
    b.settings().render.camera.pitch += 0.1f;
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "camera pitch (finishScene)");

    // (b) the light direction: irradiance and render, not point cloud / octree / mesh
    r = runsOf(b.scene());
    b.settings().light.direction = {-0.6f, 0.5f, 0.3f};
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 1, 1, "light direction");
    EXPECT_FALSE(sameIrradiance(irr0, b.scene().irradiance()))
        << "another light direction should light the points differently";
    const std::vector<glm::vec3> irr1 = b.scene().irradiance();

    // (c) material and model parameters: the render only
    r = runsOf(b.scene());
    wb.shared().params.sigmaA *= 3.0;
    wb.update(); // the effective material is computed in Workbench::update
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "sigma_a");
    r = runsOf(b.scene());
    wb.applyPreset(wb.shared(), "Skin1"); // η 1.3 like Marble: Ft(η) of E_t unchanged
    wb.update();
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "preset Skin1");
    EXPECT_TRUE(sameIrradiance(irr1, b.scene().irradiance()));

    // Multiplier scales Bssrdf() linearly: the exitance of every pixel doubles (×2 is exact in
    // floating point, so only the summation order could differ — it does not).
    const render::Readback m1 = b.scene().readback();
    r = runsOf(b.scene());
    b.entry().values["Multiplier"] = {2.0f, 2.0f, 2.0f};
    wb.update();
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "Multiplier");
    const render::Readback m2 = b.scene().readback();
    ASSERT_EQ(hitPixels(m1), hitPixels(m2));
    for (size_t p : hitPixels(m1))
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(m2.exitance[p][c], 2.0f * m1.exitance[p][c],
                        1e-5f * std::fabs(m1.exitance[p][c]))
                << "pixel " << p << " channel " << c;

    // (d) the point count: point cloud, octree, irradiance, render (the mesh stays)
    r = runsOf(b.scene());
    b.settings().points.points = 2000;
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 1, 1, 1, 1, "point count");
    EXPECT_EQ(b.scene().cloud().points.size(), 2000u);
    EXPECT_EQ(b.scene().irradiance().size(), 2000u);
    ASSERT_EQ(sceneErrors(wb), "");

    // (d) the mesh: everything; through update() (the point cloud is generated in the
    // background, the previous scene stays until it is ready)
    const std::string bunnyHash = b.scene().meshHash();
    const size_t bunnyTriangles = b.scene().mesh().triangles.size();
    const fs::path torus = b.root / "torus.obj";
    mesh::writeObj(torus, mesh::makeTorus(1.0, 0.35, 24, 12));
    r = runsOf(b.scene());
    b.settings().meshFile = torus.string();
    wb.update();
    if (b.scene().generating()) {
        // adopted only when ready: the old cloud and octree are still in place
        EXPECT_EQ(b.scene().cloud().points.size(), 2000u);
        EXPECT_EQ(runsOf(b.scene()).cloud, r.cloud);
    }
    if (b.scene().generating()) {
        const double p = b.scene().status().progress;
        EXPECT_TRUE(p >= 0 && p <= 1) << p;
    }
    b.settle();
    expectDelta(r, runsOf(b.scene()), 1, 1, 1, 1, 1, "mesh file");
    // the generation reported its relaxation to the end (the Point cloud panel's bar)
    EXPECT_EQ(b.scene().generatingProgress(), 1.0);
    EXPECT_NE(b.scene().meshHash(), bunnyHash);
    EXPECT_EQ(b.scene().mesh().triangles.size(), size_t(2 * 24 * 12));
    EXPECT_NE(b.scene().mesh().triangles.size(), bunnyTriangles);
    EXPECT_EQ(b.scene().cloud().points.size(), 2000u);
    ASSERT_EQ(sceneErrors(wb), "");

    // A new request supersedes a running generation: only the last one is adopted.
    r = runsOf(b.scene());
    b.settings().points.points = 2200;
    wb.update();
    if (b.scene().generating()) {
        b.settings().points.points = 2300;
        b.settle();
        expectDelta(r, runsOf(b.scene()), 0, 1, 1, 1, 1, "superseded point count");
        EXPECT_EQ(b.scene().cloud().points.size(), 2300u);
    } else {
        std::printf("the 2200-point cloud was ready at once: supersede not exercised\n");
        b.settle();
    }

    // and again nothing
    r = runsOf(b.scene());
    wb.finishScene();
    b.settle();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 0, "nothing changed after the mesh");
}

// ---- (f): hot reload of the model ---------------------------------------------------------

TEST(SceneStage, ModelHotReloadReRendersAndABrokenEditKeepsTheLastGoodFrame) {
    SceneBench b("reload");
    app::Workbench& wb = *b.wb;
    wb.finishScene();
    ASSERT_TRUE(b.scene().hasFrame()) << allErrors(wb);
    const fs::path file = b.root / "materials" / "dipole.bssrdf";
    const std::string original = testsupport::readText(file);
    const render::Readback before = b.scene().readback();
    const double total0 = totalExitance(before);
    ASSERT_GT(total0, 0.0);

    // A new default of Multiplier: the model reloads and the render re-runs, but the value
    // survives the reload (same name and type, bssrdf::carryOver) — same pixels.
    Runs r = runsOf(b.scene());
    writeText(file, testsupport::replaced(original, "float Multiplier 0.0 10.0 1.0",
                                          "float Multiplier 0.0 10.0 3.0"));
    wb.library().reload(file);
    wb.update();
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "new Multiplier default");
    EXPECT_FLOAT_EQ(b.entry().values.at("Multiplier")[0], 1.0f);
    EXPECT_TRUE(sameFrame(before, b.scene().readback()));

    // Changed shader text: twice the BSSRDF → twice the exitance, new pixels.
    r = runsOf(b.scene());
    const std::string doubled = testsupport::replaced(original, "return Multiplier/(4.0*PI)",
                                                      "return 2.0*Multiplier/(4.0*PI)");
    writeText(file, doubled);
    wb.reloadAll();
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "shader edit");
    const render::Readback after = b.scene().readback();
    EXPECT_FALSE(sameFrame(before, after));
    EXPECT_NEAR(totalExitance(after) / total0, 2.0, 1e-4);
    EXPECT_EQ(allErrors(wb), "");

    // A broken edit: the error names the model file and line; no re-render, same pixels.
    const std::string broken =
        testsupport::replaced(doubled, "vec3 Dr = sqrt(R + Zr*Zr);", "vec3 Dr = ;");
    const int line = testsupport::lineOf(broken, "vec3 Dr = ;");
    r = runsOf(b.scene());
    writeText(file, broken);
    wb.library().reload(file);
    wb.update();
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 0, "broken edit");
    EXPECT_TRUE(sameFrame(after, b.scene().readback())) << "the last good frame should stay";
    const std::string errors = allErrors(wb);
    EXPECT_TRUE(contains(errors, "materials/dipole.bssrdf:" + std::to_string(line)))
        << "expected an error at the broken line " << line << ", got:\n"
        << errors;

    // Fixing it again renders the good model (the original: the first frame's pixels).
    r = runsOf(b.scene());
    writeText(file, original);
    wb.reloadAll();
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "fixed");
    EXPECT_EQ(allErrors(wb), "");
    EXPECT_NEAR(totalExitance(b.scene().readback()) / total0, 1.0, 1e-5);
}

// NaN, Inf or negative radiance from the model: magenta (or black) pixels, and a count in Errors
// naming the model; gone when the model is good again.
TEST(SceneStage, InvalidPixelsFromTheModelAreCountedInErrorsNamingIt) {
    SceneBench b("invalid");
    app::Workbench& wb = *b.wb;
    wb.finishScene();
    ASSERT_TRUE(b.scene().hasFrame()) << allErrors(wb);
    EXPECT_FALSE(b.scene().frame().invalid.any());
    const uint32_t surface = b.scene().frame().invalid.surface;
    EXPECT_GT(surface, 0u);
    const fs::path file = b.root / "materials" / "dipole.bssrdf";
    const std::string original = testsupport::readText(file);
    writeText(file, testsupport::replaced(original, "return Multiplier/(4.0*PI)",
                                          "return sqrt(-1.0 - R)*Multiplier/(4.0*PI)"));
    wb.reloadAll();
    wb.finishScene();
    const render::InvalidPixels n = b.scene().frame().invalid;
    EXPECT_EQ(n.nan, surface);
    EXPECT_EQ(n.surface, surface);
    const std::string errors = allErrors(wb);
    EXPECT_TRUE(contains(errors, "render values: materials/dipole.bssrdf: L_o is NaN at " +
                                     std::to_string(surface) + " of " + std::to_string(surface) +
                                     " surface pixels (magenta)"))
        << errors;
    // negative values: counted too (they show black)
    writeText(file, testsupport::replaced(original, "return Multiplier/(4.0*PI)",
                                          "return -Multiplier/(4.0*PI)"));
    wb.reloadAll();
    wb.finishScene();
    EXPECT_EQ(b.scene().frame().invalid.negative, surface);
    EXPECT_TRUE(contains(allErrors(wb), "L_o is negative at " + std::to_string(surface)))
        << allErrors(wb);
    writeText(file, original);
    wb.reloadAll();
    wb.finishScene();
    EXPECT_FALSE(b.scene().frame().invalid.any());
    EXPECT_EQ(allErrors(wb), "");
}

// ---- (g): bad inputs keep the previous scene ----------------------------------------------

TEST(SceneStage, BadInputsKeepThePreviousSceneAndNameTheFile) {
    SceneBench b("bad");
    app::Workbench& wb = *b.wb;
    wb.finishScene();
    ASSERT_TRUE(b.scene().hasFrame()) << allErrors(wb);
    ASSERT_EQ(sceneErrors(wb), "");
    const std::string hash = b.scene().meshHash();
    const size_t points = b.scene().cloud().points.size();
    const render::Readback frame = b.scene().readback();
    const Runs r0 = runsOf(b.scene());

    auto expectKept = [&](const std::string& what) {
        EXPECT_EQ(b.scene().meshHash(), hash) << what;
        EXPECT_EQ(b.scene().cloud().points.size(), points) << what;
        EXPECT_TRUE(sameFrame(frame, b.scene().readback())) << what << ": the frame changed";
    };

    // Bad meshes: (file name, contents).
    std::string garbage;
    {
        std::mt19937 rng(7);
        for (int i = 0; i < 4096; ++i)
            garbage.push_back(char(rng() & 0xff));
    }
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"empty.obj", ""},
        {"garbage.obj", garbage},
        {"malformed.obj", "v 0 0 0\nv 1 zero 0\nv 0 1 0\nf 1 2 3\n"},
        {"out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"},
        {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n"},
        {"points_only.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n"},
        {"no_area.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 2 3 4\n"},
    };
    std::vector<std::string> files = {(b.root / "missing.obj").string()};
    for (const auto& [name, text] : bad) {
        writeText(b.root / name, text);
        files.push_back((b.root / name).string());
    }
    for (const auto& f : files) {
        SCOPED_TRACE(f);
        b.settings().meshFile = f;
        wb.update();
        wb.finishScene();
        const std::string errors = sceneErrors(wb);
        EXPECT_TRUE(contains(errors, f)) << "expected a scene problem naming " << f << ", got:\n"
                                         << allErrors(wb);
        expectKept(f);
    }
    expectDelta(r0, runsOf(b.scene()), 0, 0, 0, 0, 0, "bad meshes");

    // Back to the good mesh: the problem goes away.
    b.settings().meshFile = "third_party/bunny/bunny.obj";
    wb.finishScene();
    EXPECT_EQ(sceneErrors(wb), "");
    EXPECT_EQ(b.scene().meshHash(), hash);
    const render::Readback frame2 = b.scene().readback();
    const size_t points2 = b.scene().cloud().points.size();
    const Runs r1 = runsOf(b.scene());

    // Bad point counts: a clear problem, the old cloud stays.
    struct BadCount {
        size_t points, cap;
        std::string fragment;
    };
    const size_t defaultCap = b.settings().points.memoryCapBytes;
    for (const BadCount& c :
         {BadCount{0, defaultCap, "at least 1"}, BadCount{size_t(1) << 25, defaultCap, "16777216"},
          BadCount{3000, 1024, "cap"}}) {
        SCOPED_TRACE(std::to_string(c.points) + " points, cap " + std::to_string(c.cap));
        b.settings().points.points = c.points;
        b.settings().points.memoryCapBytes = c.cap;
        wb.update();
        wb.finishScene();
        const std::string errors = sceneErrors(wb);
        EXPECT_TRUE(contains(errors, "--points") && contains(errors, c.fragment)) << "got:\n"
                                                                                  << allErrors(wb);
        EXPECT_EQ(b.scene().cloud().points.size(), points2);
        EXPECT_TRUE(sameFrame(frame2, b.scene().readback()));
    }
    expectDelta(r1, runsOf(b.scene()), 0, 0, 0, 0, 0, "bad point counts");
    b.settings().points.points = kPoints;
    b.settings().points.memoryCapBytes = defaultCap;
    wb.finishScene();
    EXPECT_EQ(sceneErrors(wb), "");
    EXPECT_EQ(b.scene().cloud().points.size(), kPoints);

    // IBL with a good environment, then bad ones: the problem names the file, the irradiance
    // of the good environment stays.
    b.settings().light.mode = irradiance::LightMode::Ibl;
    wb.finishScene();
    ASSERT_EQ(sceneErrors(wb), "");
    const std::vector<glm::vec3> irr = b.scene().irradiance();
    ASSERT_EQ(irr.size(), kPoints);
    const Runs beforeBadEnv = runsOf(b.scene());
    {
        std::mt19937 rng(11);
        std::string bytes;
        for (int i = 0; i < 2000; ++i)
            bytes.push_back(char(rng() & 0xff));
        writeText(b.root / "corrupt.exr", bytes);
    }
    testsupport::writeRawExr(b.root / "luminance.exr", 8, 4, {"Y"}, std::vector<float>(32, 1.0f));
    for (const std::string name : {"missing.exr", "corrupt.exr", "luminance.exr"}) {
        SCOPED_TRACE(name);
        b.settings().environmentFile = name; // relative to the root
        wb.update();
        wb.finishScene();
        const std::string errors = sceneErrors(wb);
        EXPECT_TRUE(contains(errors, name)) << "got:\n" << allErrors(wb);
        EXPECT_TRUE(sameIrradiance(irr, b.scene().irradiance()))
            << "the previous environment's irradiance should stay";
    }
    EXPECT_TRUE(contains(sceneErrors(wb), "no channel 'R'")) << sceneErrors(wb);
    // a file that failed to load changes nothing, so nothing re-runs
    expectDelta(beforeBadEnv, runsOf(b.scene()), 0, 0, 0, 0, 0, "bad environments");
    b.settings().environmentFile = "materials/env/default_sky.exr";
    wb.finishScene();
    EXPECT_EQ(sceneErrors(wb), "");
    EXPECT_TRUE(sameIrradiance(irr, b.scene().irradiance()));
}

// A file fixed on disk under the same name is read again on reloadFiles() (Enter in the
// panel's file field); reading unchanged content again re-runs nothing.
TEST(SceneStage, AFixedFileIsReadAgainOnReload) {
    SceneBench b("fixed");
    app::Workbench& wb = *b.wb;
    wb.finishScene();
    ASSERT_EQ(sceneErrors(wb), "");
    const std::string bunnyHash = b.scene().meshHash();
    const fs::path file = b.root / "fixme.obj";
    writeText(file, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    b.settings().meshFile = file.string();
    wb.finishScene();
    EXPECT_TRUE(contains(sceneErrors(wb), "fixme.obj")) << allErrors(wb);
    EXPECT_EQ(b.scene().meshHash(), bunnyHash);
    mesh::writeObj(file, mesh::makeTorus(0.35, 0.12, 24, 12));
    wb.finishScene(); // same name: not read again by itself
    EXPECT_TRUE(contains(sceneErrors(wb), "fixme.obj"));
    b.scene().reloadFiles();
    wb.finishScene();
    EXPECT_EQ(sceneErrors(wb), "") << allErrors(wb);
    EXPECT_NE(b.scene().meshHash(), bunnyHash);
    const Runs r = runsOf(b.scene());
    b.scene().reloadFiles(); // unchanged content
    wb.finishScene();
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 0, "reload of unchanged files");
}

// An IBL request with no environment ever loaded: a problem naming the file; the directional
// irradiance stays.
TEST(SceneStage, IblWithoutAnyGoodEnvironmentKeepsTheDirectionalIrradiance) {
    SceneBench b("noenv");
    app::Workbench& wb = *b.wb;
    wb.finishScene();
    ASSERT_TRUE(b.scene().hasFrame()) << allErrors(wb);
    const std::vector<glm::vec3> irr = b.scene().irradiance();
    const render::Readback frame = b.scene().readback();
    const Runs r = runsOf(b.scene());
    b.settings().light.mode = irradiance::LightMode::Ibl;
    b.settings().environmentFile = "materials/env/nope.exr";
    wb.finishScene();
    EXPECT_TRUE(contains(sceneErrors(wb), "materials/env/nope.exr")) << allErrors(wb);
    EXPECT_TRUE(sameIrradiance(irr, b.scene().irradiance()));
    EXPECT_TRUE(sameFrame(frame, b.scene().readback()));
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 0, "IBL without an environment");
}

// ---- (h): the traversal debugger ----------------------------------------------------------

struct DebugSummary {
    size_t compared = 0, excluded = 0;
    double worstReplicaRel = 0; // CPU replica vs GPU
    double worstBruteRel = 0;   // brute force vs GPU
    double meanBruteRel = 0;
};

DebugSummary debugPixels(app::SceneStage& scene, const std::vector<size_t>& pixels, int width) {
    DebugSummary s;
    double bruteSum = 0;
    size_t bruteCount = 0;
    for (size_t p : pixels) {
        const int x = int(p % size_t(width)), y = int(p / size_t(width));
        const app::PixelDebug d = scene.debugPixel(x, y);
        EXPECT_TRUE(d.hit) << x << "," << y;
        EXPECT_EQ(d.x, x);
        EXPECT_EQ(d.y, y);
        if (!d.hit) continue;
        // The statistics match the GPU exactly.
        EXPECT_EQ(d.gpuStats.x, uint32_t(d.trace.steps.size())) << x << "," << y;
        EXPECT_EQ(d.gpuStats.y, d.trace.maxStackDepth) << x << "," << y;
        EXPECT_EQ(d.gpuStats.z, d.trace.flags) << x << "," << y;
        EXPECT_EQ(d.gpuStats.w, uint32_t(d.trace.evaluations.size())) << x << "," << y;
        for (int c = 0; c < 3; ++c) {
            const double g = d.gpuExitance[c];
            const double brute = std::fabs(double(d.bruteExitance[c]) - g) / std::fabs(g);
            s.worstBruteRel = std::max(s.worstBruteRel, brute);
            bruteSum += brute;
            ++bruteCount;
        }
        // The CPU replica's M equals the GPU's to float rounding, unless a criterion test sat
        // within 1e-5 of its threshold (then CPU and GPU may legitimately decide differently).
        if (d.trace.closestMargin < 1e-5f) {
            ++s.excluded;
            continue;
        }
        for (int c = 0; c < 3; ++c) {
            const double cpu = d.trace.radiantExitance[c], g = d.gpuExitance[c];
            const double rel = std::fabs(cpu - g) / std::max(std::fabs(cpu), 1e-30);
            s.worstReplicaRel = std::max(s.worstReplicaRel, rel);
            EXPECT_LE(rel, 1e-5) << "pixel " << x << "," << y << " channel " << c << " cpu " << cpu
                                 << " gpu " << g;
        }
        ++s.compared;
    }
    s.meanBruteRel = bruteCount ? bruteSum / double(bruteCount) : 0;
    return s;
}

TEST(SceneStage, TraversalDebuggerReplaysGpuPixels) {
    SceneBench b("debug");
    app::Workbench& wb = *b.wb;
    // The replica's values come from Bssrdf() itself, so the GPU must call it too (a radial
    // model otherwise reads the interpolated profile table).
    b.settings().render.directBssrdf = true;
    wb.finishScene();
    ASSERT_TRUE(b.scene().hasFrame()) << allErrors(wb);
    render::Readback rb = b.scene().readback();
    const std::vector<size_t> hits = hitPixels(rb);
    ASSERT_GT(hits.size(), 100u);
    std::vector<size_t> pixels;
    for (size_t i = 0; i < hits.size(); i += hits.size() / 16)
        pixels.push_back(hits[i]);

    const DebugSummary coarse = debugPixels(b.scene(), pixels, rb.width);
    std::printf("debugger eps 0.05: %zu pixels compared, %zu excluded (margin < 1e-5), worst "
                "replica rel %.3g, brute force vs GPU: worst %.3g mean %.3g\n",
                coarse.compared, coarse.excluded, coarse.worstReplicaRel, coarse.worstBruteRel,
                coarse.meanBruteRel);
    EXPECT_GE(coarse.compared, pixels.size() / 2);
    // The hierarchy's error at eps 0.05 against the sum over every point.
    EXPECT_LT(coarse.worstBruteRel, 0.05);

    // A smaller eps opens more nodes: closer to the brute-force sum.
    b.settings().render.eps = 0.005f;
    wb.finishScene();
    rb = b.scene().readback();
    ASSERT_EQ(hitPixels(rb), hits) << "same view, same coverage";
    const DebugSummary fine = debugPixels(b.scene(), pixels, rb.width);
    std::printf("debugger eps 0.005: %zu compared, %zu excluded, worst replica rel %.3g, brute "
                "force vs GPU: worst %.3g mean %.3g\n",
                fine.compared, fine.excluded, fine.worstReplicaRel, fine.worstBruteRel,
                fine.meanBruteRel);
    EXPECT_LT(fine.meanBruteRel, coarse.meanBruteRel);
    EXPECT_LT(fine.worstBruteRel, coarse.worstBruteRel);

    // A background pixel: no hit. Outside the frame: core::Error.
    size_t miss = rb.position.size();
    for (size_t p = 0; p < rb.position.size() && miss == rb.position.size(); ++p)
        if (rb.position[p].w < 0.5f) miss = p;
    ASSERT_LT(miss, rb.position.size()) << "no background pixel";
    const app::PixelDebug bg =
        b.scene().debugPixel(int(miss % size_t(rb.width)), int(miss / size_t(rb.width)));
    EXPECT_FALSE(bg.hit);
    EXPECT_THROW(b.scene().debugPixel(kWidth, 0), core::Error);
    EXPECT_THROW(b.scene().debugPixel(0, kHeight), core::Error);
    EXPECT_THROW(b.scene().debugPixel(-1, 3), core::Error);
}

// ---- (i): half resolution while interacting -----------------------------------------------

TEST(SceneStage, HalfResolutionWhileInteractingFullAtRest) {
    SceneBench b("half");
    app::Workbench& wb = *b.wb;
    wb.finishScene();
    ASSERT_TRUE(b.scene().hasFrame()) << allErrors(wb);
    EXPECT_EQ(b.scene().frame().width, kWidth);

    Runs r = runsOf(b.scene());
    wb.setInteracting(true);
    b.settings().render.camera.yaw += 0.3f;
    b.settle();
    EXPECT_EQ(b.scene().frame().width, kWidth / 2);
    EXPECT_EQ(b.scene().frame().height, kHeight / 2);
    EXPECT_EQ(b.scene().readback().width, kWidth / 2);
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "interactive camera move");

    r = runsOf(b.scene());
    wb.setInteracting(false);
    b.settle();
    EXPECT_EQ(b.scene().frame().width, kWidth);
    EXPECT_EQ(b.scene().frame().height, kHeight);
    expectDelta(r, runsOf(b.scene()), 0, 0, 0, 0, 1, "at rest");

    // halfResolutionWhileChanging off: full size even while interacting
    b.settings().halfResolutionWhileChanging = false;
    wb.setInteracting(true);
    b.settings().render.camera.yaw += 0.3f;
    b.settle();
    EXPECT_EQ(b.scene().frame().width, kWidth);
}

} // namespace

// The brute-force comparison pass runs progressively on its own renderer: the displayed frame
// stays untouched, the result matches the hierarchical frame to the hierarchy's accuracy, and
// it stops belonging to the view once a new frame is rendered.
TEST(SceneStage, BruteForcePassRunsBesideTheDisplayedFrame) {
    SceneBench b("brute");
    app::Workbench& wb = *b.wb;
    wb.finishScene();
    ASSERT_TRUE(b.scene().hasFrame()) << allErrors(wb);
    const render::Readback frame = b.scene().readback();
    b.scene().comparison().requestBruteForce();
    int updates = 0;
    while (b.scene().comparison().running() && updates < 100000) {
        wb.update();
        ++updates;
    }
    EXPECT_GT(updates, 1) << "the pass should be spread over several updates";
    const std::vector<glm::vec4>* brute = b.scene().comparison().bruteForceResult();
    ASSERT_NE(brute, nullptr) << allErrors(wb);
    ASSERT_EQ(brute->size(), frame.exitance.size());
    EXPECT_TRUE(sameFrame(frame, b.scene().readback())) << "the displayed frame changed";
    double num = 0, den = 0;
    for (size_t p : hitPixels(frame))
        for (int c = 0; c < 3; ++c) {
            const double d = double(frame.exitance[p][c]) - double((*brute)[p][c]);
            num += d * d;
            den += double((*brute)[p][c]) * double((*brute)[p][c]);
        }
    ASSERT_GT(den, 0);
    // default settings: bounding-box criterion, eps 4, second-order clusters (~0.5 % on the
    // bench scene); a coarse cloud of kPoints points is allowed 2 %
    EXPECT_LT(std::sqrt(num / den), 0.02);
    b.settings().render.camera.yaw += 0.2f;
    wb.finishScene();
    EXPECT_EQ(b.scene().comparison().bruteForceResult(), nullptr);
}

// A point cloud loaded directly from a PLY file replaces the generated one (same points in, same
// octree out); a malformed PLY names the file and keeps the previous cloud.
TEST(SceneStage, PointCloudLoadsDirectlyFromPly) {
    SceneBench b("ply");
    app::Workbench& wb = *b.wb;
    wb.finishScene();
    ASSERT_EQ(sceneErrors(wb), "");
    pointcloud::PointCloud mine = pointcloud::sampleUniform(b.scene().mesh(), 1234, 77);
    const fs::path ply = b.root / "mine.ply";
    pointcloud::writePly(ply, mine);
    const Runs r0 = runsOf(b.scene());
    b.settings().pointCloudFile = ply.string();
    wb.finishScene();
    ASSERT_EQ(sceneErrors(wb), "") << allErrors(wb);
    expectDelta(r0, runsOf(b.scene()), 0, 1, 1, 1, 1, "PLY loaded");
    ASSERT_EQ(b.scene().cloud().points.size(), 1234u);
    EXPECT_EQ(b.scene().cloud().points[17].p[0], mine.points[17].p[0]);
    EXPECT_EQ(b.scene().tree()->stats.points, 1234u);

    writeText(b.root / "bad.ply", "ply\nformat ascii 1.0\nend_header\n");
    const Runs r1 = runsOf(b.scene());
    b.settings().pointCloudFile = (b.root / "bad.ply").string();
    wb.finishScene();
    EXPECT_TRUE(contains(sceneErrors(wb), "bad.ply")) << allErrors(wb);
    EXPECT_EQ(b.scene().cloud().points.size(), 1234u);
    expectDelta(r1, runsOf(b.scene()), 0, 0, 0, 0, 0, "bad PLY");
}

// The point-cloud panel's readout: M at an arbitrary surface point by the replica. At a frame
// pixel's surface point it equals the GPU's value there; at a cloud point it is positive.
TEST(SceneStage, ExitanceAtASurfacePointMatchesTheFrame) {
    SceneBench b("exitance");
    app::Workbench& wb = *b.wb;
    EXPECT_THROW(b.scene().exitanceAt({0, 0, 0}, {0, 0, 1}), core::Error); // nothing yet
    // the replica's values come from Bssrdf() itself: make the frame use it too (not the
    // profile table), so both sides evaluate the same function
    b.settings().render.directBssrdf = true;
    wb.finishScene();
    const render::Readback rb = b.scene().readback();
    const std::vector<size_t> hits = hitPixels(rb);
    ASSERT_FALSE(hits.empty());
    for (size_t k = 0; k < hits.size(); k += std::max<size_t>(1, hits.size() / 5)) {
        const size_t p = hits[k];
        const glm::vec3 m =
            b.scene().exitanceAt(glm::vec3(rb.position[p]), glm::vec3(rb.normal[p]));
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(m[c], rb.exitance[p][c], 1e-5 * std::fabs(rb.exitance[p][c]) + 1e-12)
                << "pixel " << p << " channel " << c;
    }
    const auto& pt = b.scene().cloud().points[42];
    const glm::vec3 m =
        b.scene().exitanceAt({pt.p[0], pt.p[1], pt.p[2]}, {pt.n[0], pt.n[1], pt.n[2]});
    for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(std::isfinite(m[c]));
        EXPECT_GT(m[c], 0.0f);
    }
}
