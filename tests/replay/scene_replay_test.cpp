// Captures of the mesh pipeline (app/pipeline/scene_capture.cpp, texspace_stage.cpp): what a
// replay reads as recorded (the point cloud from the cache, the irradiance as its factors E_u and
// V, the G-buffer, the hybrid's local term) and what it allows another driver's samplers and
// rasterisers (shadow maps drawn elsewhere, vertices snapped apart, the light-view map's taps),
// each shown to pass what it should and to fail what it should not (captures/README.md,
// Tolerances and Recorded inputs).
#include "../support/gl_fixture.h"
#include "capture/capture.h"
#include "captures/capture_io.h"
#include "pathtrace/image_io.h"
#include "pointcloud/pointcloud.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>

namespace {
namespace fs = std::filesystem;

// The scene on with `points` points and a width × height render.
app::SceneSettings& sceneOn(app::Workbench& wb, size_t points, int width, int height) {
    app::SceneSettings& s = wb.scene().settings();
    s.enabled = true;
    s.points.points = points;
    s.render.width = width;
    s.render.height = height;
    return s;
}
// The texture-space renderer on at K texels per side, N draws a set and `sets` sets.
app::TextureSpaceSettings& textureSpaceOn(app::Workbench& wb, int k, int n, int sets) {
    app::TextureSpaceSettings& ts = wb.textureSpaceSettings();
    ts.enabled = true;
    ts.sampling.textureSize = k;
    ts.sampling.samples = n;
    ts.sampling.sampleSets = sets;
    return ts;
}
// The scene (1 500 points, 48 × 27) and its texture-space render with the hybrid (64² texels,
// 256 draws, 2 sets, a 256² light-view map), computed; the render's pipeline.
texspace::Pipeline& hybridOn(app::Workbench& wb) {
    sceneOn(wb, 1500, 48, 27);
    app::TextureSpaceSettings& ts = textureSpaceOn(wb, 64, 256, 2);
    ts.sampling.hybrid = true;
    ts.sampling.local.lightMapSize = 256;
    wb.update();
    wb.finishScene();
    wb.finishTextureSpace();
    return *wb.textureSpace().pipeline();
}
// The hybrid's render begun again with the workbench's settings and run to the end (what its
// pipeline was told since is taken).
void renderHybridAgain(app::Workbench& wb) {
    texspace::Pipeline& p = *wb.textureSpace().pipeline();
    p.begin(wb.textureSpaceSettings().sampling, wb.scene().settings().render);
    while (!p.advance(1e30)) {
    }
}
// Occluded image based lighting of K = 32 samples with 256² shadow maps (two steps).
void occludedLightOn(irradiance::Settings& light) {
    light.mode = irradiance::LightMode::OccludedIbl;
    light.shadowMapSize = 256;
    light.occludedTotalSamples = 32;
    light.occludedSamplesPerStep = 16;
}
// The report's line that starts with `start` ("PASS scene.render  "), "" when there is none.
std::string lineOf(const std::string& out, const std::string& start) {
    const size_t at = out.find(start);
    return at == std::string::npos ? std::string() : out.substr(at, out.find('\n', at) - at);
}
// Writes `t` as the recorded table of `stage` (its hash in `m`) and the manifest.
void plantTable(const fs::path& dir, capture::Manifest& m, const std::string& stage,
                const capture::Table& t) {
    for (capture::StageOutput& o : m.outputs)
        if (o.stage == stage)
            o = capture::writeCsvStage(dir, o.stage, o.file, t, o.absTol, o.relTol, o.tolNote);
    capture::writeManifest(dir, m);
}
// Writes `m` with each recorded image input that `which` picks replaced by a width × height image
// (its file rewritten, its hash in the manifest updated): a recorded input of another size.
void plantImageInputs(const fs::path& dir, capture::Manifest m, int width, int height,
                      const std::function<bool(const capture::StageOutput&)>& which) {
    pathtrace::Image image;
    image.width = width;
    image.height = height;
    image.samples = 1;
    image.mean.assign(size_t(3 * width * height), 0.5f);
    image.variance.assign(size_t(3 * width * height), 0.0f);
    for (capture::StageOutput& o : m.outputs)
        if (which(o)) {
            pathtrace::writeExr(dir / o.file, image);
            o.hash = capture::hashFile(dir / o.file);
        }
    capture::writeManifest(dir, m);
}
// E_t = E_u · V per row of the scene's recorded factors, in float as the shader forms it.
std::vector<glm::vec3> productOf(const capture::Table& eu, const capture::Table& v) {
    std::vector<glm::vec3> et;
    for (size_t i = 0; i < eu.rows.size(); ++i)
        et.push_back(glm::vec3(float(eu.rows[i][1]), float(eu.rows[i][2]), float(eu.rows[i][3])) *
                     float(v.rows[i][1]));
    return et;
}
// The manifest without the outputs of `stages` (as a capture recorded before they existed).
capture::Manifest without(capture::Manifest m, const std::vector<std::string>& stages) {
    m.outputs.erase(std::remove_if(m.outputs.begin(), m.outputs.end(),
                                   [&](const capture::StageOutput& o) {
                                       return std::find(stages.begin(), stages.end(), o.stage) !=
                                              stages.end();
                                   }),
                    m.outputs.end());
    return m;
}
} // namespace

