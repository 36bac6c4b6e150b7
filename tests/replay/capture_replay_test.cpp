// Captures end to end: record → replay PASS; a tampered output, a missing output, a changed
// model and a corrupt manifest all FAIL with a message naming the stage or file; captures from
// elsewhere (hostile paths, wrong JSON types) are refused by name. The mesh pipeline's recorded
// inputs and what its replays allow another driver: scene_replay_test.cpp.
#include "../support/gl_fixture.h"
#include "capture/capture.h"
#include "captures/capture_io.h"
#include "core/core.h"
#include "mesh/mesh.h"
#include "pathtrace/image_io.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include <nlohmann/json.hpp>

namespace {
namespace fs = std::filesystem;

struct Recorded {
    fs::path root, dir;
};
Recorded record(const std::string& tag) {
    testsupport::context();
    Recorded r;
    r.root = testsupport::makeProjectRoot(tag, {"dipole.bssrdf", "better_dipole.bssrdf"});
    r.dir = r.root / "captures" / "rec";
    app::Workbench wb(r.root, false);
    wb.applyPreset(wb.shared(), "Skin1");
    wb.view("materials/better_dipole.bssrdf").override = true;
    auto& own = wb.view("materials/better_dipole.bssrdf").own;
    own.mode = app::ParamMode::RdrLd;
    own.rdr = {0.7, 0.5, 0.3};
    own.ld = {3.0, 1.5, 0.7};
    wb.library().find("materials/dipole.bssrdf")->values["Multiplier"] = {1.25f, 0, 0};
    wb.plotSettings().samples = 600;
    app::recordCaptureTo(wb, r.dir, "rec");
    return r;
}
int replay(const Recorded& r, std::string& out, bool update = false) {
    return app::replayCapture(r.dir, r.root, update, out);
}
} // namespace

TEST(CaptureReplay, RecordThenReplayPasses) {
    auto r = record("pass");
    auto m = capture::readManifest(r.dir);
    EXPECT_EQ(m.models.size(), 2u);
    EXPECT_EQ(m.outputs.size(), 4u); // material + pencil plot per model
    EXPECT_FALSE(m.glRenderer.empty());
    EXPECT_NE(m.models[0].source.find("::begin shader"), std::string::npos);
    std::string out;
    EXPECT_EQ(replay(r, out), 0) << out;
    EXPECT_NE(out.find("PASS pencil_plot.dipole"), std::string::npos) << out;
    EXPECT_NE(out.find("PASS material.better_dipole"), std::string::npos) << out;
    // the recorded state was really restored: Multiplier 1.25 and the inverted material
    auto table = capture::readCsv(r.dir / "material_better_dipole.csv");
    EXPECT_NE(table.rows[0][1], 0.032); // not Skin1's sigma_a: came from R_dr/l_d
    fs::remove_all(r.root);
}

TEST(CaptureReplay, TamperedOutputFailsNamingTheStage) {
    auto r = record("tamper");
    auto t = capture::readCsv(r.dir / "pencil_plot_dipole.csv");
    t.rows[37][2] *= 1.001; // 0.1 %: far above float32 evaluation error (1e-5)
    capture::writeCsv(r.dir / "pencil_plot_dipole.csv", t);
    std::string out;
    EXPECT_EQ(replay(r, out), 1) << out;
    EXPECT_NE(out.find("FAIL pencil_plot.dipole"), std::string::npos) << out;
    EXPECT_NE(out.find("row 38"), std::string::npos) << out;
    EXPECT_NE(out.find("PASS pencil_plot.better_dipole"), std::string::npos) << out;
    // --update rewrites on purpose, after which replay passes again
    EXPECT_EQ(replay(r, out, true), 0) << out;
    EXPECT_EQ(replay(r, out), 0) << out;
    fs::remove_all(r.root);
}

TEST(CaptureReplay, MissingOutputFails) {
    auto r = record("missing");
    fs::remove(r.dir / "material_dipole.csv");
    std::string out;
    EXPECT_EQ(replay(r, out), 1) << out;
    EXPECT_NE(out.find("material_dipole.csv"), std::string::npos) << out;
    EXPECT_NE(out.find("FAIL material.dipole"), std::string::npos) << out;
    fs::remove_all(r.root);
}

