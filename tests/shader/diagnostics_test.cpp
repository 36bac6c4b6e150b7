// Driver info logs (Mesa, NVIDIA, glslang/AMD, Intel) mapped back through a SourceMap.
#include "shader/diagnostics.h"

#include <gtest/gtest.h>

#include <string>

namespace {

const std::string kPath = "materials/t.bssrdf";

shader::SourceMap sampleMap() {
    return shader::SourceMap{{"shaders/pencil.frag", "shaders/common/bssrdf_prelude.glsl", kPath}};
}

} // namespace

TEST(BssrdfDiagnostics, Mesa) {
    const auto d = shader::parseDriverLog(
        "0:12(5): error: `Foo' undeclared\n0:3(1): warning: unused variable\n", sampleMap());
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(d[0].file, "shaders/pencil.frag");
    EXPECT_EQ(d[0].line, 12);
    EXPECT_EQ(d[0].column, 5);
    EXPECT_EQ(d[0].severity, "error");
    EXPECT_EQ(d[0].message, "`Foo' undeclared");
    EXPECT_EQ(d[1].severity, "warning");
    EXPECT_EQ(d[1].line, 3);
}

TEST(BssrdfDiagnostics, MesaModelSourceAndPreprocessorError) {
    const auto d = shader::parseDriverLog("2:17(22): preprocessor error: syntax error, unexpected "
                                          "IDENTIFIER\n",
                                          sampleMap());
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0].file, kPath);
    EXPECT_EQ(d[0].line, 17);
    EXPECT_EQ(d[0].severity, "error");
    EXPECT_EQ(d[0].message, "syntax error, unexpected IDENTIFIER");
}

TEST(BssrdfDiagnostics, Nvidia) {
    const auto d = shader::parseDriverLog(
        "2(7) : error C1008: undefined variable \"Foo\"\n"
        "1(3) : warning C7050: \"x\" might be used before being initialized\n",
        sampleMap());
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(d[0].file, kPath);
    EXPECT_EQ(d[0].line, 7);
    EXPECT_EQ(d[0].severity, "error");
    EXPECT_EQ(d[0].message, "C1008: undefined variable \"Foo\"");
    EXPECT_EQ(d[1].file, "shaders/common/bssrdf_prelude.glsl");
    EXPECT_EQ(d[1].severity, "warning");
}

TEST(BssrdfDiagnostics, GlslangAndAmd) {
    const auto d = shader::parseDriverLog("ERROR: 2:9: 'Foo' : undeclared identifier\n"
                                          "WARNING: 0:3: '' : extension not supported\n"
                                          "ERROR: 1 compilation errors.  No code generated.\n",
                                          sampleMap());
    ASSERT_EQ(d.size(), 2u);
    EXPECT_EQ(d[0].file, kPath);
    EXPECT_EQ(d[0].line, 9);
    EXPECT_EQ(d[0].severity, "error");
    EXPECT_EQ(d[0].message, "'Foo' : undeclared identifier");
    EXPECT_EQ(d[1].file, "shaders/pencil.frag");
    EXPECT_EQ(d[1].line, 3);
    EXPECT_EQ(d[1].severity, "warning");
}

TEST(BssrdfDiagnostics, IntelWindows) {
    const auto d = shader::parseDriverLog("ERROR: 0:12: syntax error\r\n", sampleMap());
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0].line, 12);
    EXPECT_EQ(d[0].message, "syntax error");
}

TEST(BssrdfDiagnostics, UnknownSourceNumber) {
    const auto d = shader::parseDriverLog("7:1(1): error: x\n", sampleMap());
    ASSERT_EQ(d.size(), 1u);
    EXPECT_EQ(d[0].file, "<source 7>");
}