// A capture recorded with the point cloud read from the cache (the GUI's default, useCache on)
// replays PASS: a cloud read back from the cache is bitwise the cloud generated (triangles
// included), and replay generates its own instead of reading the cache.
TEST(CaptureReplay, SceneRecordedFromTheCacheReplays) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("cached_cloud", {"dipole.bssrdf"});
    const char* before = std::getenv("BSSRDF_WORKBENCH_CACHE");
    const std::string saved = before ? before : "";
    ::setenv("BSSRDF_WORKBENCH_CACHE", (root / "cache").c_str(), 1);
    auto sceneOn = [](app::Workbench& wb) {
        app::SceneSettings& s = wb.scene().settings();
        s.enabled = true;
        s.useCache = true;
        s.points.points = 3000;
        s.render.width = 64;
        s.render.height = 36;
    };
    {
        app::Workbench first(root, false);
        sceneOn(first);
        first.finishScene();
        EXPECT_FALSE(first.scene().cloudFromCache()); // generated, and written to the cache
    }
    app::Workbench wb(root, false);
    sceneOn(wb);
    wb.finishScene();
    EXPECT_TRUE(wb.scene().cloudFromCache());
    const fs::path dir = root / "captures" / "cached";
    app::recordCaptureTo(wb, dir, "cached", 32, 18);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("PASS scene.pointcloud"), std::string::npos) << out;
    {
        // the replay's workbench generates the cloud though this machine's cache holds it
        int traceX = -1, traceY = -1;
        const app::ExternalModels external;
        auto replayed = app::workbenchFromInputs(capture::readManifest(dir), root, external.dir,
                                                 dir.string(), traceX, traceY);
        EXPECT_FALSE(replayed->scene().settings().useCache);
        replayed->finishScene();
        EXPECT_FALSE(replayed->scene().cloudFromCache());
    }
    if (before)
        ::setenv("BSSRDF_WORKBENCH_CACHE", saved.c_str(), 1);
    else
        ::unsetenv("BSSRDF_WORKBENCH_CACHE");
    fs::remove_all(root);
}

// Under a directional light a capture records E_t = E_u · V as its factors, each with its own
// tolerance (captures/README.md, Tolerances): the unshadowed E_u and the visibility V. A capture
// recorded before that split (its E_t as `scene.irradiance`) still replays, and its E_t made here
// from the factors passes at E_t's own 1e-5: the factors multiply back to what the shader
// computes. V's tolerance can fail: a point moved by 0.02 is named.
TEST(CaptureReplay, IrradianceIsRecordedAsItsFactorsAndOlderCapturesStillReplay) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("factors", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    sceneOn(wb, 1500, 48, 27);
    wb.finishScene();
    const fs::path dir = root / "captures" / "factors";
    app::recordCaptureTo(wb, dir, "factors", -1, -1);
    capture::Manifest m = capture::readManifest(dir);
    auto has = [&](const std::string& stage) {
        return std::any_of(m.outputs.begin(), m.outputs.end(),
                           [&](const capture::StageOutput& o) { return o.stage == stage; });
    };
    ASSERT_TRUE(has("scene.irradiance_unshadowed"));
    ASSERT_TRUE(has("scene.visibility"));
    EXPECT_FALSE(has("scene.irradiance"));
    std::string out;
    ASSERT_EQ(app::replayCapture(dir, root, false, out), 0) << out;

    const capture::Table eu = capture::readCsv(dir / "scene_irradiance_unshadowed.csv");
    capture::Table v = capture::readCsv(dir / "scene_visibility.csv");
    ASSERT_EQ(eu.rows.size(), v.rows.size());
    capture::Table et = eu;
    size_t lit = eu.rows.size();
    for (size_t i = 0; i < et.rows.size(); ++i) {
        for (int c = 1; c <= 3; ++c)
            et.rows[i][size_t(c)] = double(float(eu.rows[i][size_t(c)]) * float(v.rows[i][1]));
        if (lit == eu.rows.size() && v.rows[i][1] == 1.0 && eu.rows[i][2] > 0) lit = i;
    }
    ASSERT_LT(lit, eu.rows.size()) << "no lit point";

    // The same capture as recorded before the split: E_t in place of its factors.
    capture::Manifest old = without(m, {"scene.irradiance_unshadowed", "scene.visibility"});
    old.outputs.push_back(capture::writeCsvStage(dir, "scene.irradiance", "scene_irradiance.csv",
                                                 et, 1e-7, 1e-5, "E_t, recorded whole"));
    fs::remove(dir / "scene_irradiance_unshadowed.csv");
    fs::remove(dir / "scene_visibility.csv");
    capture::writeManifest(dir, old);
    ASSERT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("PASS scene.irradiance "), std::string::npos) << out;

    // Back to the factors, with one lit point's V moved by 0.02 (2.6× V's 2^-7; a lit point away
    // from the shadow's edges, where no shadow map drawn 1/16 texel aside moves V).
    fs::remove(dir / "scene_irradiance.csv");
    v.rows[lit][1] -= 0.02;
    capture::Manifest moved = m;
    for (capture::StageOutput& o : moved.outputs) {
        if (o.stage == "scene.irradiance_unshadowed")
            o = capture::writeCsvStage(dir, o.stage, o.file, eu, o.absTol, o.relTol, o.tolNote);
        if (o.stage == "scene.visibility")
            o = capture::writeCsvStage(dir, o.stage, o.file, v, o.absTol, o.relTol, o.tolNote);
    }
    capture::writeManifest(dir, moved);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL scene.visibility  1 of"), std::string::npos) << out;
    EXPECT_NE(out.find("PASS scene.irradiance_unshadowed"), std::string::npos) << out;
    fs::remove_all(root);
}