// A model edited in comments or whitespace only compiles to the same program: a note, and
// the replay passes; a change of its code fails it.
TEST(CaptureReplay, CommentOnlyModelEditIsANoteACodeEditFails) {
    auto r = record("hash");
    const std::string text = testsupport::readText(r.root / "materials/dipole.bssrdf");
    std::string commented = testsupport::replaced(
        text, "void init() {", "/* why:\n   a note */ void init() { // see 2.30");
    core::writeFile(r.root / "materials/dipole.bssrdf",
                    "# edited after recording\n" + commented + "\n\n   \n");
    std::string out;
    EXPECT_EQ(replay(r, out), 0) << out;
    EXPECT_NE(out.find("NOTE materials/dipole.bssrdf: only comments or whitespace changed"),
              std::string::npos)
        << out;
    core::writeFile(r.root / "materials/dipole.bssrdf",
                    testsupport::replaced(text, "A = (1.0 + Fdr)/(1.0 - Fdr);",
                                          "A = 1.01*(1.0 + Fdr)/(1.0 - Fdr);"));
    EXPECT_EQ(replay(r, out), 1) << out;
    EXPECT_NE(out.find("materials/dipole.bssrdf: content hash changed"), std::string::npos) << out;
    // --update takes the edit: the manifest's hash and its copy of the model's text both
    // follow the file, so a later comment-only edit is compared with the edited code
    EXPECT_EQ(replay(r, out, true), 0) << out;
    const capture::Manifest m = capture::readManifest(r.dir);
    bool found = false;
    for (const auto& mf : m.models)
        if (mf.path == "materials/dipole.bssrdf") {
            found = true;
            EXPECT_NE(mf.source.find("A = 1.01*(1.0 + Fdr)/(1.0 - Fdr);"), std::string::npos);
        }
    EXPECT_TRUE(found);
    EXPECT_EQ(replay(r, out), 0) << out;
    fs::remove_all(r.root);
}

TEST(CaptureReplay, MissingModelFails) {
    auto r = record("nomodel");
    fs::remove(r.root / "materials/better_dipole.bssrdf");
    std::string out;
    EXPECT_EQ(replay(r, out), 1) << out;
    EXPECT_NE(out.find("materials/better_dipole.bssrdf: missing"), std::string::npos) << out;
    EXPECT_NE(out.find("FAIL pencil_plot.better_dipole"), std::string::npos) << out;
    fs::remove_all(r.root);
}

TEST(CaptureReplay, CorruptManifestIsUnreadable) {
    auto r = record("corrupt");
    std::string text = testsupport::readText(r.dir / "manifest.json");
    text.insert(text.find("\"outputs\""), "{{{ not json ");
    core::writeFile(r.dir / "manifest.json", text);
    std::string out;
    EXPECT_EQ(replay(r, out), 2) << out;
    EXPECT_NE(out.find("manifest.json:"), std::string::npos) << out;
    fs::remove_all(r.root);
}

TEST(CaptureReplay, LitSphereImagesAreComparedPerPixel) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("images", {"dipole.bssrdf"});
    const auto dir = root / "captures" / "img";
    {
        app::Workbench wb(root, false);
        wb.applyPreset(wb.shared(), "Skin1");
        auto& s = wb.litSphereSettings();
        s.enabled = true;
        s.size = 16;
        s.radiusMm = 4;
        s.pathSpp = 4;
        s.integratedSpp = 256;
        app::recordCaptureTo(wb, dir, "img");
    }
    auto m = capture::readManifest(dir);
    int images = 0;
    for (const auto& o : m.outputs)
        images += o.kind == "exr_stat";
    EXPECT_EQ(images, 2);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("PASS lit_sphere.path_traced"), std::string::npos) << out;
    EXPECT_NE(out.find("PASS lit_sphere.integrated"), std::string::npos) << out;
    // same build, same seed: bitwise the same images (z = 0 everywhere)
    for (const char* stage : {"lit_sphere.path_traced", "lit_sphere.integrated"}) {
        const auto at = out.find(stage);
        ASSERT_NE(at, std::string::npos);
        const std::string line = out.substr(at, out.find('\n', at) - at);
        EXPECT_NE(line.find("identical"), std::string::npos) << line;
    }
    // a pixel moved by 20 of its standard errors fails, naming the stage
    auto img = pathtrace::readExr(dir / "lit_sphere_integrated.exr");
    const size_t p = (8 * 16 + 8) * 3;
    img.mean[p] += 20.0f * std::sqrt(img.variance[p]);
    pathtrace::writeExr(dir / "lit_sphere_integrated.exr", img);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1);
    EXPECT_NE(out.find("FAIL lit_sphere.integrated"), std::string::npos) << out;
    EXPECT_NE(out.find("PASS lit_sphere.path_traced"), std::string::npos) << out;
    std::filesystem::remove_all(root);
}

