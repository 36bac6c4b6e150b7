// .bssrdf parser (thesis Appendix A.2): shipped models, file-level structure and every error.
#include "test_util.h"

#include <algorithm>

using namespace bssrdf_test;
using bssrdf::ParamType;

namespace {

bssrdf::Model loadShipped(const std::string& name) {
    return bssrdf::loadModel(sourceRoot() + "/materials/" + name + ".bssrdf",
                             "materials/" + name + ".bssrdf");
}

// The section's first code line is the line after its ::begin, and its text matches the file.
void expectSectionAt(const bssrdf::Model& m, const std::optional<bssrdf::Section>& s,
                     const std::string& name) {
    ASSERT_TRUE(s.has_value()) << name;
    EXPECT_EQ(s->name, name);
    EXPECT_EQ(s->beginLine, lineContaining(m.source, "::begin " + name));
    EXPECT_EQ(s->firstLine, s->beginLine + 1);
    const int endLine = lineContaining(m.source, "::end " + name);
    EXPECT_EQ(std::count(s->code.begin(), s->code.end(), '\n'), endLine - s->firstLine);
}

} // namespace

TEST(BssrdfParser, DipoleMatchesThesisListing) {
    const auto m = loadShipped("dipole");
    EXPECT_EQ(m.path, "materials/dipole.bssrdf");
    EXPECT_EQ(m.name, "dipole");
    EXPECT_EQ(m.hash, core::hashHex(m.source));
    EXPECT_TRUE(m.attrs.analytic && m.attrs.radial && m.attrs.noWi && m.attrs.noWo);
    ASSERT_EQ(m.params.size(), 1u);
    const bssrdf::Param* p = m.findParam("Multiplier");
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(p->type, ParamType::Float);
    EXPECT_EQ(p->min, 0.0f);
    EXPECT_EQ(p->max, 10.0f);
    EXPECT_EQ(p->value[0], 1.0f);
    EXPECT_EQ(p->line, lineContaining(m.source, "float Multiplier"));
    EXPECT_EQ(m.findParam("Nope"), nullptr);
    expectSectionAt(m, m.initializer, "initializer");
    expectSectionAt(m, m.diffuseReflectance, "diffuseReflectance");
    expectSectionAt(m, m.shader, "shader");
    EXPECT_NE(m.shader->code.find("Multiplier/(4.0*PI)*AlphaPrime"), std::string::npos);
    EXPECT_TRUE(m.notes.empty());
}

TEST(BssrdfParser, BetterDipoleParses) {
    const auto m = loadShipped("better_dipole");
    EXPECT_EQ(m.name, "better_dipole");
    EXPECT_TRUE(m.attrs.analytic && m.attrs.radial && m.attrs.noWi && m.attrs.noWo);
    EXPECT_TRUE(m.params.empty());
    expectSectionAt(m, m.initializer, "initializer");
    expectSectionAt(m, m.diffuseReflectance, "diffuseReflectance");
    expectSectionAt(m, m.shader, "shader");
    EXPECT_TRUE(m.notes.empty());
}

TEST(BssrdfParser, CrlfFileParsesLikeLf) {
    const auto lf = loadShipped("dipole");
    std::string crlf;
    for (char c : lf.source) {
        if (c == '\n') crlf += '\r';
        crlf += c;
    }
    const auto m = bssrdf::parseModel(crlf, "materials/dipole.bssrdf");
    EXPECT_EQ(m.shader->code, lf.shader->code);
    EXPECT_EQ(m.shader->firstLine, lf.shader->firstLine);
    EXPECT_EQ(m.initializer->code, lf.initializer->code);
    ASSERT_EQ(m.params.size(), 1u);
    EXPECT_EQ(m.params[0].line, lf.params[0].line);
    EXPECT_EQ(m.shader->code.find('\r'), std::string::npos);
}

TEST(BssrdfParser, CommentsAndBlankLinesBeforeAttributesAndBetweenSections) {
    const std::string text =
        "# header\n\n  analytic   radial\n# between\n\n" + kShader + "   # trailing\n";
    const auto m = bssrdf::parseModel(text, kPath);
    EXPECT_TRUE(m.attrs.radial);
    EXPECT_FALSE(m.attrs.noWi);
    EXPECT_EQ(m.shader->beginLine, 6);
    EXPECT_EQ(m.shader->firstLine, 7);
    EXPECT_FALSE(m.initializer.has_value());
    EXPECT_FALSE(m.diffuseReflectance.has_value());
}

