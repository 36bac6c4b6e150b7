// The model's loop budget (bssrdf/loop_budget.h): every loop condition of a model's code is
// guarded, so a loop that does not end for some inputs (here: only once the parameter Knob is
// past 0.5, so the model passes its first check and is adopted) stops after the budget, on any
// driver, and each consumer reports it as core::Error at the loop's line: the pencil profile,
// the lit-sphere integrator, explicit pairs (the renderer's replica), the inversion, the
// sampler queries. Two runaway loops: one that never ends and one of 10^9 iterations. Each
// consumer must end within 5 s (llvmpipe, 2 cores; a GPU is faster still).
#include "../support/gl_fixture.h"
#include "bssrdf/loop_budget.h"
#include "bssrdf/program.h"
#include "bssrdf/sphere_integrator.h"
#include "core/core.h"
#include "render/render.h"

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <string>

namespace {

using Clock = std::chrono::steady_clock;

std::string model(const std::string& loop) {
    return "analytic radial no_wi no_wo\n"                       // 1
           "::begin parameters\n"                                // 2
           "float Knob 0.0 1.0 0.0\n"                            // 3
           "::end parameters\n"                                  // 4
           "::begin diffuseReflectance\n"                        // 5
           "vec3 DiffuseReflectance(vec3 a) {\n"                 // 6
           "    float s = 0.0;\n"                                // 7
           "    for (int i = 0; i < 4; ++i) s += 0.25;\n"        // 8
           "    return a * s;\n"                                 // 9
           "}\n"                                                 // 10
           "::end diffuseReflectance\n"                          // 11
           "::begin shader\n"                                    // 12
           "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n" // 13
           "    float x = length(Xo - Xi) + 1.0;\n"              // 14
           "    float sum = 0.0;\n"                              // 15
           "    for (int k = 0; k < 3; ++k) { sum += x; }\n"     // 16
           + loop +                                              // 17
           "    return vec3(exp(-sum) * (1.0 + 1e-30 * x));\n"   // 18
           "}\n"                                                 // 19
           "::end shader\n";
}

// never ends once Knob > 0.5 (the body keeps the compiler from removing it)
const std::string kForever =
    "    while (Knob > 0.5) { x = sin(x * 1.37 + 0.11) + cos(x * 0.73); }\n";
// 10^9 iterations once Knob > 0.5
const std::string kBillion = "    for (int i = 0; i < (Knob > 0.5 ? 1000000000 : 0); ++i) "
                             "{ x = sin(x * 1.37 + 0.11) + cos(x * 0.73); }\n";

struct Runaway {
    bssrdf::Model m;
    gl::Program pencil, sphere, pairs, invert;
    bssrdf::ParamValues values;
    explicit Runaway(const std::string& loop) {
        testsupport::context();
        m = bssrdf::parseModel(model(loop), "materials/runaway.bssrdf");
        shader::Sources src{testsupport::sourceRoot()};
        pencil = bssrdf::buildModelProgram(m, "pencil_profile.comp", src);
        sphere = bssrdf::buildModelProgram(m, "sphere_bssrdf.comp", src);
        pairs = bssrdf::buildModelProgram(m, "render_pairs.comp", src);
        invert = bssrdf::buildModelProgram(m, "invert_rdr.comp", src);
        values = bssrdf::defaultValues(m);
    }
};

// Runs `consumer`, expects core::Error at line 17 of the model naming the budget (its message:
// a driver that cut the loop, or a wait's deadline, would write another) and prints how long it
// took (the 5 s; tests do not assert times).
void expectBudgetError(const std::string& what, const std::function<void()>& consumer) {
    SCOPED_TRACE(what);
    const auto start = Clock::now();
    try {
        consumer();
        ADD_FAILURE() << what << ": no error";
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "materials/runaway.bssrdf");
        EXPECT_EQ(e.line(), 17) << e.what();
        EXPECT_NE(std::string(e.what()).find("the loop at line 17 ran past the loop budget of " +
                                             std::to_string(bssrdf::kLoopBudget)),
                  std::string::npos)
            << e.what();
    }
    const double s = std::chrono::duration<double>(Clock::now() - start).count();
    std::printf("%s: ended in %.3f s\n", what.c_str(), s);
}