// Under filtered light E_u carries the projected texture T(uv), which the shader filters in float
// from a uv another driver rounds a few ulp apart: the capture allows E_u that spread
// (irradiance::Stage::unshadowedSpread) on top of float arithmetic's 1e-7 + 1e-5, says so in its
// note, and replays.
TEST(CaptureReplay, FilteredLightAllowsItsUnshadowedIrradianceTheProjectedTexturesSpread) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("filtered", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    app::SceneSettings& s = sceneOn(wb, 1500, 32, 18);
    s.light.mode = irradiance::LightMode::Filtered;
    wb.finishScene();
    const fs::path dir = root / "captures" / "filtered";
    app::recordCaptureTo(wb, dir, "filtered", -1, -1);
    const capture::Manifest m = capture::readManifest(dir);
    const glm::vec3 e0 = wb.scene().settings().light.irradiance;
    // the default checker: 64 texels of 1 and 0.25
    const double spread = std::max({e0.x, e0.y, e0.z}) * 2 * 64 * (8.0 / 16777216.0) * (1.0 - 0.25);
    bool found = false;
    for (const capture::StageOutput& o : m.outputs) {
        if (o.stage != "scene.irradiance_unshadowed") continue;
        found = true;
        EXPECT_NEAR(o.absTol, 1e-7 + spread, 1e-12);
        EXPECT_EQ(o.relTol, 1e-5);
        EXPECT_NE(o.tolNote.find("the projected texture's weights"), std::string::npos)
            << o.tolNote;
    }
    EXPECT_TRUE(found);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("PASS scene.irradiance_unshadowed"), std::string::npos) << out;
    fs::remove_all(root);
}

// Occluded image based lighting sums K shadow-mapped samples per point, each V_k a mean of
// bilinear depth comparisons that another sampler weights up to 2^-7 apart: a replay allows each
// E_t (scene.irradiance) and E′ (texture_space.eprime) 2^-7 of its sum without shadows, made on the
// replaying machine (irradiance::Stage::occludedUnshadowed), and says so. Emulated: the capture
// holds E_t moved by 2^-8 of itself (half the least that allowance can be, 400x the 1e-5 floor)
// and the render the workbench traced from it; it replays, the render exactly (traced from the
// recorded E_t). E′ moved likewise passes; a lit point's E_t (every sample unshadowed, away from
// the shadows' edges that another rasteriser moves) moved by three times its sum's 2^-7 fails.
TEST(CaptureReplay, OccludedLightAllowsEachValueItsVisibilitiesSpread) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("occluded", {"dipole.bssrdf"});
    const fs::path dir = root / "captures" / "occluded";
    const double half = 0.5 * irradiance::kVisibilityTolerance;
    std::vector<glm::vec3> unshadowed; // U per point, at the light's own η
    capture::Table et;                 // E_t as recorded, moved by 2^-8 of itself
    {
        app::Workbench wb(root, false);
        app::SceneSettings& s = sceneOn(wb, 1500, 32, 18);
        occludedLightOn(s.light);
        textureSpaceOn(wb, 64, 16, 1);
        wb.update();
        wb.finishScene();
        wb.finishTextureSpace();
        std::vector<glm::vec3> moved = wb.scene().irradiance();
        for (glm::vec3& e : moved)
            e *= float(1 + half);
        wb.scene().setGivenIrradiance(moved);
        wb.finishScene();
        app::recordCaptureTo(wb, dir, "occluded", -1, -1);
        et = capture::readCsv(dir / "scene_irradiance.csv");
        for (size_t i = 0; i < moved.size(); ++i)
            et.rows[i] = {double(i), moved[i].x, moved[i].y, moved[i].z};
        std::vector<glm::vec3> normals;
        for (const pointcloud::Point& p : wb.scene().cloud().points)
            normals.emplace_back(p.n[0], p.n[1], p.n[2]);
        unshadowed = wb.scene().irradianceStage()->occludedUnshadowed(s.light, normals);
    }
    capture::Manifest edited = capture::readManifest(dir);
    plantTable(dir, edited, "scene.irradiance", et);
    ASSERT_EQ(et.rows.size(), unshadowed.size());
    const std::string note = "plus 2^-7 of each value's sum without shadows";

    std::string out;
    ASSERT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(lineOf(out, "PASS scene.irradiance  ").find(note), std::string::npos) << out;
    EXPECT_NE(lineOf(out, "PASS scene.render  ").find("exact match"), std::string::npos) << out;
    EXPECT_NE(out.find("NOTE scene: the octree and the render read the recorded irradiance "
                       "(scene.irradiance)"),
              std::string::npos)
        << out;

    const capture::Table ep = capture::readCsv(dir / "texture_space_eprime.csv");
    capture::Table movedE = ep;
    for (auto& row : movedE.rows)
        for (int c = 1; c <= 3; ++c)
            row[size_t(c)] *= 1 - half;
    plantTable(dir, edited, "texture_space.eprime", movedE);
    ASSERT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(lineOf(out, "PASS texture_space.eprime  ").find(note), std::string::npos) << out;
    plantTable(dir, edited, "texture_space.eprime", ep);

    size_t lit = et.rows.size();
    for (size_t i = 0; i < et.rows.size() && lit == et.rows.size(); ++i)
        if (et.rows[i][2] > 0.999 * unshadowed[i].g && unshadowed[i].g > 0) lit = i;
    ASSERT_LT(lit, et.rows.size()) << "no lit point";
    capture::Table far = et;
    far.rows[lit][2] -= 3 * irradiance::kVisibilityTolerance * unshadowed[lit].g;
    plantTable(dir, edited, "scene.irradiance", far);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL scene.irradiance  1 of 6000 values out of tolerance; worst at row " +
                       std::to_string(lit + 1)),
              std::string::npos)
        << out;
    EXPECT_NE(out.find(note), std::string::npos) << out;
    fs::remove_all(root);
}