TEST(BssrdfParser, SectionCodeIsVerbatimIncludingHashLines) {
    const std::string text = "analytic\n::begin shader\n#define K 2.0\n\n  // c\n"
                             "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { return vec3(K); }\n"
                             "::end shader\n";
    const auto m = bssrdf::parseModel(text, kPath);
    EXPECT_EQ(m.shader->code, "#define K 2.0\n\n  // c\nvec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, "
                              "vec3 Wo) { return vec3(K); }\n");
}

TEST(BssrdfParser, UnknownSectionIsANoteNotAnError) {
    const std::string text = "analytic\n::begin foo\nanything ::: here\n::end foo\n" + kShader;
    const auto m = bssrdf::parseModel(text, kPath);
    ASSERT_EQ(m.notes.size(), 1u);
    EXPECT_NE(m.notes[0].find("materials/t.bssrdf:2: unknown section 'foo' ignored"),
              std::string::npos)
        << m.notes[0];
}

TEST(BssrdfParser, LoadMissingFileReportsDisplayPath) {
    try {
        bssrdf::loadModel("/nonexistent/x.bssrdf", "materials/x.bssrdf");
        FAIL() << "expected an error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "materials/x.bssrdf");
        EXPECT_EQ(e.line(), 0);
    }
}

// ---- file-level errors -------------------------------------------------------------------

TEST(BssrdfParserErrors, EmptyFile) {
    expectParseError("", 1, "empty file: expected an attribute line starting with 'analytic'");
    expectParseError("\n\n", 2, "empty file");
}

TEST(BssrdfParserErrors, CommentsOnly) {
    expectParseError("# a model\n\n# nothing else\n", 3, "empty file: expected an attribute");
}

TEST(BssrdfParserErrors, BinaryNulByte) {
    std::string text = "analytic\n::begin shader\n";
    text += std::string("ab\0cd\n", 6);
    expectParseError(text, 3, "not a UTF-8 text file (invalid byte at offset 26)");
}

TEST(BssrdfParserErrors, InvalidUtf8) {
    expectParseError("analytic\n\n# caf\xC3(\n" + kShader, 3,
                     "not a UTF-8 text file (invalid byte at offset 15)");
    expectParseError("\xFF\xFE"
                     "a\0n",
                     1, "not a UTF-8 text file (invalid byte at offset 0)");
}

TEST(BssrdfParserErrors, MissingAnalytic) {
    expectParseError("radial no_wi\n" + kShader, 1, "missing mandatory attribute 'analytic'");
    expectParseError("# c\n" + kShader, 2, "missing mandatory attribute 'analytic'");
}

TEST(BssrdfParserErrors, UnknownAttribute) {
    expectParseError("\nanalytic shiny\n" + kShader, 2, "unknown attribute 'shiny'");
}

TEST(BssrdfParserErrors, DuplicateAttribute) {
    expectParseError("analytic radial radial\n" + kShader, 1, "duplicate attribute 'radial'");
}

TEST(BssrdfParserErrors, UnterminatedSectionReportsBeginLine) {
    expectParseError("analytic\n\n::begin shader\nvec3 Bssrdf(vec3 Xi) {}\n\n", 3,
                     "section 'shader' is not terminated (missing '::end shader')");
}

TEST(BssrdfParserErrors, NestedBegin) {
    expectParseError("analytic\n::begin shader\nint x;\n::begin parameters\n::end parameters\n"
                     "::end shader\n",
                     4, "nested '::begin' inside section 'shader' (opened at line 2)");
}

TEST(BssrdfParserErrors, EndNameMismatch) {
    expectParseError("analytic\n::begin parameters\n::end shader\n" + kShader, 3,
                     "'::end shader' does not match '::begin parameters'");
}

TEST(BssrdfParserErrors, EndWithoutName) {
    expectParseError("analytic\n::begin parameters\n::end\n" + kShader, 3,
                     "'::end' without a section name");
}