TEST(BssrdfDiagnostics, EncodedLinesNameTheFileEvenWhenMesaSaysSourceZero) {
    // assemble() emits line L of source 2 as 2*kLineStride + L; Mesa reports source 0 for
    // semantic errors but keeps the line, NVIDIA/glslang keep both.
    const int encoded = shader::encodeLine(2, 107);
    EXPECT_EQ(encoded, 2 * shader::kLineStride + 107);
    const std::string l = std::to_string(encoded);
    const auto d = shader::parseDriverLog("0:" + l + "(33): error: `Foo' undeclared\n" + "2(" + l +
                                              ") : error C1008: undefined\n" + "ERROR: 2:" + l +
                                              ": 'Foo' : undeclared\n",
                                          sampleMap());
    ASSERT_EQ(d.size(), 3u);
    for (const auto& x : d) {
        EXPECT_EQ(x.file, kPath);
        EXPECT_EQ(x.line, 107);
    }
    EXPECT_EQ(shader::encodeLine(0, 12), 12);
}

TEST(BssrdfDiagnostics, FormatMapsToUserFile) {
    EXPECT_EQ(
        shader::formatDiagnostics("garbage first\n2:12(5): error: `Foo' undeclared\n", sampleMap()),
        "materials/t.bssrdf:12: error: `Foo' undeclared\n");
}

TEST(BssrdfDiagnostics, UnparsableLogIsReturnedRaw) {
    const std::string raw = "Internal compiler error\nsomething went wrong";
    EXPECT_TRUE(shader::parseDriverLog(raw, sampleMap()).empty());
    EXPECT_EQ(shader::formatDiagnostics(raw, sampleMap()),
              "could not parse driver log; raw log:\n" + raw);
}

// The undeclared name, as each compiler words it (Mesa's from llvmpipe; NVIDIA's and glslang's
// as their compilers print them); other messages name none.
TEST(BssrdfDiagnostics, TheUndeclaredNameIsReadFromEachCompilersWording) {
    EXPECT_EQ(shader::undeclaredName("`SigmaTPrme' undeclared"), "SigmaTPrme");
    EXPECT_EQ(shader::undeclaredName("no function with name 'exq'"), "exq");
    EXPECT_EQ(shader::undeclaredName("undefined variable \"SigmaTPrme\""), "SigmaTPrme");
    EXPECT_EQ(shader::undeclaredName("'SigmaTPrme' : undeclared identifier"), "SigmaTPrme");
    EXPECT_EQ(shader::undeclaredName("'exq' : no matching overloaded function found"), "exq");
    EXPECT_EQ(shader::undeclaredName("syntax error, unexpected ';'"), "");
    EXPECT_EQ(shader::undeclaredName("operands to arithmetic operators must be numeric"), "");
}

// The nearest identifier of the source (or a built-in function): one edit for short names, two
// for longer ones, a swap of neighbours one edit; the name itself, numbers' suffixes and
// names too far or too short suggest nothing.
TEST(BssrdfDiagnostics, TheNearestIdentifierIsOneOrTwoEditsAway) {
    const std::string src = "vec3 SigmaTPrime = SigmaA + SigmaS; float A = 1.0e3f;\n"
                            "vec3 SigmaTPrme2 = vec3(0.0); float Lu = 2.0;";
    EXPECT_EQ(shader::nearestIdentifier("SigmaTPrme", src), "SigmaTPrime");  // first in source
    EXPECT_EQ(shader::nearestIdentifier("SigmaTPirme", src), "SigmaTPrime"); // a swap
    EXPECT_EQ(shader::nearestIdentifier("SgmaTPrme", src), "SigmaTPrime");   // two edits
    EXPECT_EQ(shader::nearestIdentifier("exq", src), "exp");                 // a built-in
    EXPECT_EQ(shader::nearestIdentifier("sqtr", src), "sqrt");
    EXPECT_EQ(shader::nearestIdentifier("SigmaQQQ", src), ""); // three edits
    EXPECT_EQ(shader::nearestIdentifier("Sgma", src), "");     // short: one edit at most
    EXPECT_EQ(shader::nearestIdentifier("Lx", src), "");       // shorter than 3
    EXPECT_EQ(shader::nearestIdentifier("e3g", src), "");      // "1.0e3f" is a number
    EXPECT_EQ(shader::nearestIdentifier("SigmaTPrime", "vec3 SigmaTPrime;"), ""); // itself
}