// Under occluded image based lighting each of the K samples' shadow maps is a rasterisation that
// another driver may draw 1/16 texel elsewhere, which moves V_k at a shadow's edge by up to 1,
// far past the samplers' 2^-7: a replay adds to each E_t's allowance how far each sample's term
// moves here with its map drawn up to 1/16 texel aside (Stage::occludedRasterSpread), and says
// so. Emulated: the capture holds E_t and E′ from maps drawn (0.05, 0.03) texel aside, points of
// which lie past the samplers' allowance, and the render traced from it; it replays (the render
// exactly), texture space's E′ too; a lit point moved by half its sum fails.
TEST(CaptureReplay, OccludedLightAllowsShadowMapsRasterisedElsewhere) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("occluded_raster", {"dipole.bssrdf"});
    const fs::path dir = root / "captures" / "occluded";
    std::vector<glm::vec3> unshadowed, own;
    capture::Table et, ep; // E_t and E′ as recorded: from the moved maps
    size_t past = 0, texelsMoved = 0;
    {
        app::Workbench wb(root, false);
        app::SceneSettings& s = sceneOn(wb, 1500, 32, 18);
        occludedLightOn(s.light);
        textureSpaceOn(wb, 64, 16, 1);
        wb.update();
        wb.finishScene();
        wb.finishTextureSpace();
        irradiance::Stage& stage = *wb.scene().irradianceStage();
        own = wb.scene().irradiance();
        ASSERT_EQ(stage.occludedShifted(s.light, glm::vec2(0.0f)), own)
            << "the emulation does not reproduce the scene's own light";
        const std::vector<glm::vec3> moved = stage.occludedShifted(s.light, {0.05f, 0.03f});
        std::vector<glm::vec3> normals;
        for (const pointcloud::Point& p : wb.scene().cloud().points)
            normals.emplace_back(p.n[0], p.n[1], p.n[2]);
        unshadowed = stage.occludedUnshadowed(s.light, normals);
        for (size_t i = 0; i < own.size(); ++i)
            for (int c = 0; c < 3; ++c)
                if (std::abs(moved[i][c] - own[i][c]) >
                    irradiance::kVisibilityTolerance * unshadowed[i][c] +
                        1e-5 * std::abs(own[i][c]) + 1e-7) {
                    ++past;
                    break;
                }
        wb.scene().setGivenIrradiance(moved);
        wb.finishScene();
        app::recordCaptureTo(wb, dir, "occluded", -1, -1);
        et = capture::readCsv(dir / "scene_irradiance.csv");
        for (size_t i = 0; i < moved.size(); ++i)
            et.rows[i] = {double(i), moved[i].x, moved[i].y, moved[i].z};
        // the texture space's E′ likewise: its irradiance points are the covered texels in order
        texspace::Pipeline& tp = *wb.textureSpace().pipeline();
        const texspace::Texels& tx = tp.texels();
        const std::vector<glm::vec3> texelEt =
            tp.irradianceStage().occludedShifted(s.light, {0.05f, 0.03f});
        std::vector<size_t> point(tx.triangle.size(), 0);
        for (size_t t = 0, k = 0; t < tx.triangle.size(); ++t)
            if (tx.triangle[t] >= 0) point[t] = k++;
        ep = capture::readCsv(dir / "texture_space_eprime.csv");
        for (std::vector<double>& row : ep.rows) {
            const size_t t = size_t(row[0]);
            const glm::vec3 e = texelEt[point[t]] * float(tx.areaRatio[t]);
            texelsMoved += std::abs(e.y - row[2]) > 1e-5 * std::abs(row[2]);
            row = {double(t), e.x, e.y, e.z};
        }
    }
    std::printf("E_t from %d shadow maps drawn (0.05, 0.03) texel aside: %zu of %zu points past "
                "2^-7 of their unshadowed sum; E′ moved at %zu of %zu texels\n",
                32, past, own.size(), texelsMoved, ep.rows.size());
    ASSERT_GT(texelsMoved, 0u);
    ASSERT_GT(past, 0u)
        << "no point moved past the samplers' allowance: the emulation shows nothing";
    capture::Manifest edited = capture::readManifest(dir);
    plantTable(dir, edited, "scene.irradiance", et);
    plantTable(dir, edited, "texture_space.eprime", ep);
    const std::string note =
        "plus how far it moves with every sample's shadow map drawn 1/16 texel "
        "aside";
    std::string out;
    ASSERT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    std::printf("%s\n", lineOf(out, "PASS scene.irradiance  ").c_str());
    EXPECT_NE(lineOf(out, "PASS scene.irradiance  ").find(note), std::string::npos) << out;
    EXPECT_NE(lineOf(out, "PASS texture_space.eprime  ").find(note), std::string::npos) << out;
    EXPECT_NE(lineOf(out, "PASS scene.render  ").find("exact match"), std::string::npos) << out;

    size_t lit = et.rows.size();
    for (size_t i = 0; i < et.rows.size() && lit == et.rows.size(); ++i)
        if (own[i].g > 0.999f * unshadowed[i].g && unshadowed[i].g > 0) lit = i;
    ASSERT_LT(lit, et.rows.size()) << "no unshadowed point";
    capture::Table far = et;
    far.rows[lit][2] -= 0.5 * unshadowed[lit].g;
    plantTable(dir, edited, "scene.irradiance", far);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL scene.irradiance  1 of 6000 values out of tolerance; worst at row " +
                       std::to_string(lit + 1)),
              std::string::npos)
        << out;
    fs::remove_all(root);
}