TEST(BssrdfParserErrors, EndWithoutBegin) {
    expectParseError("analytic\n\n::end shader\n" + kShader, 3,
                     "'::end shader' without a matching '::begin'");
}

// A loop in a macro escapes the loop budget's rewrite (bssrdf/loop_budget.h), which leaves
// preprocessor lines alone: refused at the #define's line, also when continued over lines,
// indented, or made by pasting tokens; a macro without a loop, or naming one in a comment, stays.
TEST(BssrdfParserErrors, AMacroThatLoopsIsRefusedAtItsLine) {
    const std::string head = "analytic\n::begin shader\n";
    const std::string tail =
        "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { return vec3(1.0); }\n::end shader\n";
    expectParseError(head + "#define SPIN while (true) {}\n" + tail, 3,
                     "a macro that loops (for, while or do) or pastes tokens (##)");
    expectParseError(
        head + "float x;\n  #  define REPEAT(n) \\\n    for (int i = 0; i < n; ++i)\n" + tail, 4,
        "a macro that loops");
    expectParseError(head + "#define GLUE(a, b) a##b\n" + tail, 3, "pastes tokens (##)");
    expectParseError("analytic\n::begin initializer\n#define D do { } while (false)\n"
                     "void init() {}\n::end initializer\n" +
                         kShader,
                     3, "a macro that loops");
    const auto ok = bssrdf::parseModel(head + "#define STEP x = sin(x); // not a while loop\n" +
                                           "#define formula 2.0\n" + tail,
                                       kPath);
    EXPECT_TRUE(ok.shader.has_value());
}

TEST(BssrdfParserErrors, DuplicateSection) {
    expectParseError("analytic\n" + kShader + "\n" + kShader, 6,
                     "duplicate section 'shader' (first opened at line 2)");
}

TEST(BssrdfParserErrors, BeginWithoutName) {
    expectParseError("analytic\n::begin   \n::end\n", 2, "'::begin' without a section name");
}

TEST(BssrdfParserErrors, BeginWithTwoNames) {
    expectParseError("analytic\n::begin shader extra\n", 2, "extra text 'extra'");
}

TEST(BssrdfParserErrors, StrayTextOutsideSections) {
    expectParseError("analytic\n" + kShader + "float x;\n", 5,
                     "unexpected text outside a section: 'float x;'");
}

TEST(BssrdfParserErrors, UnknownDirective) {
    expectParseError("analytic\n::start shader\n", 2, "unknown directive '::start'");
    expectParseError("analytic\n::begin shader\n::ned shader\n", 3, "unknown directive '::ned'");
}

TEST(BssrdfParserErrors, MissingShaderSection) {
    expectParseError("analytic\n::begin parameters\nfloat X 0 1 0.5\n::end parameters\n", 4,
                     "missing ::begin shader section");
}

TEST(BssrdfParserErrors, ShaderWithoutBssrdf) {
    expectParseError("analytic\n\n::begin shader\nvec3 Foo() { return vec3(0); }\n::end shader\n",
                     3,
                     "section 'shader' does not define vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, "
                     "vec3 Wo)");
    // a commented-out definition does not count
    expectParseError("analytic\n::begin shader\n// vec3 Bssrdf(vec3 Xi) {}\n"
                     "/* vec3 Bssrdf(\n */\n::end shader\n",
                     2, "does not define vec3 Bssrdf(");
}

TEST(BssrdfParserErrors, DiffuseReflectanceWithoutFunction) {
    expectParseError("analytic\n" + kShader +
                         "::begin diffuseReflectance\nvec3 Rd(vec3 a) { return a; }\n"
                         "::end diffuseReflectance\n",
                     5, "section 'diffuseReflectance' does not define vec3 DiffuseReflectance(");
}

TEST(BssrdfParserErrors, InitializerWithoutInit) {
    expectParseError("analytic\n::begin initializer\nfloat k;\n::end initializer\n" + kShader, 2,
                     "section 'initializer' does not define void init()");
}