TEST(CaptureReplay, LitMeshImageAndItsInputAreRecorded) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("meshcap", {"dipole.bssrdf"});
    std::filesystem::create_directories(root / "meshes");
    mesh::writeObj(root / "meshes/ball.obj", mesh::makeUvSphere(16, 32));
    const auto dir = root / "captures" / "mesh";
    {
        app::Workbench wb(root, false);
        wb.applyPreset(wb.shared(), "Skin1");
        auto& s = wb.litSphereSettings();
        s.enabled = true;
        s.size = 12;
        s.radiusMm = 4;
        s.pathSpp = 2;
        s.integratedSpp = 16;
        s.mesh = "meshes/ball.obj";
        app::recordCaptureTo(wb, dir, "mesh");
    }
    auto m = capture::readManifest(dir);
    bool meshInput = false, meshImage = false;
    for (const auto& f : m.models)
        meshInput |= f.path == "meshes/ball.obj";
    for (const auto& o : m.outputs)
        meshImage |= o.stage == "lit_mesh.path_traced";
    EXPECT_TRUE(meshInput);
    EXPECT_TRUE(meshImage);
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    // an edited mesh is a changed input
    mesh::writeObj(root / "meshes/ball.obj", mesh::makeUvSphere(12, 24));
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1);
    EXPECT_NE(out.find("meshes/ball.obj: content hash changed"), std::string::npos) << out;
    // --update takes the edited mesh: recorded as it was (text below 1 MiB, else its size only)
    EXPECT_EQ(app::replayCapture(dir, root, true, out), 0) << out;
    m = capture::readManifest(dir);
    const std::string text = core::readFile(root / "meshes/ball.obj");
    for (const auto& f : m.models) {
        if (f.path == "meshes/ball.obj") {
            EXPECT_EQ(f.source, text);
        }
    }
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    std::filesystem::remove_all(root);
}

TEST(CaptureReplay, BadMeshIsAnErrorEntryNotACrash) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("badmesh", {"dipole.bssrdf"});
    core::writeFile(root / "open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    app::Workbench wb(root, false);
    auto& s = wb.litSphereSettings();
    s.enabled = true;
    s.size = 8;
    s.mesh = "open.obj";
    wb.update();
    bool listed = false;
    for (const auto& e : wb.errors())
        listed |= e.text.find("open") != std::string::npos;
    EXPECT_TRUE(listed);
    std::filesystem::remove_all(root);
}

// A failing image stage leaves recorded | replayed | difference as a PNG (and the replayed
// EXR) beside the capture, named in the report.
TEST(CaptureReplay, FailingImageStageWritesADifferenceImage) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("diffimg", {"dipole.bssrdf"});
    const fs::path dir = testsupport::copyCapture(root, "dipole_bunny_scene", "scene");
    std::string out;
    ASSERT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    auto img = pathtrace::readExr(dir / "scene_render.exr");
    for (size_t p = 0; p < img.mean.size(); p += 3 * 7)
        img.mean[p] *= 1.5f;
    pathtrace::writeExr(dir / "scene_render.exr", img);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1);
    EXPECT_NE(out.find("FAIL scene.render"), std::string::npos) << out;
    const fs::path png = root / "captures/scene.replay/scene.render.diff.png";
    EXPECT_NE(out.find(png.string()), std::string::npos) << out;
    ASSERT_TRUE(fs::exists(png)) << out;
    ASSERT_TRUE(fs::exists(root / "captures/scene.replay/scene.render.replayed.exr"));
    const std::string b = core::readFile(png);
    auto be32 = [&](size_t o) {
        return (int(uint8_t(b[o])) << 24) | (int(uint8_t(b[o + 1])) << 16) |
               (int(uint8_t(b[o + 2])) << 8) | int(uint8_t(b[o + 3]));
    };
    EXPECT_EQ(be32(16), 3 * img.width); // recorded | replayed | difference side by side
    EXPECT_EQ(be32(20), img.height);
    fs::remove_all(root);
}

