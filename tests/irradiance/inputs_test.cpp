// irradiance, bad inputs and shader errors (headless GL): each a core::Error that names the
// file or the setting; a failed environment load keeps the previous environment; a broken
// shader names its file and line; PNG projected textures are decoded from sRGB.
#include "gl_stage.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

namespace {
namespace fs = std::filesystem;
using namespace irradiance;

void expectError(const std::function<void()>& f, const std::string& file, const std::string& text) {
    try {
        f();
        ADD_FAILURE() << "no error (expected '" << text << "')";
    } catch (const core::Error& e) {
        if (!file.empty()) {
            EXPECT_EQ(e.file(), file) << e.what();
        }
        EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
}

TEST(IrradianceInputs, SettingsAreChecked) {
    Stage& st = irrtest::stage();
    const mesh::Mesh m = mesh::makeUvSphere(6, 12);
    st.setScene(m, irrtest::vertexPositions(m), irrtest::vertexNormals(m));
    Settings s;
    s.shadowMapSize = 64;
    s.direction = glm::vec3(0.0f);
    expectError([&] { st.compute(s); }, "", "'direction'");
    s.direction = glm::vec3(NAN, 1, 0);
    expectError([&] { st.compute(s); }, "", "'direction'");
    s.direction = glm::vec3(0, 1, 0);
    for (int size : {8, 100000}) {
        s.shadowMapSize = size;
        expectError([&] { st.compute(s); }, "", "'shadowMapSize'");
    }
    s.shadowMapSize = 64;
    s.ior = 0.5f;
    expectError([&] { st.compute(s); }, "", "'ior'");
    s.ior = 1.3f;
    s.jitterSamples = 0;
    expectError([&] { st.compute(s); }, "", "'jitterSamples'");
    s.jitterSamples = 8;
    s.irradiance = glm::vec3(1, -1, 1);
    expectError([&] { st.compute(s); }, "", "'irradiance'");
    s.irradiance = glm::vec3(1);
    s.mode = LightMode::OccludedIbl;
    s.shadowMapSize = 8192;
    s.occludedSamplesPerStep = 64;
    expectError([&] { st.beginOccluded(s); }, "", "512 MiB");
    EXPECT_NO_THROW(validateSettings(Settings{}));
}

TEST(IrradianceInputs, SceneAndEnvironmentErrors) {
    Stage& st = irrtest::stage();
    const mesh::Mesh m = mesh::makeUvSphere(6, 12);
    expectError([&] { st.setScene(m, {glm::vec3(0)}, {}); }, "", "1 positions but 0 normals");
    expectError([&] { st.setScene(m, {glm::vec3(0)}, {glm::vec3(0)}); }, "", "zero");
    expectError([&] { st.setScene(mesh::Mesh{}, {glm::vec3(0)}, {glm::vec3(0, 1, 0)}); }, "",
                "no triangles");

    const fs::path dir = irrtest::tempDir("inputs");
    st.setEnvironment(irrtest::constantEnv(8, 4, glm::vec3(2.0f)));
    expectError([&] { st.loadEnvironment(dir / "missing.exr"); }, (dir / "missing.exr").string(),
                "");
    irrtest::writeRawExr(dir / "y.exr", 4, 2, {"Y"}, std::vector<float>(8, 1.0f));
    expectError([&] { st.loadEnvironment(dir / "y.exr"); }, (dir / "y.exr").string(),
                "no channel 'R'");
    { std::ofstream(dir / "junk.exr") << "junk"; }
    expectError([&] { st.loadEnvironment(dir / "junk.exr"); }, (dir / "junk.exr").string(),
                "cannot read EXR");
    // the previous environment is kept
    ASSERT_TRUE(st.hasEnvironment());
    EXPECT_EQ(st.environment().width, 8);
    EXPECT_EQ(st.environment().rgb[0], 2.0f);

    expectError([&] { st.loadProjectedTexture(dir / "missing.png"); },
                (dir / "missing.png").string(), "");
    { std::ofstream(dir / "junk.png") << "not a png"; }
    expectError([&] { st.loadProjectedTexture(dir / "junk.png"); }, (dir / "junk.png").string(),
                "cannot decode image");
    expectError([&] { st.setProjectedTexture(2, 2, std::vector<float>(12, -1.0f), "tex"); }, "tex",
                "negative");
}

TEST(IrradianceInputs, FreshStageNeedsSceneAndEnvironment) {
    irrtest::stage();
    Stage fresh(testsupport::sourceRoot() / "shaders");
    Settings s;
    s.shadowMapSize = 64;
    expectError([&] { fresh.compute(s); }, "", "no scene");
    const mesh::Mesh m = mesh::makeUvSphere(6, 12);
    fresh.setScene(m, irrtest::vertexPositions(m), irrtest::vertexNormals(m));
    s.mode = LightMode::Ibl;
    expectError([&] { fresh.compute(s); }, "", "environment");
    expectError([&] { fresh.beginOccluded(s); }, "", "environment");
    EXPECT_EQ(fresh.irradianceCubemap(), 0u);
}

TEST(IrradianceInputs, PngProjectedTextureIsDecodedFromSrgb) {
    Stage& st = irrtest::stage();
    const fs::path dir = irrtest::tempDir("png");
    gl::writePng(dir / "grey.png", 2, 2, std::vector<unsigned char>(16, 128));
    st.loadProjectedTexture(dir / "grey.png");
    const mesh::Mesh m = mesh::makeUvSphere(8, 16);
    const auto P = irrtest::vertexPositions(m), N = irrtest::vertexNormals(m);
    st.setScene(m, P, N);
    Settings s;
    s.mode = LightMode::Filtered;
    s.shadowMapSize = 256;
    s.direction = glm::vec3(0, 1, 0);
    const auto E = st.compute(s);
    const double t = std::pow((128 / 255.0 + 0.055) / 1.055, 2.4); // sRGB 128 -> 0.2158
    for (size_t i = 0; i < P.size(); ++i) {
        if (N[i].y < 0.5f) continue;
        const double want = t * irrtest::ft(N[i].y, s.ior) * N[i].y;
        EXPECT_NEAR(E[i].g, want, 1e-5 * want) << i;
    }
    st.useCheckerTexture();
}

TEST(IrradianceInputs, BrokenShaderNamesFileAndLine) {
    irrtest::stage();
    const fs::path root = irrtest::tempDir("shaders");
    fs::remove_all(root / "shaders");
    fs::copy(testsupport::sourceRoot() / "shaders", root / "shaders", fs::copy_options::recursive);
    const fs::path inc = root / "shaders/common/irradiance_shadow.glsl";
    const std::string text = core::readFile(inc);
    core::writeFile(inc,
                    testsupport::replaced(text, "float bias =", "float bias = undefinedName +"));
    const int line = testsupport::lineOf(core::readFile(inc), "undefinedName");
    try {
        Stage broken(root / "shaders");
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/common/irradiance_shadow.glsl") << e.what();
        EXPECT_EQ(e.line(), line) << e.what();
    }
    core::writeFile(inc, text);
    const fs::path vert = root / "shaders/irradiance_shadow.vert";
    core::writeFile(vert, testsupport::replaced(core::readFile(vert),
                                                "gl_Position =", "gl_Position = nothing +"));
    try {
        Stage broken(root / "shaders");
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/irradiance_shadow.vert") << e.what();
        EXPECT_EQ(e.line(), testsupport::lineOf(core::readFile(vert), "nothing")) << e.what();
    }
    fs::remove(root / "shaders/irradiance_ibl.comp");
    try {
        Stage broken(root / "shaders");
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("irradiance"), std::string::npos) << e.what();
    }
}

} // namespace