TEST(BssrdfParser, DefinitionsAllowWhitespace) {
    const std::string text = "analytic\n::begin initializer\nvoid  init ( ) {}\n"
                             "::end initializer\n::begin shader\nvec3\n  Bssrdf (vec3 Xi, vec3 "
                             "Wi, vec3 Xo, vec3 Wo) { return Xi; }\n::end shader\n";
    EXPECT_NO_THROW(bssrdf::parseModel(text, kPath));
}

// The optional analytic sampler: `::begin sample` with SampleRadius, PdfRadius and MaxRadius.
namespace {
const std::string kSample = "::begin sample\n"                                           // 5
                            "float MaxRadius(int c) { return 1.0; }\n"                   // 6
                            "float PdfRadius(float r, int c) { return 2.0*r; }\n"        // 7
                            "float SampleRadius(float xi, int c) { return sqrt(xi); }\n" // 8
                            "::end sample\n";                                            // 9
} // namespace

TEST(BssrdfParser, SampleSectionParses) {
    const auto m = bssrdf::parseModel("analytic radial\n" + kShader + kSample, kPath);
    expectSectionAt(m, m.sample, "sample");
    EXPECT_EQ(m.sample->beginLine, 5);
    EXPECT_NE(m.sample->code.find("float PdfRadius(float r, int c)"), std::string::npos);
    EXPECT_TRUE(m.notes.empty());
    EXPECT_EQ(m.lobesLine, 0);
    EXPECT_FALSE(bssrdf::parseModel("analytic\n" + kShader, kPath).sample.has_value());
}

TEST(BssrdfParserErrors, SampleSectionWithoutItsFunctions) {
    auto without = [](const std::string& function) {
        std::string s = kSample;
        const size_t at = s.find("float " + function);
        s.replace(at, s.find('\n', at) - at, "// " + function + " is missing");
        return "analytic radial\n" + kShader + s;
    };
    expectParseError(without("SampleRadius"), 5,
                     "section 'sample' does not define float SampleRadius(float xi, int channel)");
    expectParseError(without("PdfRadius"), 5,
                     "section 'sample' does not define float PdfRadius(float r, int channel)");
    expectParseError(without("MaxRadius"), 5,
                     "section 'sample' does not define float MaxRadius(int channel)");
    // structural errors are reported as for every section
    expectParseError("analytic\n" + kShader + "::begin sample\nfloat MaxRadius(int c);\n", 5,
                     "section 'sample' is not terminated");
    expectParseError("analytic\n" + kShader + kSample + kSample, 10,
                     "duplicate section 'sample' (first opened at line 5)");
    expectParseError("analytic\n" + kShader + "::begin sample\n::end shader\n", 6,
                     "'::end shader' does not match '::begin sample'");
}

TEST(BssrdfParser, LobeInterfaceIsFoundWithItsLine) {
    const std::string lobes = "::begin shader\n"                                        // 2
                              "int QdLobeCount() { return 1; }\n"                       // 3
                              "/* vec2 QdLobe( */\n"                                    // 4
                              "vec2 QdLobe(int k, int channel) { return vec2(1.0); }\n" // 5
                              "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { return Xi; }\n"
                              "::end shader\n";
    EXPECT_EQ(bssrdf::parseModel("analytic radial\n" + lobes, kPath).lobesLine, 5);
    EXPECT_EQ(bssrdf::parseModel("analytic\n" + kShader, kPath).lobesLine, 0);
    const auto qd = bssrdf::loadModel(sourceRoot() + "/materials/quantized_diffusion.bssrdf",
                                      "materials/quantized_diffusion.bssrdf");
    EXPECT_EQ(qd.lobesLine, lineContaining(qd.source, "vec2 QdLobe(int k"));
    // one of the two functions alone is an error at its definition
    std::string noCount = lobes;
    noCount.replace(noCount.find("int QdLobeCount"), 3, "// ");
    expectParseError("analytic radial\n" + noCount, 5,
                     "'vec2 QdLobe(int k, int channel)' is defined but 'int QdLobeCount()' is not");
    std::string noLobe = lobes;
    noLobe.replace(noLobe.find("vec2 QdLobe(int"), 4, "vec3");
    expectParseError("analytic radial\n" + noLobe, 3,
                     "'int QdLobeCount()' is defined but 'vec2 QdLobe(int k, int channel)' is not");
}
