// The 'parameters' section: accepted forms and every rejected declaration, with exact lines.
#include "test_util.h"

#include <algorithm>

using namespace bssrdf_test;
using bssrdf::ParamType;

namespace {

// A model whose parameters section holds `body`; the first body line is file line 4.
std::string withParams(const std::string& body) {
    return "analytic\n\n::begin parameters\n" + body + "::end parameters\n" + kShader;
}

} // namespace

TEST(BssrdfParams, AcceptedForms) {
    const auto m = bssrdf::parseModel(
        withParams("# comment\n\nfloat Gain -1 +2.5 0.25   # trailing comment\n"
                   "bool Flip true\nbool Off 0\ncolor Tint 0.5 1 2\nfloat Fixed 3 3 3\n"),
        kPath);
    ASSERT_EQ(m.params.size(), 5u);
    const auto* gain = m.findParam("Gain");
    ASSERT_NE(gain, nullptr);
    EXPECT_EQ(gain->type, ParamType::Float);
    EXPECT_EQ(gain->min, -1.0f);
    EXPECT_EQ(gain->max, 2.5f);
    EXPECT_EQ(gain->value[0], 0.25f);
    EXPECT_EQ(gain->line, 6);
    EXPECT_EQ(m.findParam("Flip")->type, ParamType::Bool);
    EXPECT_EQ(m.findParam("Flip")->value[0], 1.0f);
    EXPECT_EQ(m.findParam("Off")->value[0], 0.0f);
    const auto* tint = m.findParam("Tint");
    EXPECT_EQ(tint->type, ParamType::Color);
    EXPECT_EQ(tint->value[0], 0.5f);
    EXPECT_EQ(tint->value[1], 1.0f);
    EXPECT_EQ(tint->value[2], 2.0f);
    EXPECT_EQ(tint->line, 9);
    EXPECT_EQ(m.params[4].name, "Fixed");
}

TEST(BssrdfParams, UnknownType) {
    expectParseError(withParams("float A 0 1 0.5\nint N 0 10 3\n"), 5,
                     "unknown parameter type 'int' (expected float, bool or color)");
}

TEST(BssrdfParams, TooFewFields) {
    expectParseError(withParams("float X 0 1\n"), 4, "too few fields for a float parameter");
    expectParseError(withParams("bool B\n"), 4, "too few fields for a bool parameter");
    expectParseError(withParams("\ncolor C 1 0\n"), 5, "too few fields for a color parameter");
    expectParseError(withParams("float\n"), 4, "expected 'float NAME MIN MAX DEFAULT'");
}

TEST(BssrdfParams, TooManyFields) {
    expectParseError(withParams("float X 0 1 0.5 7\n"), 4, "too many fields for a float");
    expectParseError(withParams("bool B true false\n"), 4, "too many fields for a bool");
    expectParseError(withParams("color C 1 0 0 1\n"), 4, "too many fields for a color");
}

TEST(BssrdfParams, NonNumeric) {
    expectParseError(withParams("float X zero 1 0.5\n"), 4, "minimum 'zero' is not a number");
    expectParseError(withParams("float X 0 1 0.5f\n"), 4, "default '0.5f' is not a number");
    expectParseError(withParams("color C 1 0,5 0\n"), 4, "green '0,5' is not a number");
}

TEST(BssrdfParams, NonFinite) {
    expectParseError(withParams("float X 0 inf 0.5\n"), 4, "maximum 'inf' is not a finite number");
    expectParseError(withParams("float X nan 1 0.5\n"), 4, "minimum 'nan' is not a finite");
    expectParseError(withParams("color C 1e99 0 0\n"), 4, "red '1e99' is not a finite number");
}

TEST(BssrdfParams, MinGreaterThanMax) {
    expectParseError(withParams("float X 2 1 1.5\n"), 4, "minimum '2' is greater than maximum '1'");
}

TEST(BssrdfParams, DefaultOutsideRange) {
    expectParseError(withParams("float X 0 1 1.5\n"), 4, "default '1.5' is outside [0, 1]");
    expectParseError(withParams("float X 0 1 -0.1\n"), 4, "default '-0.1' is outside [0, 1]");
}

TEST(BssrdfParams, BadBoolDefault) {
    expectParseError(withParams("bool B yes\n"), 4,
                     "invalid bool default 'yes' (expected true, false, 1 or 0)");
}

TEST(BssrdfParams, DuplicateNames) {
    expectParseError(withParams("float X 0 1 0.5\nbool Y true\ncolor X 1 1 1\n"), 6,
                     "duplicate parameter 'X' (first declared at line 4)");
}

TEST(BssrdfParams, BuiltinClash) {
    expectParseError(withParams("float SigmaA 0 1 0.5\n"), 4,
                     "parameter name 'SigmaA' clashes with a built-in name");
    expectParseError(withParams("bool init true\n"), 4, "'init' clashes with a built-in");
    expectParseError(withParams("float PI 0 4 3\n"), 4, "'PI' clashes with a built-in");
}

TEST(BssrdfParams, InvalidIdentifier) {
    for (const char* bad : {"2x", "gl_Foo", "a__b", "x-y", "float", "uniform", "vec3"}) {
        SCOPED_TRACE(bad);
        expectParseError(withParams(std::string("float ") + bad + " 0 1 0.5\n"), 4,
                         std::string("invalid parameter name '") + bad + "'");
    }
}

TEST(BssrdfParams, IdentifierRules) {
    EXPECT_TRUE(bssrdf::isValidIdentifier("_x1"));
    EXPECT_TRUE(bssrdf::isValidIdentifier("Multiplier"));
    EXPECT_TRUE(bssrdf::isValidIdentifier("gl"));
    EXPECT_FALSE(bssrdf::isValidIdentifier(""));
    EXPECT_FALSE(bssrdf::isValidIdentifier("gl_Position"));
    EXPECT_FALSE(bssrdf::isValidIdentifier("a__"));
    EXPECT_FALSE(bssrdf::isValidIdentifier("ä"));
}

TEST(BssrdfParams, BuiltinNamesList) {
    const auto& b = bssrdf::builtinNames();
    for (const char* n :
         {"SigmaA", "SigmaS", "G", "IOR", "Scale", "PI", "Bssrdf", "DiffuseReflectance", "init",
          "main", "SampleRadius", "PdfRadius", "MaxRadius", "QdLobeCount", "QdLobe"})
        EXPECT_NE(std::find(b.begin(), b.end(), n), b.end()) << n;
    EXPECT_EQ(b.size(), 15u);
}