void everyConsumerEnds(const std::string& loop) {
    Runaway r(loop);
    bssrdf::Builtins b;
    b.sigmaA = glm::vec3(0.01f);
    b.sigmaS = glm::vec3(1.0f);
    const std::vector<double> radii = bssrdf::radiusGrid(10.0, 512);
    // Knob = 0: the loop does not run, every consumer works
    EXPECT_NO_THROW(bssrdf::evaluateProfile(r.pencil.id(), r.m, r.values, b, radii));
    r.values["Knob"] = {1.0f, 1.0f, 1.0f};
    expectBudgetError("pencil profile",
                      [&] { bssrdf::evaluateProfile(r.pencil.id(), r.m, r.values, b, radii); });
    expectBudgetError("lit sphere", [&] {
        bssrdf::SphereIntegrator integrator;
        litsphere::Setup setup;
        setup.width = setup.height = 64;
        setup.radiusMm = 5.0;
        integrator.reset(setup);
        integrator.step(r.sphere.id(), r.m, r.values, b, 16);
    });
    expectBudgetError("explicit pairs", [&] {
        std::vector<render::BssrdfPair> pairs(4096);
        for (size_t i = 0; i < pairs.size(); ++i)
            pairs[i] = {glm::vec3(0.0f), glm::vec3(0, 0, 1), glm::vec3(0.001f * float(i), 0, 0),
                        glm::vec3(0, 0, 1)};
        render::evaluatePairs(r.pairs.id(), r.m, r.values, b, pairs);
    });
    expectBudgetError("sampler queries (the integrated R_dr)", [&] {
        bssrdf::integrateDiffuseReflectance(r.pencil.id(), r.m, r.values, b,
                                            {glm::dvec3(0.5), glm::dvec3(0.9)});
    });
    // the inversion's own loop (line 8) is short and within the budget: it works
    EXPECT_NO_THROW(
        bssrdf::evaluateDiffuseReflectance(r.invert.id(), r.m, r.values, b, {glm::dvec3(0.5)}));
    // and the consumer works again once the parameter is back
    r.values["Knob"] = {0.0f, 0.0f, 0.0f};
    EXPECT_NO_THROW(bssrdf::evaluateProfile(r.pencil.id(), r.m, r.values, b, radii));
}

} // namespace

TEST(LoopBudget, ALoopThatNeverEndsStopsInEveryConsumerAtItsLine) {
    everyConsumerEnds(kForever);
}

TEST(LoopBudget, ALoopOfABillionIterationsStopsInEveryConsumerAtItsLine) {
    everyConsumerEnds(kBillion);
}

TEST(LoopBudget, ConditionsAreGuardedAndLinesKept) {
    unsigned site = 0;
    std::vector<int> lines;
    const std::string code = "for (int i = 0; i < n; ++i) x++;\n"
                             "// while (comment) stays\n"
                             "for (;;) { if (f(a, (b))) break; }\n"
                             "do { y--; } while (y > 0\n"
                             "   && z);\n"
                             "#define LOOP while (w) {}\n"
                             "float format = 1.0; whiles(2);\n";
    const std::string out = bssrdf::guardLoops(code, 10, site, lines);
    EXPECT_EQ(out, "for (int i = 0;( i < n) && bw_loop(0u); ++i) x++;\n"
                   "// while (comment) stays\n"
                   "for (;bw_loop(1u);) { if (f(a, (b))) break; }\n"
                   "do { y--; } while ((y > 0\n"
                   "   && z) && bw_loop(2u));\n"
                   "#define LOOP while (w) {}\n"
                   "float format = 1.0; whiles(2);\n");
    EXPECT_EQ(site, 3u);
    EXPECT_EQ(lines, (std::vector<int>{10, 12, 13}));
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), std::count(code.begin(), code.end(), '\n'));
}

TEST(LoopBudget, ABadBudgetInTheEnvironmentIsNamed) {
    ::setenv("BSSRDF_WORKBENCH_LOOP_BUDGET", "lots", 1);
    try {
        bssrdf::loopBudget();
        ADD_FAILURE() << "no error";
    } catch (const core::Error& e) {
        EXPECT_NE(std::string(e.what()).find("BSSRDF_WORKBENCH_LOOP_BUDGET: 'lots' is not a loop "
                                             "budget"),
                  std::string::npos)
            << e.what();
    }
    ::setenv("BSSRDF_WORKBENCH_LOOP_BUDGET", "1000", 1);
    EXPECT_EQ(bssrdf::loopBudget(), 1000u);
    ::unsetenv("BSSRDF_WORKBENCH_LOOP_BUDGET");
    EXPECT_EQ(bssrdf::loopBudget(), bssrdf::kLoopBudget);
}
