// Where a model loops (bssrdf/loop_sites.h): the loop statements of its GLSL sections by file
// line, none in comments, a do-while counted once; whether the inversion program can reach one.
#include "bssrdf/loop_sites.h"
#include "bssrdf/model_probe.h"

#include <gtest/gtest.h>

TEST(LoopSites, FindsEveryLoopStatementByFileLine) {
    const std::string text = "analytic radial no_wi no_wo\n"                       // 1
                             "::begin parameters\n"                                // 2
                             "float K 0 1 0.5\n"                                   // 3
                             "::end parameters\n"                                  // 4
                             "::begin shader\n"                                    // 5
                             "// a for loop in a comment\n"                        // 6
                             "/* while (true) {}\n"                                // 7
                             "   for (;;) */\n"                                    // 8
                             "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n" // 9
                             "    float s = 0.0;\n"                                // 10
                             "    for (int i = 0; i < 4; ++i) s += K;\n"           // 11
                             "    float forward = 1.0; float dowhile = 2.0;\n"     // 12
                             "    do {\n"                                          // 13
                             "        s += 1.0;\n"                                 // 14
                             "    } while (s < 2.0);\n"                            // 15
                             "    while (s > 1e9) { s -= 1.0; }\n"                 // 16
                             "    return vec3(s * forward * dowhile);\n"           // 17
                             "}\n"                                                 // 18
                             "::end shader\n";
    const bssrdf::Model m = bssrdf::parseModel(text, "materials/loops.bssrdf");
    const std::vector<bssrdf::LoopSite> loops = bssrdf::loopSites(m);
    ASSERT_EQ(loops.size(), 3u);
    EXPECT_EQ(loops[0].line, 11);
    EXPECT_EQ(loops[0].keyword, "for");
    EXPECT_EQ(loops[1].line, 13);
    EXPECT_EQ(loops[1].keyword, "do");
    EXPECT_EQ(loops[2].line, 16);
    EXPECT_EQ(loops[2].keyword, "while");
    EXPECT_EQ(bssrdf::describeLoops(loops), "loops at lines 11 (for), 13 (do), 16 (while)");
    EXPECT_EQ(bssrdf::describeLoops({loops[2]}), "the loop at line 16 (while)");
    EXPECT_EQ(bssrdf::describeLoops({}), "");
}

TEST(LoopSites, ShippedModelsWithoutLoopsHaveNone) {
    const bssrdf::Model m =
        bssrdf::loadModel(std::string(BW_SOURCE_ROOT) + "/materials/dipole.bssrdf", "dipole");
    EXPECT_TRUE(bssrdf::loopSites(m).empty());
}

// The inversion program calls init() and DiffuseReflectance(); GLSL calls only what is declared
// before, and the sections are assembled initializer, diffuseReflectance, shader: so a loop of
// the shader section alone cannot reach it, a loop in either earlier section can, and so can a
// prototype there whose body (with a loop) comes later; a comment saying `f();` is not one.
TEST(InversionMayLoop, OnlyWhenInitOrDiffuseReflectanceCanReachALoop) {
    auto model = [](const std::string& init, const std::string& dr, const std::string& shader) {
        std::string t = "analytic radial no_wi no_wo\n";
        if (!init.empty()) t += "::begin initializer\n" + init + "\n::end initializer\n";
        if (!dr.empty()) t += "::begin diffuseReflectance\n" + dr + "\n::end diffuseReflectance\n";
        t += "::begin shader\n" + shader + "\n::end shader\n";
        return bssrdf::parseModel(t, "materials/m.bssrdf");
    };
    const std::string plainDr =
        "// helper(x);\nvec3 DiffuseReflectance(vec3 AlphaPrime) { return AlphaPrime; }";
    const std::string plainShader =
        "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) { return vec3(1.0); }";
    const std::string loopShader = "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
                                   "    float s = 0.0;\n"
                                   "    for (int i = 0; i < 4; ++i) s += 1.0;\n"
                                   "    return vec3(s);\n}";
    EXPECT_FALSE(bssrdf::inversionMayLoop(model("", plainDr, plainShader)));
    EXPECT_FALSE(bssrdf::inversionMayLoop(model("", plainDr, loopShader)));
    EXPECT_FALSE(bssrdf::inversionMayLoop(model("", "", loopShader))); // no inversion program
    EXPECT_TRUE(bssrdf::inversionMayLoop(
        model("",
              "vec3 DiffuseReflectance(vec3 A) { vec3 s = A; while (s.x > 2.0) s -= 1.0; "
              "return s; }",
              plainShader)));
    EXPECT_TRUE(bssrdf::inversionMayLoop(
        model("float K;\nvoid init() { K = 0.0; for (int i = 0; i < 3; ++i) K += 1.0; }", plainDr,
              plainShader)));
    EXPECT_TRUE(bssrdf::inversionMayLoop(
        model("", "float helper(float x);\nvec3 DiffuseReflectance(vec3 A) { return A; }",
              "float helper(float x) { while (x > 1.0) x -= 1.0; return x; }\n" + plainShader)));
    const bssrdf::Model dipole =
        bssrdf::loadModel(std::string(BW_SOURCE_ROOT) + "/materials/dipole.bssrdf", "dipole");
    EXPECT_FALSE(bssrdf::inversionMayLoop(dipole));
}

// What the workbench generates code for itself while a new version is checked: what the check's
// process does not evaluate (and so does not put in the driver's shader cache) and the first
// frame after adoption dispatches; everything it dispatches where the cache is off.
TEST(ProgramsToWarmDuringCheck, WhatTheCheckDoesNotGenerateAndTheFirstFrameUses) {
    auto model = [](const std::string& dr) {
        std::string t = "analytic radial no_wi no_wo\n";
        if (!dr.empty()) t += "::begin diffuseReflectance\n" + dr + "\n::end diffuseReflectance\n";
        t += "::begin shader\nvec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
             "    float s = 0.0;\n    for (int i = 0; i < 4; ++i) s += 1.0;\n"
             "    return vec3(s);\n}\n::end shader\n";
        return bssrdf::parseModel(t, "materials/m.bssrdf");
    };
    using V = std::vector<std::string>;
    const bssrdf::Model plain = model("vec3 DiffuseReflectance(vec3 A) { return A; }");
    const bssrdf::Model looping = model(
        "vec3 DiffuseReflectance(vec3 A) { vec3 s = A; while (s.x > 2.0) s -= 1.0; return s; }");
    const bssrdf::Model none = model("");
    // the cache on: the pencil program always comes from the check
    EXPECT_EQ(bssrdf::programsToWarmDuringCheck(plain, true, false), V{"invert_rdr.comp"});
    EXPECT_EQ(bssrdf::programsToWarmDuringCheck(plain, false, false), V{});
    EXPECT_EQ(bssrdf::programsToWarmDuringCheck(looping, true, false),
              V{}); // the check evaluates it
    EXPECT_EQ(bssrdf::programsToWarmDuringCheck(none, true, false), V{});
    // the cache off: everything the first frame dispatches
    EXPECT_EQ(bssrdf::programsToWarmDuringCheck(plain, true, true),
              (V{"pencil_profile.comp", "invert_rdr.comp"}));
    EXPECT_EQ(bssrdf::programsToWarmDuringCheck(looping, true, true),
              (V{"pencil_profile.comp", "invert_rdr.comp"}));
    EXPECT_EQ(bssrdf::programsToWarmDuringCheck(looping, false, true), V{"pencil_profile.comp"});
    EXPECT_EQ(bssrdf::programsToWarmDuringCheck(none, true, true), V{"pencil_profile.comp"});
}