// A model opened from outside the project is recorded as external/FILE with its text, and
// replays from that text wherever the original went.
TEST(CaptureReplay, ModelFromOutsideTheProjectRecordsAndReplays) {
    testsupport::context();
    const fs::path root = testsupport::makeProjectRoot("external", {"dipole.bssrdf"});
    const fs::path outside = root.parent_path() / (root.filename().string() + "_outside");
    fs::create_directories(outside);
    const std::string text =
        testsupport::readText(testsupport::sourceRoot() / "materials/better_dipole.bssrdf");
    core::writeFile(outside / "mine.bssrdf", text);
    const fs::path dir = root / "captures" / "ext";
    {
        app::Workbench wb(root, false);
        wb.openModel(outside / "mine.bssrdf");
        ASSERT_NE(wb.library().find("mine"), nullptr);
        ASSERT_TRUE(wb.library().find("mine")->usable());
        app::recordCaptureTo(wb, dir, "ext");
    }
    const capture::Manifest m = capture::readManifest(dir);
    const auto ext = std::find_if(m.models.begin(), m.models.end(),
                                  [](const auto& f) { return f.path == "external/mine.bssrdf"; });
    ASSERT_NE(ext, m.models.end());
    EXPECT_EQ(ext->source, text);
    EXPECT_TRUE(m.params["models"].contains("external/mine.bssrdf")) << m.params.dump();
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("NOTE external/mine.bssrdf: opened from outside the project"),
              std::string::npos)
        << out;
    EXPECT_NE(out.find("PASS pencil_plot.mine"), std::string::npos) << out;
    // the original is gone: the recorded text still replays
    fs::remove_all(outside);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    fs::remove_all(root);
}

// The BSSRDF slice: its path-traced table is replayed by per-value z-tests (bitwise identical on
// the same build), every model's table by float tolerance; a value moved by 20 standard errors,
// or a model's value by 1 %, fails naming the stage.
TEST(CaptureReplay, SliceTablesAreComparedStatisticallyAndModelsByTolerance) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("slicecap", {"dipole.bssrdf"});
    const auto dir = root / "captures" / "slice";
    {
        app::Workbench wb(root, false);
        auto& s = wb.sliceSettings();
        s.enabled = true;
        s.thetaIDeg = 60;
        s.rBins = 5;
        s.thetaSBins = 4;
        s.dirCosBins = 2;
        s.dirPhiBins = 2;
        s.paths = 16384;
        app::recordCaptureTo(wb, dir, "slice");
    }
    std::string out;
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 0) << out;
    EXPECT_NE(out.find("PASS slice "), std::string::npos) << out;
    EXPECT_NE(out.find("PASS slice_model.dipole"), std::string::npos) << out;
    const std::string line = out.substr(
        out.find("PASS slice "), out.find('\n', out.find("PASS slice ")) - out.find("PASS slice "));
    EXPECT_NE(line.find("identical"), std::string::npos) << line;
    // the recorded settings are what the replay runs (θi 60, 5 × 4 bins, 2 × 2 cells)
    capture::Table t = capture::readCsv(dir / "slice.csv");
    ASSERT_EQ(t.rows.size(), 21u); // 20 bins and the total
    ASSERT_EQ(t.columns.size(), 5u + 2u + 2u * 4u);
    // R of bin 3 moved by 20 standard errors fails the z-test
    const auto col = size_t(std::find(t.columns.begin(), t.columns.end(), "R") - t.columns.begin());
    t.rows[3][col] += 20 * t.rows[3][col + 1];
    capture::writeCsv(dir / "slice.csv", t);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1);
    EXPECT_NE(out.find("FAIL slice "), std::string::npos) << out;
    // a model value 1 % off fails the model's stage
    capture::Table m = capture::readCsv(dir / "slice_model_dipole.csv");
    const auto mc = size_t(std::find(m.columns.begin(), m.columns.end(), "R") - m.columns.begin());
    m.rows[2][mc] *= 1.01;
    capture::writeCsv(dir / "slice_model_dipole.csv", m);
    EXPECT_EQ(app::replayCapture(dir, root, false, out), 1);
    EXPECT_NE(out.find("FAIL slice_model.dipole"), std::string::npos) << out;
    std::filesystem::remove_all(root);
}