// The octree, and so the render, read the recorded irradiance (E_u · V of scene.
// irradiance_unshadowed and scene.visibility, formed as the shader forms E_t), so a capture made on
// a driver whose sampler weighted the shadow map's comparisons otherwise (emulated: the workbench
// traced V moved by 2^-8 at every partly shadowed point, and that V is what the capture holds)
// replays its render and traced pixel exactly here, while V itself passes within its 2^-7 and the
// report says what the traversal read. Without the factors (a capture that has only the render)
// the same replay fails on the render; factors of different lengths, or of another length than
// the point cloud, are an error naming both.
TEST(CaptureReplay, TheTraversalReadsTheRecordedIrradiance) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("irradiance_input", {"dipole.bssrdf"});
    const fs::path dir = root / "captures" / "moved";
    capture::Table v;
    size_t partial = 0;
    {
        app::Workbench wb(root, false);
        sceneOn(wb, 2000, 96, 54);
        wb.finishScene();
        app::recordCaptureTo(wb, dir, "moved", 48, 27);
        const capture::Table eu = capture::readCsv(dir / "scene_irradiance_unshadowed.csv");
        v = capture::readCsv(dir / "scene_visibility.csv");
        ASSERT_EQ(eu.rows.size(), v.rows.size());
        for (auto& row : v.rows)
            if (row[1] > 0.02 && row[1] < 0.98) {
                row[1] = double(float(row[1] + 1.0 / 256));
                ++partial;
            }
        wb.scene().setGivenIrradiance(productOf(eu, v));
        wb.finishScene();
        app::recordCaptureTo(wb, dir, "moved", 48, 27);
    }
    ASSERT_GT(partial, 20u);
    capture::Manifest m = capture::readManifest(dir);
    plantTable(dir, m, "scene.visibility", v);

    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    for (const char* stage :
         {"scene.render", "scene.trace_steps", "scene.trace_values", "scene.irradiance_unshadowed"})
        EXPECT_NE(lineOf(out, std::string("PASS ") + stage + "  ").find("exact match"),
                  std::string::npos)
            << stage << "\n"
            << out;
    EXPECT_NE(out.find("PASS scene.visibility  " + std::to_string(2 * v.rows.size()) +
                       " values, worst diff 0.0039"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("NOTE scene: the octree and the render read the recorded irradiance "
                       "(scene.irradiance_unshadowed x scene.visibility)"),
              std::string::npos)
        << out;

    capture::writeManifest(dir, without(m, {"scene.irradiance_unshadowed", "scene.visibility"}));
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    const std::string fail = lineOf(out, "FAIL scene.render");
    ASSERT_FALSE(fail.empty()) << out;
    std::printf("V moved by 2^-8 at %zu points, traced from this run's V: %s\n", partial,
                fail.c_str());
    EXPECT_EQ(out.find("NOTE scene: the octree"), std::string::npos) << out;

    capture::Table shorter = v;
    shorter.rows.pop_back();
    plantTable(dir, m, "scene.visibility", shorter);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 2) << out;
    EXPECT_NE(out.find("scene.visibility: the recorded table has " +
                       std::to_string(shorter.rows.size()) +
                       " points, scene.irradiance_unshadowed " + std::to_string(v.rows.size())),
              std::string::npos)
        << out;

    // both factors a point short: the traversal cannot read them as the point cloud's
    capture::Table eu = capture::readCsv(dir / "scene_irradiance_unshadowed.csv");
    eu.rows.pop_back();
    plantTable(dir, m, "scene.irradiance_unshadowed", eu);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 2) << out;
    EXPECT_NE(out.find("given irradiance: " + std::to_string(eu.rows.size()) + " values for " +
                       std::to_string(v.rows.size()) + " points"),
              std::string::npos)
        << out;
    fs::remove_all(root);
}

// The shadow map is a rasterisation too: another driver's sub-pixel precision may draw its
// silhouettes up to 1/16 texel elsewhere, which moves V at points along the shadow's edge by far
// more than the samplers' 2^-7. A replay allows each V how far it moves here with the map drawn
// up to 1/16 texel aside (irradiance::Stage::visibilitySpread). Emulated: the capture
// holds V from a map drawn (0.05, 0.03) texel aside and the render traced from it; V passes,
// saying why, though some points moved past 2^-7, and the render replays exactly. A lit point's V
// moved by 0.5 fails.
TEST(CaptureReplay, TheVisibilityAllowsAShadowMapRasterisedElsewhere) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("raster_shift", {"dipole.bssrdf"});
    const fs::path dir = root / "captures" / "shifted";
    capture::Table v;
    size_t past = 0, lit = 0;
    {
        app::Workbench wb(root, false);
        sceneOn(wb, 2000, 48, 27);
        wb.finishScene();
        app::recordCaptureTo(wb, dir, "shifted", -1, -1);
        const capture::Table eu = capture::readCsv(dir / "scene_irradiance_unshadowed.csv");
        v = capture::readCsv(dir / "scene_visibility.csv");
        const std::vector<glm::vec4> moved = wb.scene().irradianceStage()->computeShifted(
            wb.scene().settings().light, glm::vec2(0.05f, 0.03f));
        ASSERT_EQ(moved.size(), v.rows.size());
        for (size_t i = 0; i < moved.size(); ++i) {
            past += std::abs(moved[i].w - v.rows[i][1]) > irradiance::kVisibilityTolerance;
            if (v.rows[i][1] == 1.0 && moved[i].w == 1.0f && lit == 0) lit = i;
            v.rows[i][1] = moved[i].w;
        }
        wb.scene().setGivenIrradiance(productOf(eu, v));
        wb.finishScene();
        app::recordCaptureTo(wb, dir, "shifted", -1, -1);
    }
    ASSERT_GT(past, 0u) << "no point's V moved past 2^-7: the emulation shows nothing";
    ASSERT_GT(lit, 0u);
    capture::Manifest m = capture::readManifest(dir);
    plantTable(dir, m, "scene.visibility", v);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    const std::string note = "how far V moves with the shadow map drawn 1/16 texel aside";
    EXPECT_NE(lineOf(out, "PASS scene.visibility  ").find(note), std::string::npos) << out;
    EXPECT_NE(lineOf(out, "PASS scene.render  ").find("exact match"), std::string::npos) << out;
    std::printf("V from a shadow map drawn (0.05, 0.03) texel aside: %zu points past 2^-7; %s\n",
                past, lineOf(out, "PASS scene.visibility  ").c_str());

    capture::Table far = v;
    far.rows[lit][1] -= 0.5;
    plantTable(dir, m, "scene.visibility", far);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL scene.visibility  1 of " + std::to_string(2 * v.rows.size()) +
                       " values out of tolerance; worst at row " + std::to_string(lit + 1)),
              std::string::npos)
        << out;
    fs::remove_all(root);
}

