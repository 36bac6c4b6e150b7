// Driver errors land on the right line of the right file: real Mesa compiles of models and
// templates with planted errors, through the same path the app uses.
#include "../support/gl_fixture.h"
#include "bssrdf/program_library.h"

using testsupport::lineOf;
using testsupport::replaced;

namespace {
struct Planted {
    std::unique_ptr<bssrdf::ModelLibrary> lib;
    std::filesystem::path root;
};
// Writes `text` as materials/<name> in a fresh root and loads it.
Planted loadModelText(const std::string& tag, const std::string& name, const std::string& text) {
    testsupport::context();
    Planted p;
    p.root = testsupport::makeProjectRoot(tag, {});
    core::writeFile(p.root / "materials" / name, text);
    p.lib = std::make_unique<bssrdf::ModelLibrary>(
        p.root, std::vector<std::string>{"pencil_profile.comp", "invert_rdr.comp"});
    p.lib->scanAll();
    return p;
}
std::string dipole() {
    return testsupport::readText(testsupport::sourceRoot() / "materials/dipole.bssrdf");
}
} // namespace

TEST(GlslMapping, SyntaxErrorInShaderSectionLandsOnItsLine) {
    std::string text = replaced(dipole(), "    vec3 Zr = Lu;", "    vec3 Zr = Lu +* ;");
    const int line = lineOf(text, "Lu +* ;");
    auto p = loadModelText("syntax", "broken.bssrdf", text);
    auto& e = p.lib->entries().at(0);
    ASSERT_TRUE(e.problem.has_value());
    EXPECT_EQ(e.problem->file, "materials/broken.bssrdf");
    EXPECT_EQ(e.problem->line, line) << e.problem->text();
    EXPECT_FALSE(e.model.has_value()); // never loaded: nothing good to keep
}

TEST(GlslMapping, TypeErrorsAndUndeclaredNamesLandOnTheirLines) {
    // Mesa reports semantic errors against source 0; the line encoding still finds the file.
    std::string text = replaced(dipole(), "    vec3 Dr = sqrt(R + Zr*Zr);",
                                "    vec3 Dr = sqrt(R + Zr*UndeclaredThing);");
    auto p = loadModelText("undeclared", "undeclared.bssrdf", text);
    auto& e = p.lib->entries().at(0);
    ASSERT_TRUE(e.problem.has_value());
    EXPECT_EQ(e.problem->file, "materials/undeclared.bssrdf");
    EXPECT_EQ(e.problem->line, lineOf(text, "UndeclaredThing")) << e.problem->text();
    EXPECT_NE(e.problem->message.find("UndeclaredThing"), std::string::npos);

    std::string typed =
        replaced(dipole(), "    A = (1.0 + Fdr)/(1.0 - Fdr);", "    A = vec2(1.0, Fdr);");
    auto q = loadModelText("type", "typed.bssrdf", typed);
    auto& f = q.lib->entries().at(0);
    ASSERT_TRUE(f.problem.has_value());
    EXPECT_EQ(f.problem->file, "materials/typed.bssrdf");
    EXPECT_EQ(f.problem->line, lineOf(typed, "vec2(1.0, Fdr)")) << f.problem->text();
}

TEST(GlslMapping, ErrorInDiffuseReflectanceSectionLandsOnItsLine) {
    std::string text = replaced(dipole(), "    vec3 T = sqrt(3.0*(1.0 - AlphaPrime));",
                                "    vec3 T = sqrt(3.0*(1.0 - AlphaPrime))");
    auto p = loadModelText("dr", "dr.bssrdf", text);
    auto& e = p.lib->entries().at(0);
    ASSERT_TRUE(e.problem.has_value());
    EXPECT_EQ(e.problem->file, "materials/dr.bssrdf");
    // a missing ';' is reported on the line of the next token
    const int line = lineOf(text, "vec3 T = sqrt");
    EXPECT_TRUE(e.problem->line == line || e.problem->line == line + 1) << e.problem->text();
}

TEST(GlslMapping, MissingBssrdfIsAParseError) {
    std::string text = replaced(dipole(), "vec3 Bssrdf(vec3 Xi", "vec3 NotBssrdf(vec3 Xi");
    auto p = loadModelText("missing", "missing.bssrdf", text);
    auto& e = p.lib->entries().at(0);
    ASSERT_TRUE(e.problem.has_value());
    EXPECT_NE(e.problem->message.find("Bssrdf"), std::string::npos) << e.problem->text();
    EXPECT_EQ(e.problem->line, lineOf(text, "::begin shader"));
}

TEST(GlslMapping, ErrorInATemplateLandsOnTheTemplate) {
    testsupport::context();
    auto root = testsupport::makeProjectRoot("template", {"dipole.bssrdf"});
    std::string tpl = testsupport::readText(root / "shaders/pencil_profile.comp");
    tpl = replaced(tpl, "    init();", "    init();\n    float broken = undefinedInTemplate;");
    core::writeFile(root / "shaders/pencil_profile.comp", tpl);
    bssrdf::ModelLibrary lib(root, {"pencil_profile.comp"});
    lib.scanAll();
    auto& e = lib.entries().at(0);
    ASSERT_TRUE(e.problem.has_value());
    EXPECT_EQ(e.problem->file, "shaders/pencil_profile.comp");
    EXPECT_EQ(e.problem->line, lineOf(tpl, "undefinedInTemplate")) << e.problem->text();
}