// ---- untrusted captures -------------------------------------------------------------------
namespace {
// Rewrites the capture's manifest through `edit` (the JSON as the recorder wrote it).
template <class F> void editManifest(const Recorded& r, F edit) {
    nlohmann::json j = nlohmann::json::parse(testsupport::readText(r.dir / "manifest.json"));
    edit(j);
    core::writeFile(r.dir / "manifest.json", j.dump(2));
}
} // namespace

TEST(CaptureReplay, HostileInputPathsStayInsideTheCaptureAndTheProject) {
    auto r = record("hostile_inputs");
    const nlohmann::json original =
        nlohmann::json::parse(testsupport::readText(r.dir / "manifest.json"));
    // a folder outside the project, reached by "..", by an absolute path and by a symlink
    const fs::path outside = r.root.parent_path() / (r.root.filename().string() + "_outside");
    fs::create_directories(outside);
    core::writeFile(outside / "secret.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    fs::create_symlink(outside, r.dir / "link");
    const std::string relOut = "../" + outside.filename().string() + "/secret.obj";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"mesh", "../../../etc/passwd"},
        {"mesh", relOut},
        {"mesh", (outside / "secret.obj").string()},
        {"mesh", "captures/rec/link/secret.obj"},
        {"environment", relOut},
        {"point_cloud_file", "/etc/hostname"},
        {"projected_texture", "captures/rec/link/secret.obj"},
    };
    for (const auto& c : cases) {
        const std::string& key = c.first; // (not a structured binding: clang 15 cannot capture one)
        const std::string& value = c.second;
        SCOPED_TRACE(key + " = " + value);
        editManifest(r, [&](nlohmann::json& j) {
            j = original;
            j["settings"]["scene"][key] = value;
        });
        std::string out;
        EXPECT_EQ(replay(r, out), 2) << out;
        EXPECT_NE(out.find("settings.scene." + key + ": '" + value + "'"), std::string::npos)
            << out;
        EXPECT_NE(out.find("outside the folders a capture may read"), std::string::npos) << out;
    }
    editManifest(r, [&](nlohmann::json& j) {
        j = original;
        j["settings"]["lit_spheres"]["mesh"] = relOut;
    });
    std::string out;
    EXPECT_EQ(replay(r, out), 2) << out;
    EXPECT_NE(out.find("settings.lit_spheres.mesh"), std::string::npos) << out;
    // the project's own data folders and the capture folder itself are fine
    fs::copy_file(outside / "secret.obj", r.dir / "own.obj");
    editManifest(r, [&](nlohmann::json& j) {
        j = original;
        j["settings"]["scene"]["projected_texture"] = "captures/rec/own.obj";
    });
    EXPECT_EQ(capture::confinedInputProblem("captures/rec/own.obj", r.root, {r.dir}), "");
    EXPECT_EQ(capture::confinedInputProblem("materials/dipole.bssrdf", r.root,
                                            {r.dir, r.root / "materials"}),
              "");
    editManifest(r, [&](nlohmann::json& j) { j = original; });
    EXPECT_EQ(replay(r, out), 0) << out;
    fs::remove_all(outside);
    fs::remove_all(r.root);
}