// The texture-space renderer's CDF, draws and render read the recorded E_t per texel
// (texture_space.irradiance, kind exr_input), so a capture made on a driver whose sampler weighted
// the shadow map's comparisons otherwise (emulated: the draws read E_t with V moved by 2^-8 at
// every partly shadowed texel) replays its draws and its render exactly here. Without that input
// the draws and the render follow this run's own E_t again (on llvmpipe 2 of the 512 draws move
// and the render is no longer identical); a recorded image of another size is an error naming
// both sizes.
TEST(CaptureReplay, TheTextureSpaceDrawsReadTheRecordedIrradiance) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("texel_input", {"dipole.bssrdf"});
    const fs::path dir = root / "captures" / "texels";
    size_t partial = 0;
    {
        app::Workbench wb(root, false);
        sceneOn(wb, 1500, 32, 18);
        textureSpaceOn(wb, 64, 256, 2);
        wb.update();
        wb.finishScene();
        wb.finishTextureSpace();
        texspace::Pipeline& p = *wb.textureSpace().pipeline();
        const texspace::Pipeline::EprimeFactors f = p.eprimeFactors();
        std::vector<glm::vec3> et = p.transmitted();
        for (size_t t = 0; t < et.size(); ++t) {
            const float v = f.visibility[t];
            if (p.texels().triangle[t] < 0 || !(v > 0.02f && v < 0.98f)) continue;
            et[t] *= (v + 1.0f / 256) / v;
            ++partial;
        }
        wb.textureSpace().setGivenIrradiance(et);
        wb.finishTextureSpace();
        app::recordCaptureTo(wb, dir, "texels", -1, -1);
    }
    ASSERT_GT(partial, 10u);
    const capture::Manifest m = capture::readManifest(dir);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("PASS texture_space.irradiance  recorded input, given to the stage (hash "
                       "matches)"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("PASS texture_space.samples  512 values, exact match"), std::string::npos)
        << out;
    EXPECT_NE(out.find("PASS texture_space.render  2880 values, identical"), std::string::npos)
        << out;

    capture::writeManifest(dir, without(m, {"texture_space.irradiance"}));
    app::replayCapture(dir, root, false, out);
    for (const char* stage : {"texture_space.samples  ", "texture_space.render  "}) {
        const std::string line = lineOf(out, stage);
        ASSERT_FALSE(line.empty()) << out;
        std::printf("E_t with V moved by 2^-8 at %zu texels, drawn from this run's: %s\n", partial,
                    line.c_str());
    }
    EXPECT_EQ(out.find("texture_space.render  2880 values, identical"), std::string::npos) << out;

    plantImageInputs(dir, m, 16, 16, [](const capture::StageOutput& o) {
        return o.stage == "texture_space.irradiance";
    });
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 2) << out;
    EXPECT_NE(out.find("texture_space.irradiance: the recorded irradiance is 16x16, "
                       "settings.texture_space.sampling.texture_size is 64"),
              std::string::npos)
        << out;
    fs::remove_all(root);
}

// The scene's G-buffer is a recorded input (kind exr_input): a replay traces the recorded one, so
// a capture made on a driver that places its samples elsewhere (emulated: the workbench traced a
// G-buffer rasterised with the image moved by 0.07 px) replays its render and traced pixel
// exactly here, and the raster rule (scene.gbuffer_rule) finds both that G-buffer and this
// run's own conforming. The same capture without its G-buffer (as recorded before it was an
// input) fails on the render. A G-buffer moved by 0.6 px, planted with its hashes, breaks the
// rule; a changed file is named by its hash; one of another size is an error naming both sizes.
TEST(CaptureReplay, TheRecordedGbufferIsTracedAndCheckedByTheRasterRule) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("gbuffer_input", {"dipole.bssrdf"});
    const fs::path dir = root / "captures" / "moved";
    render::Gbuffer far;
    {
        app::Workbench wb(root, false);
        const app::SceneSettings& s = sceneOn(wb, 2000, 96, 54);
        wb.finishScene();
        render::Renderer& r = *wb.scene().renderer();
        wb.scene().setGivenGbuffer(r.rasteriseGbuffer(s.render, glm::vec2(0.07f, -0.05f)));
        far = r.rasteriseGbuffer(s.render, glm::vec2(0.6f, 0.0f));
        wb.finishScene();
        app::recordCaptureTo(wb, dir, "moved", 48, 27);
    }
    const capture::Manifest m = capture::readManifest(dir);
    auto kindOf = [&](const std::string& stage) {
        for (const capture::StageOutput& o : m.outputs)
            if (o.stage == stage) return o.kind;
        return std::string("(none)");
    };
    EXPECT_EQ(kindOf("scene.gbuffer_position"), "exr_input");
    EXPECT_EQ(kindOf("scene.gbuffer_normal"), "exr_input");
    EXPECT_EQ(kindOf("scene.gbuffer_rule"), "csv");
    const capture::Table rule = capture::readCsv(dir / "scene_gbuffer_rule.csv");
    ASSERT_EQ(rule.rows.size(), 2u);
    for (const auto& row : rule.rows)
        for (size_t c = 2; c < row.size(); ++c)
            EXPECT_EQ(row[c], 0.0) << "row " << row[0] << ", " << rule.columns[c];

    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    for (const char* stage : {"scene.render", "scene.trace_steps", "scene.trace_values"}) {
        const size_t at = out.find(std::string("PASS ") + stage + "  ");
        ASSERT_NE(at, std::string::npos) << stage << "\n" << out;
        EXPECT_NE(out.substr(at, out.find('\n', at) - at).find("exact match"), std::string::npos)
            << out;
    }
    EXPECT_NE(out.find("PASS scene.gbuffer_position  recorded input"), std::string::npos) << out;
    EXPECT_NE(out.find("PASS scene.gbuffer_rule  14 values, exact match"), std::string::npos)
        << out;

    auto withoutGbuffer = [](capture::Manifest x) {
        x.outputs.erase(std::remove_if(x.outputs.begin(), x.outputs.end(),
                                       [](const capture::StageOutput& o) {
                                           return o.stage.rfind("scene.gbuffer", 0) == 0;
                                       }),
                        x.outputs.end());
        return x;
    };
    capture::writeManifest(dir, withoutGbuffer(m));
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL scene.render"), std::string::npos) << out;

    // the far G-buffer planted as the recorded one, hashes and all
    capture::Manifest planted = m;
    for (capture::StageOutput& o : planted.outputs)
        if (o.kind == "exr_input") {
            pathtrace::Image img;
            img.width = far.width;
            img.height = far.height;
            img.samples = 1;
            for (const glm::vec4& v :
                 o.stage == "scene.gbuffer_position" ? far.position : far.normal)
                img.mean.insert(img.mean.end(), {v.x, v.y, v.z});
            img.variance.assign(img.mean.size(), 0.0f);
            pathtrace::writeExr(dir / o.file, img);
            o.hash = capture::hashFile(dir / o.file);
        }
    capture::writeManifest(dir, planted);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("PASS scene.gbuffer_position  recorded input"), std::string::npos) << out;
    EXPECT_NE(out.find("FAIL scene.gbuffer_rule"), std::string::npos) << out;
    EXPECT_NE(out.find("column off_centre"), std::string::npos) << out;

    // a changed file: its hash names it
    capture::Manifest stale = planted;
    for (capture::StageOutput& o : stale.outputs)
        if (o.stage == "scene.gbuffer_normal") o.hash = m.outputs.front().hash;
    capture::writeManifest(dir, stale);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL scene.gbuffer_normal  recorded input changed since it was recorded"),
              std::string::npos)
        << out;

    // another size
    plantImageInputs(dir, planted, 10, 6,
                     [](const capture::StageOutput& o) { return o.kind == "exr_input"; });
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 2) << out;
    EXPECT_NE(out.find("scene.gbuffer_position: the recorded G-buffer is 10x6, "
                       "settings.scene.render renders 96x54"),
              std::string::npos)
        << out;
    fs::remove_all(root);
}

