// Where a model loops (bssrdf/loop_sites.h): the loop statements of its GLSL sections by file
// line, none in comments, a do-while counted once.
#include "bssrdf/loop_sites.h"

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
