// GLSL assembly: #version first, #line source maps into the model and include files, errors.
#include "bssrdf/assembly.h"
#include "test_util.h"

#include <cstdio>
#include <map>
#include <sstream>

using namespace bssrdf_test;

namespace {

struct Location {
    int source = -1;
    int line = 0;
};

// Simulates GLSL line numbering (GLSL 4.50 section 3.3): "#line L S" makes the NEXT line line L
// of source string S; every other line advances the line number by one. Returns where the
// first line containing `token` is reported, decoded with shader::decodeLine (which must agree
// with the source number of the directive).
Location locate(const std::string& glsl, const std::string& token) {
    std::istringstream in(glsl);
    std::string line;
    Location cur{0, 1};
    while (std::getline(in, line)) {
        int l = 0, s = 0;
        if (std::sscanf(line.c_str(), "#line %d %d", &l, &s) == 2) {
            cur = {s, l};
            continue;
        }
        if (line.find(token) != std::string::npos) {
            const shader::SourceLine d = shader::decodeLine(cur.source, cur.line);
            EXPECT_EQ(d.source, cur.source) << "line encoding disagrees with #line source";
            // Mesa reports source 0 for semantic errors: the line alone must still decode
            const shader::SourceLine mesa = shader::decodeLine(0, cur.line);
            EXPECT_EQ(mesa.source, cur.source);
            EXPECT_EQ(mesa.line, d.line);
            return {d.source, d.line};
        }
        ++cur.line;
    }
    ADD_FAILURE() << "token " << token << " not found in\n" << glsl;
    return {};
}

// The physical line just before the first line containing `token`.
std::string lineBefore(const std::string& glsl, const std::string& token) {
    std::istringstream in(glsl);
    std::string prev, line;
    while (std::getline(in, line)) {
        if (line.find(token) != std::string::npos) return prev;
        prev = line;
    }
    return "";
}

int sourceOf(const shader::SourceMap& map, const std::string& file) {
    for (size_t i = 0; i < map.files.size(); ++i)
        if (map.files[i] == file) return static_cast<int>(i);
    ADD_FAILURE() << file << " not in the source map";
    return -1;
}

// Resolves "common/x.glsl" against the repository's shaders/ folder.
std::string repoResolver(const std::string& name, std::string& display) {
    display = "shaders/" + name;
    return core::readFile(sourceRoot() + "/" + display);
}

// Resolves from an in-memory table.
shader::IncludeResolver tableResolver(std::map<std::string, std::string> files) {
    return [files](const std::string& name, std::string& display) -> std::string {
        auto it = files.find(name);
        if (it == files.end()) throw core::Error("shaders/" + name, 0, "no such file");
        display = "shaders/" + name;
        return it->second;
    };
}

const std::string kTemplate = "#version 450\n"                             // 1
                              "#include \"common/bssrdf_prelude.glsl\"\n"  // 2
                              "layout(location = 0) out vec4 color;\n"     // 3
                              "#pragma bssrdf_model\n"                     // 4
                              "void main() { init(); TEMPLATE_TOKEN; }\n"; // 5

const std::string kModelText = "analytic radial\n"                                   // 1
                               "::begin parameters\n"                                // 2
                               "float Gain 0 1 0.5\n"                                // 3
                               "color Tint 1 1 1\n"                                  // 4
                               "::end parameters\n"                                  // 5
                               "\n"                                                  // 6
                               "::begin shader\n"                                    // 7
                               "float FIRST_TOKEN = 1.0;\n"                          // 8
                               "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n" // 9
                               "    return Tint*Gain*DEEP_TOKEN;\n"                  // 10
                               "}\n"                                                 // 11
                               "::end shader\n";                                     // 12

} // namespace