TEST(CaptureReplay, OutputsNeverLeadOutOfTheCaptureFolder) {
    auto r = record("hostile_outputs");
    const fs::path outside = r.root.parent_path() / (r.root.filename().string() + "_victim");
    fs::create_directories(outside);
    const std::string victimText = "must stay unchanged\n";
    core::writeFile(outside / "victim.csv", victimText);
    // an output replaced by a symlink to a file outside: refused before anything is read or
    // written, with --update too
    const fs::path out0 = r.dir / "pencil_plot_dipole.csv";
    fs::remove(out0);
    fs::create_symlink(outside / "victim.csv", out0);
    for (bool update : {false, true}) {
        std::string out;
        EXPECT_EQ(replay(r, out, update), 2) << out;
        EXPECT_NE(out.find("pencil_plot_dipole.csv"), std::string::npos) << out;
        EXPECT_NE(out.find("symbolic link"), std::string::npos) << out;
        EXPECT_EQ(testsupport::readText(outside / "victim.csv"), victimText);
    }
    // a symlinked sub-folder: the output resolves outside
    fs::remove(out0);
    fs::create_symlink(outside, r.dir / "sub");
    EXPECT_NE(capture::outputPathProblem(r.dir, "sub/victim.csv").find("outside the capture"),
              std::string::npos);
    // "..", absolute names: refused by the manifest reader, naming the JSON path
    editManifest(r, [&](nlohmann::json& j) { j["outputs"][0]["file"] = "../../victim.csv"; });
    std::string out;
    EXPECT_EQ(replay(r, out), 2) << out;
    EXPECT_NE(out.find("outputs[0].file"), std::string::npos) << out;
    EXPECT_NE(out.find("'..' would escape the folder"), std::string::npos) << out;
    fs::remove_all(outside);
    fs::remove_all(r.root);
}

TEST(CaptureReplay, UpdateNeverWritesThroughAPlantedTemporaryFile) {
    auto r = record("hostile_tmp");
    const fs::path outside = r.root.parent_path() / (r.root.filename().string() + "_tmpvictim");
    fs::create_directories(outside);
    core::writeFile(outside / "victim.csv", "unchanged\n");
    // every output's temporary name is a symlink out of the folder
    for (const auto& o : capture::readManifest(r.dir).outputs)
        fs::create_symlink(outside / "victim.csv", r.dir / (o.file + ".tmp"));
    std::string out;
    EXPECT_EQ(replay(r, out, true), 0) << out;
    EXPECT_EQ(testsupport::readText(outside / "victim.csv"), "unchanged\n");
    EXPECT_EQ(replay(r, out), 0) << out; // the update wrote the real outputs
    fs::remove_all(outside);
    fs::remove_all(r.root);
}

TEST(CaptureReplay, WrongJsonTypesNameTheirPathNotTheLibrary) {
    auto r = record("hostile_types");
    const nlohmann::json original =
        nlohmann::json::parse(testsupport::readText(r.dir / "manifest.json"));
    const std::vector<std::pair<std::function<void(nlohmann::json&)>, std::string>> cases = {
        {[](nlohmann::json& j) {
             j["params"]["models"] = nlohmann::json::array({1, 2});
         },
         "params.models: expected an object"},
        {[](nlohmann::json& j) {
             j["params"]["models"]["materials/dipole.bssrdf"]["visible"] = "yes";
         },
         "params.models.materials/dipole.bssrdf.visible: expected true or false"},
        {[](nlohmann::json& j) { j["params"]["models"]["materials/dipole.bssrdf"] = 3; },
         "params.models.materials/dipole.bssrdf: needs 'own' and 'values'"},
        {[](nlohmann::json& j) { j["settings"]["plot"]["samples"] = "many"; },
         "settings.plot.samples: expected an integer"},
        {[](nlohmann::json& j) { j["settings"]["plot"]["samples"] = 1; },
         "settings.plot.samples: must be between 2 and 16384, got 1"},
        {[](nlohmann::json& j) { j["settings"]["scene"]["render"]["width"] = 1e9; },
         "settings.scene.render.width: expected an integer"},
        {[](nlohmann::json& j) { j["settings"]["reference"] = nlohmann::json::array(); },
         "settings.reference: expected an object"},
    };
    for (const auto& c : cases) {
        const auto& edit = c.first; // (not a structured binding: clang 15 cannot capture one)
        const auto& message = c.second;
        SCOPED_TRACE(message);
        editManifest(r, [&](nlohmann::json& j) {
            j = original;
            edit(j);
        });
        std::string out;
        EXPECT_EQ(replay(r, out), 2) << out;
        EXPECT_NE(out.find(message), std::string::npos) << out;
        EXPECT_EQ(out.find("json.exception"), std::string::npos) << out;
    }
    fs::remove_all(r.root);
}