// The texture-space render traces the scene's view, so on replay it reads the recorded G-buffer
// (scene.gbuffer_*) as the scene's traversal does: a capture made on a driver that places its
// samples elsewhere (emulated: the scene and the texture space traced a G-buffer rasterised with
// the image moved by 0.07 px) replays its texture-space render exactly here, and a NOTE says what
// it read. Without the recorded G-buffer the texture-space render follows this run's own
// rasterisation, whose silhouette differs, and fails.
TEST(CaptureReplay, TheTextureSpaceRenderTracesTheRecordedGbuffer) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("texel_gbuffer", {"dipole.bssrdf"});
    const fs::path dir = root / "captures" / "moved";
    {
        app::Workbench wb(root, false);
        const app::SceneSettings& s = sceneOn(wb, 1500, 48, 27);
        textureSpaceOn(wb, 64, 256, 2);
        wb.update();
        wb.finishScene();
        const render::Gbuffer moved =
            wb.scene().renderer()->rasteriseGbuffer(s.render, glm::vec2(0.07f, -0.05f));
        wb.scene().setGivenGbuffer(moved);
        wb.textureSpace().setGivenGbuffer(moved);
        wb.finishScene();
        wb.finishTextureSpace();
        app::recordCaptureTo(wb, dir, "moved", -1, -1);
    }
    const capture::Manifest m = capture::readManifest(dir);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(lineOf(out, "PASS texture_space.render  ").find("identical"), std::string::npos)
        << out;
    EXPECT_NE(out.find("NOTE texture space: the render reads the recorded G-buffer"),
              std::string::npos)
        << out;

    capture::writeManifest(dir, without(m, {"scene.gbuffer_position", "scene.gbuffer_normal"}));
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL texture_space.render"), std::string::npos) << out;
    fs::remove_all(root);
}