TEST(BssrdfAssembly, VersionStaysFirstAndModelLinesMapBack) {
    const auto model = bssrdf::parseModel(kModelText, kPath);
    const auto out = bssrdf::assemble(kTemplate, "shaders/test.frag", &model, repoResolver);
    EXPECT_EQ(out.glsl.rfind("#version 450\n", 0), 0u) << out.glsl;
    ASSERT_FALSE(out.map.files.empty());
    EXPECT_EQ(out.map.files[0], "shaders/test.frag");
    const int ms = sourceOf(out.map, kPath);

    // the first shader line is directly preceded by "#line <8 in model source> <model source>"
    EXPECT_EQ(lineBefore(out.glsl, "FIRST_TOKEN"),
              "#line " + std::to_string(ms * shader::kLineStride + 8) + " " + std::to_string(ms));
    const Location first = locate(out.glsl, "FIRST_TOKEN");
    EXPECT_EQ(first.source, ms);
    EXPECT_EQ(first.line, 8);
    const Location deep = locate(out.glsl, "DEEP_TOKEN");
    EXPECT_EQ(deep.source, ms);
    EXPECT_EQ(deep.line, 10);
    // uniforms map to their declaration lines
    const Location gain = locate(out.glsl, "uniform float Gain;");
    EXPECT_EQ(gain.source, ms);
    EXPECT_EQ(gain.line, 3);
    const Location tint = locate(out.glsl, "uniform vec3 Tint;");
    EXPECT_EQ(tint.line, 4);
    // back in the template after the model
    const Location tmpl = locate(out.glsl, "TEMPLATE_TOKEN");
    EXPECT_EQ(tmpl.source, 0);
    EXPECT_EQ(tmpl.line, 5);
    EXPECT_EQ(locate(out.glsl, "out vec4 color;").line, 3);
    EXPECT_EQ(locate(out.glsl, "out vec4 color;").source, 0);
}

TEST(BssrdfAssembly, IncludeMapsToItsOwnFile) {
    const auto model = bssrdf::parseModel(kModelText, kPath);
    const auto out = bssrdf::assemble(kTemplate, "shaders/test.frag", &model, repoResolver);
    const std::string prelude = "shaders/common/bssrdf_prelude.glsl";
    const int ps = sourceOf(out.map, prelude);
    const std::string text = core::readFile(sourceRoot() + "/" + prelude);
    for (const char* decl : {"uniform vec3 SigmaA;", "uniform float Scale;", "const float PI"}) {
        SCOPED_TRACE(decl);
        const Location l = locate(out.glsl, decl);
        EXPECT_EQ(l.source, ps);
        EXPECT_EQ(l.line, lineContaining(text, decl));
    }
    EXPECT_EQ(out.glsl.find("#include"), std::string::npos);
}

TEST(BssrdfAssembly, NestedIncludesAndReturnLines) {
    auto resolve = tableResolver(
        {{"a.glsl", "A1\n#include \"b.glsl\"\nA3_TOKEN\n"}, {"b.glsl", "B1\nB2_TOKEN\n"}});
    const auto out = bssrdf::assemble("#version 450\n#include \"a.glsl\"\nT3_TOKEN\n",
                                      "shaders/t.comp", nullptr, resolve);
    const int a = sourceOf(out.map, "shaders/a.glsl");
    const int b = sourceOf(out.map, "shaders/b.glsl");
    EXPECT_EQ(locate(out.glsl, "B2_TOKEN").source, b);
    EXPECT_EQ(locate(out.glsl, "B2_TOKEN").line, 2);
    EXPECT_EQ(locate(out.glsl, "A3_TOKEN").source, a);
    EXPECT_EQ(locate(out.glsl, "A3_TOKEN").line, 3);
    EXPECT_EQ(locate(out.glsl, "T3_TOKEN").source, 0);
    EXPECT_EQ(locate(out.glsl, "T3_TOKEN").line, 3);
    // without a model nothing model-specific is added
    EXPECT_EQ(out.glsl.find("BSSRDF_"), std::string::npos);
}

