// Driver errors land on the right line of the right file: real Mesa compiles of models and
// templates with planted errors, through the same path the app uses.
#include "../support/gl_fixture.h"
#include "bssrdf/program_library.h"

#include <set>

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

// A misspelt name is an undeclared one that is near a declared one: the message says which.
TEST(GlslMapping, AMisspeltNameSaysWhichNameItIsNear) {
    std::string text = replaced(dipole(), "    SigmaTr = sqrt(3.0*SigmaA*SigmaTPrime);",
                                "    SigmaTr = sqrt(3.0*SigmaA*SigmaTPrme);");
    auto p = loadModelText("typo", "typo.bssrdf", text);
    auto& e = p.lib->entries().at(0);
    ASSERT_TRUE(e.problem.has_value());
    EXPECT_EQ(e.problem->line, lineOf(text, "SigmaTPrme")) << e.problem->text();
    const std::string headline = e.problem->message.substr(0, e.problem->message.find('\n'));
    EXPECT_NE(headline.find("SigmaTPrme"), std::string::npos) << e.problem->text();
    EXPECT_NE(headline.find("; did you mean `SigmaTPrime'?"), std::string::npos)
        << e.problem->text();
    // a built-in function
    text = replaced(dipole(), "    SigmaTr = sqrt(3.0*SigmaA*SigmaTPrime);",
                    "    SigmaTr = sqtr(3.0*SigmaA*SigmaTPrime);");
    auto q = loadModelText("typo_fn", "typo_fn.bssrdf", text);
    ASSERT_TRUE(q.lib->entries().at(0).problem.has_value());
    EXPECT_NE(q.lib->entries().at(0).problem->message.find("did you mean `sqrt'?"),
              std::string::npos)
        << q.lib->entries().at(0).problem->text();
    // a name near nothing suggests nothing
    text = replaced(dipole(), "    SigmaTr = sqrt(3.0*SigmaA*SigmaTPrime);",
                    "    SigmaTr = sqrt(3.0*SigmaA*Qwertyuiop);");
    auto u = loadModelText("far", "far.bssrdf", text);
    ASSERT_TRUE(u.lib->entries().at(0).problem.has_value());
    EXPECT_EQ(u.lib->entries().at(0).problem->message.find("did you mean"), std::string::npos)
        << u.lib->entries().at(0).problem->text();
}

// An error is one headline, never listed twice (it was: the mapped message and the driver's line
// again), with what the compiler said after it folded below it: "N more compiler messages", then
// each distinct message once with its count (it was six and more lines, repeats included). How
// much follows depends on the compiler: Mesa stops at a syntax error and follows an undeclared
// name with more errors; NVIDIA goes on after a syntax error (undefined names that follow from
// it) and says an undeclared name once, "(2 times)".
static void expectOneHeadlineAndFoldedCascade(const std::string& all,
                                              const std::string& inHeadline) {
    const std::string headline = all.substr(0, all.find('\n'));
    EXPECT_NE(headline.find(inHeadline), std::string::npos) << all;
    std::vector<std::string> rest;
    for (size_t at = all.find('\n'); at != std::string::npos;) {
        const size_t next = all.find('\n', at + 1);
        rest.push_back(all.substr(at + 1, next == std::string::npos ? next : next - at - 1));
        at = next;
    }
    if (rest.empty()) return;
    EXPECT_NE(rest[0].find("more compiler message"), std::string::npos) << all;
    std::set<std::string> distinct(rest.begin(), rest.end());
    EXPECT_EQ(distinct.size(), rest.size()) << "a message repeated instead of counted:\n" << all;
    for (const std::string& line : rest)
        EXPECT_EQ(line.find(headline.substr(headline.find(": ") + 2)), std::string::npos)
            << "the headline again:\n"
            << all;
}

TEST(GlslMapping, AnErrorIsOneHeadlineAndItsCascadeIsFoldedBelowIt) {
    std::string text = replaced(dipole(), "    vec3 Zr = Lu;", "    vec3 Zr = Lu +* ;");
    auto p = loadModelText("syntax_once", "broken.bssrdf", text);
    const std::string syntax = p.lib->entries().at(0).problem->text();
    expectOneHeadlineAndFoldedCascade(syntax, "syntax error");

    text = replaced(dipole(), "    vec3 Dr = sqrt(R + Zr*Zr);",
                    "    vec3 Dr = sqrt(R + UndeclaredThing*UndeclaredThing);");
    auto q = loadModelText("cascade", "undeclared.bssrdf", text);
    const std::string all = q.lib->entries().at(0).problem->text();
    expectOneHeadlineAndFoldedCascade(all, "UndeclaredThing");
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