// The hybrid's local term filters a light-view map, a rasterisation whose silhouettes another
// driver may draw 1/16 texel elsewhere, read at tap places a float division puts a few ulp apart.
// A hybrid capture records the local L_o the render added (texture_space.local_radiance, kind
// exr_input) and a replay adds the recorded one, while texture_space.local compares this run's
// own with an allowance measured here (Pipeline::localSpread). Emulated: the capture was made
// with the map drawn (0.05, 0.03) texel aside and read (4, -3)·10^-4 texel aside; values past
// 1e-4 relative pass within the allowance and the render is identical; without the recorded
// local term the render fails; a value moved far past the allowance fails; a recorded local term
// of another size is an error naming both sizes.
TEST(CaptureReplay, TheHybridAddsTheRecordedLocalTermAndAllowsItsLightMapsSpread) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("hybrid_local", {"dipole.bssrdf"});
    const fs::path dir = root / "captures" / "hybrid";
    size_t past = 0, shown = 0;
    {
        app::Workbench wb(root, false);
        texspace::Pipeline& p = hybridOn(wb);
        const std::vector<glm::vec4> own = p.ownLocalRadiance();
        p.setLocalShift({0.05f, 0.03f}, {0.0004f, -0.0003f}); // as another driver may
        renderHybridAgain(wb);
        const std::vector<glm::vec4>& moved = p.ownLocalRadiance();
        ASSERT_EQ(moved.size(), own.size());
        float largest = 0;
        for (const glm::vec4& l : own)
            largest = std::max({largest, l.x, l.y, l.z});
        for (size_t px = 0; px < own.size(); ++px) {
            if (own[px].w == 0.0f) continue;
            ++shown;
            for (int c = 0; c < 3; ++c)
                if (std::abs(moved[px][c] - own[px][c]) >
                    1e-4 * std::abs(own[px][c]) + 1e-6 * largest) {
                    ++past;
                    break;
                }
        }
        app::recordCaptureTo(wb, dir, "hybrid", -1, -1);
    }
    std::printf("local term from a map drawn and read elsewhere: %zu of %zu pixels past 1e-4\n",
                past, shown);
    ASSERT_GT(past, 0u) << "the emulation moves nothing past the tolerance: it shows nothing";
    capture::Manifest m = capture::readManifest(dir);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    std::printf("%s\n", lineOf(out, "PASS texture_space.local  ").c_str());
    EXPECT_NE(lineOf(out, "PASS texture_space.local  ")
                  .find("how far the local term moves with the light-view map drawn"),
              std::string::npos)
        << out;
    EXPECT_NE(lineOf(out, "PASS texture_space.render  ").find("identical"), std::string::npos)
        << out;
    EXPECT_NE(out.find("NOTE texture space: the hybrid's render adds the recorded local term"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("PASS texture_space.local_radiance  recorded input, given to the stage"),
              std::string::npos)
        << out;

    // without the recorded local term the render adds this run's own
    capture::writeManifest(dir, without(m, {"texture_space.local_radiance"}));
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL texture_space.render"), std::string::npos) << out;
    std::printf("without the recorded local term: %s\n",
                lineOf(out, "FAIL texture_space.render").c_str());
    capture::writeManifest(dir, m);

    capture::Table far = capture::readCsv(dir / "texture_space_local.csv");
    ASSERT_GT(far.rows.size(), 10u);
    far.rows[5][1] *= 1.5;
    plantTable(dir, m, "texture_space.local", far);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1) << out;
    EXPECT_NE(out.find("FAIL texture_space.local  1 of " + std::to_string(4 * far.rows.size()) +
                       " values out of tolerance; worst at row 6"),
              std::string::npos)
        << out;

    plantImageInputs(dir, m, 10, 6, [](const capture::StageOutput& o) {
        return o.stage == "texture_space.local_radiance";
    });
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 2) << out;
    EXPECT_NE(out.find("texture_space.local_radiance: the recorded local term is 10x6, "
                       "settings.scene.render renders 48x27"),
              std::string::npos)
        << out;
    fs::remove_all(root);
}

// Pipeline::localSpread measures each tap of the ring filter with the light-view map moved to
// irradiance::rasterShifts(); a driver snaps each vertex on its own, so each tap reads the
// surface moved its own way. Emulated on the bunny (Pipeline::setLocalVertexSnap: every vertex
// moved on its own by up to 1/16 and 1/256 texel along both image axes and 8 ulps of depth):
// every lit pixel's own local L_o, per channel, stays within the spread (the same taps and
// driver, so to 1e-6 of the largest), though the moves change most pixels past 1e-4; moves of
// 1/2 texel fail. (A whole-map measure, the sum of the taps' changes, missed by up to 3.7x.)
TEST(CaptureReplay, TheLocalSpreadBoundsALightMapWhoseVerticesSnapApart) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("hybrid_snap", {"dipole.bssrdf"});
    app::Workbench wb(root, false);
    texspace::Pipeline& p = hybridOn(wb);
    const std::vector<glm::vec4> own = p.ownLocalRadiance();
    std::vector<size_t> lit;
    float largest = 0;
    for (size_t px = 0; px < own.size(); ++px) {
        if (own[px].w == 0.0f) continue;
        lit.push_back(px);
        largest = std::max({largest, own[px].x, own[px].y, own[px].z});
    }
    const std::vector<glm::vec3> spread = p.localSpread(lit);
    ASSERT_EQ(spread.size(), lit.size());
    auto snapped = [&](const gl::VertexSnap& snap) {
        p.setLocalVertexSnap(snap);
        renderHybridAgain(wb);
        p.setLocalVertexSnap({});
        return p.ownLocalRadiance();
    };
    const float rounding = 1e-6f * largest;
    size_t past = 0, beyond = 0;
    double worst = 0;
    for (const uint32_t seed : {1u, 2u}) {
        for (const float texels : {irradiance::kRasterShiftTexels, 1.0f / 256.0f}) {
            const std::vector<glm::vec4> near = snapped({texels, 8.0f, seed});
            for (size_t i = 0; i < lit.size(); ++i) {
                const size_t px = lit[i];
                bool moved = false;
                for (int c = 0; c < 3; ++c) {
                    const float d = std::abs(near[px][c] - own[px][c]);
                    moved = moved || d > 1e-4f * std::abs(own[px][c]) + rounding;
                    worst = std::max(worst, double(d) / (spread[i][c] + rounding));
                    EXPECT_LE(d, spread[i][c] + rounding)
                        << "snap " << texels << " seed " << seed << " pixel " << px << " channel "
                        << c << " L " << own[px][c] << " moved " << near[px][c] << " spread "
                        << spread[i][c];
                }
                past += moved;
            }
        }
        const std::vector<glm::vec4> far =
            snapped({8.0f * irradiance::kRasterShiftTexels, 8.0f, seed});
        for (size_t i = 0; i < lit.size(); ++i)
            for (int c = 0; c < 3; ++c)
                if (std::abs(far[lit[i]][c] - own[lit[i]][c]) > spread[i][c] + rounding) {
                    ++beyond;
                    break;
                }
    }
    EXPECT_GT(past, lit.size()) << "the emulation moves too little to show anything";
    EXPECT_GT(beyond, 10u) << "moves of 1/2 texel stay within the spread too";
    std::printf("local term, the light-view map's vertices snapped apart by up to 1/16 and 1/256 "
                "texel: %zu of %zu lit pixels past 1e-4, each within the spread (at most %.0f %% "
                "of it); at 1/2 texel %zu past it\n",
                past, 4 * lit.size(), 100 * worst, beyond);
}