TEST(BssrdfAssembly, IncludeCycleIsAnError) {
    auto resolve =
        tableResolver({{"a.glsl", "\n#include \"b.glsl\"\n"}, {"b.glsl", "#include \"a.glsl\"\n"}});
    try {
        bssrdf::assemble("#version 450\n#include \"a.glsl\"\n", "shaders/t.comp", nullptr, resolve);
        FAIL() << "expected an include cycle error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/b.glsl");
        EXPECT_EQ(e.line(), 1);
        EXPECT_NE(e.message().find("include cycle: shaders/t.comp -> shaders/a.glsl -> "
                                   "shaders/b.glsl -> shaders/a.glsl"),
                  std::string::npos)
            << e.message();
    }
}

TEST(BssrdfAssembly, MissingIncludeReportsIncludingLine) {
    try {
        bssrdf::assemble("#version 450\n\n#include \"nope.glsl\"\n", "shaders/t.comp", nullptr,
                         tableResolver({}));
        FAIL() << "expected an error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/t.comp");
        EXPECT_EQ(e.line(), 3);
        EXPECT_NE(e.message().find("cannot include \"nope.glsl\""), std::string::npos);
    }
}

TEST(BssrdfAssembly, PragmaWithoutModelIsAnError) {
    try {
        bssrdf::assemble(kTemplate, "shaders/test.frag", nullptr, repoResolver);
        FAIL() << "expected an error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/test.frag");
        EXPECT_EQ(e.line(), 4);
        EXPECT_NE(e.message().find("#pragma bssrdf_model"), std::string::npos);
    }
}

TEST(BssrdfAssembly, TemplateMustStartWithVersion) {
    EXPECT_THROW(bssrdf::assemble("void main() {}\n", "t.frag", nullptr, tableResolver({})),
                 core::Error);
    EXPECT_THROW(bssrdf::assemble("", "t.frag", nullptr, tableResolver({})), core::Error);
    try {
        bssrdf::assemble("#version 450\n#include \"v.glsl\"\n", "t.frag", nullptr,
                         tableResolver({{"v.glsl", "\n#version 450\n"}}));
        FAIL() << "expected an error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "shaders/v.glsl");
        EXPECT_EQ(e.line(), 2);
    }
}

TEST(BssrdfAssembly, DefinesAndDefaultsForModelWithoutOptionalSections) {
    const auto model = bssrdf::parseModel(kModelText, kPath); // no initializer, no Rd
    const auto out = bssrdf::assemble(kTemplate, "shaders/test.frag", &model, repoResolver);
    EXPECT_NE(out.glsl.find("#define BSSRDF_RADIAL 1\n"), std::string::npos);
    EXPECT_EQ(out.glsl.find("BSSRDF_NO_WI"), std::string::npos);
    EXPECT_EQ(out.glsl.find("BSSRDF_NO_WO"), std::string::npos);
    const size_t noRd = out.glsl.find("#define BSSRDF_NO_DIFFUSE_REFLECTANCE");
    ASSERT_NE(noRd, std::string::npos);
    EXPECT_LT(noRd, out.glsl.find("uniform float Gain;"));
    EXPECT_LT(noRd, out.glsl.find("FIRST_TOKEN"));
    // the default init() is reported at the pragma line of the template
    const Location init = locate(out.glsl, "void init() {}");
    EXPECT_EQ(init.source, 0);
    EXPECT_EQ(init.line, 4);
    // the line after the defines is template line 2
    const auto plain =
        bssrdf::assemble("#version 450\nSECOND_TOKEN\n", "t.frag", &model, tableResolver({}));
    EXPECT_EQ(plain.glsl.rfind("#version 450\n", 0), 0u);
    EXPECT_EQ(locate(plain.glsl, "SECOND_TOKEN").source, 0);
    EXPECT_EQ(locate(plain.glsl, "SECOND_TOKEN").line, 2);
}

TEST(BssrdfAssembly, DipoleSectionsInOrder) {
    const auto model =
        bssrdf::loadModel(sourceRoot() + "/materials/dipole.bssrdf", "materials/dipole.bssrdf");
    const auto out = bssrdf::assemble(kTemplate, "shaders/test.frag", &model, repoResolver);
    for (const char* d : {"BSSRDF_RADIAL", "BSSRDF_NO_WI", "BSSRDF_NO_WO"})
        EXPECT_NE(out.glsl.find(std::string("#define ") + d + " 1\n"), std::string::npos) << d;
    EXPECT_EQ(out.glsl.find("BSSRDF_NO_DIFFUSE_REFLECTANCE"), std::string::npos);
    const size_t u = out.glsl.find("uniform float Multiplier;");
    const size_t i = out.glsl.find("void init()");
    const size_t r = out.glsl.find("vec3 DiffuseReflectance(");
    const size_t b = out.glsl.find("vec3 Bssrdf(");
    ASSERT_NE(u, std::string::npos);
    EXPECT_LT(u, i);
    EXPECT_LT(i, r);
    EXPECT_LT(r, b);
    const Location l = locate(out.glsl, "vec3 DiffuseReflectance(");
    EXPECT_EQ(out.map.files.at(l.source), "materials/dipole.bssrdf");
    EXPECT_EQ(l.line, lineContaining(model.source, "vec3 DiffuseReflectance("));
}

TEST(BssrdfAssembly, SampleSectionOnlyWhereTheTemplateAsksForIt) {
    const auto model =
        bssrdf::parseModel(kModelText + "::begin sample\n"                         // 13
                                        "float MaxRadius(int c) { return 1.0; }\n" // 14
                                        "float PdfRadius(float r, int c) { return 2.0*r; }\n"
                                        "float SampleRadius(float x, int c) { return x; }\n"
                                        "::end sample\n",
                           kPath);
    const auto out = bssrdf::assemble(kTemplate, "shaders/test.frag", &model, repoResolver);
    EXPECT_NE(out.glsl.find("#define BSSRDF_HAS_SAMPLE 1\n"), std::string::npos);
    EXPECT_EQ(out.glsl.find("BSSRDF_HAS_LOBES"), std::string::npos);
    // the section follows the shader section, inside #if defined(BSSRDF_WANT_SAMPLE)
    const size_t want = out.glsl.find("#if defined(BSSRDF_WANT_SAMPLE)\n");
    ASSERT_NE(want, std::string::npos);
    EXPECT_LT(out.glsl.find("vec3 Bssrdf("), want);
    EXPECT_LT(want, out.glsl.find("float MaxRadius("));
    EXPECT_LT(out.glsl.find("float SampleRadius("), out.glsl.find("#endif\n", want));
    const Location l = locate(out.glsl, "float MaxRadius(");
    EXPECT_EQ(out.map.files.at(l.source), kPath);
    EXPECT_EQ(l.line, 14);
    // the template's next line is still mapped to the template
    EXPECT_EQ(locate(out.glsl, "TEMPLATE_TOKEN").source, 0);
    EXPECT_EQ(locate(out.glsl, "TEMPLATE_TOKEN").line, 5);
    // a model without the section assembles as before
    const auto plain = bssrdf::parseModel(kModelText, kPath);
    const auto p = bssrdf::assemble(kTemplate, "shaders/test.frag", &plain, repoResolver);
    EXPECT_EQ(p.glsl.find("BSSRDF_WANT_SAMPLE"), std::string::npos);
    EXPECT_EQ(p.glsl.find("BSSRDF_HAS_SAMPLE"), std::string::npos);
}

TEST(BssrdfAssembly, UniformDeclarations) {
    const auto model = bssrdf::parseModel(
        "analytic\n::begin parameters\nfloat M 0 1 1\nbool B true\ncolor C 1 0 0\n"
        "::end parameters\n" +
            kShader,
        kPath);
    EXPECT_EQ(bssrdf::uniformDeclarations(model),
              "uniform float M;\nuniform bool B;\nuniform vec3 C;\n");
}
