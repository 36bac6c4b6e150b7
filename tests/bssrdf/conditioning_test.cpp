// The spread of a model's values under the errors GLSL allows its transcendental functions
// (bssrdf/conditioning.h) against closed forms: one exp moves by exactly its bound,
// (3 + 2|x|) ulp; a difference of two exps by the sum of the two terms' bounds wherever the
// seeds give the two opposite signs, never more; and the allowance a replay makes on the shipped
// captures (pencil plots and the slice) covers what an NVIDIA card gave where the better dipole and
// the multipole cancel.
#include "../support/gl_fixture.h"
#include "bssrdf/conditioning.h"
#include "bssrdf/program.h"
#include "captures/capture_io.h"
#include "core/core.h"
#include "pipeline/workbench.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace {
namespace fs = std::filesystem;

constexpr double kUlp = 1.0 / 8388608.0; // 2^-23, as perturbed_builtins.glsl takes one ulp

std::string model(const std::string& body) {
    return "analytic radial no_wi no_wo\n"
           "::begin parameters\n"
           "float A 0.0 10.0 1.0\n"
           "float B 0.0 10.0 1.001\n"
           "::end parameters\n"
           "::begin shader\n"
           "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {\n"
           "    float r = length(Xo - Xi);\n" +
           body +
           "}\n"
           "::end shader\n";
}

struct Built {
    bssrdf::Model m;
    std::vector<double> radii;
    std::vector<glm::dvec3> spread;
    bssrdf::Profile profile;
    explicit Built(const std::string& body) {
        testsupport::context();
        m = bssrdf::parseModel(model(body), "materials/conditioning.bssrdf");
        const shader::Sources src{testsupport::sourceRoot()};
        radii = bssrdf::radiusGrid(30.0, 121);
        spread = bssrdf::profileSpread(m, src, bssrdf::defaultValues(m), {}, radii);
        const gl::Program pencil = bssrdf::buildModelProgram(m, "pencil_profile.comp", src);
        profile = bssrdf::evaluateProfile(pencil.id(), m, bssrdf::defaultValues(m), {}, radii);
    }
};

// The model's values at the radii under every seed (the unperturbed first) in the query mode, the
// slice's: one vector of RGB per seed.
std::vector<std::vector<glm::dvec3>> queriedAtTheRadii(const Built& b) {
    std::vector<bssrdf::Query> q(b.radii.size());
    for (size_t i = 0; i < q.size(); ++i)
        q[i].xo = {float(b.radii[i]), 0.0f, 0.0f};
    auto evals = bssrdf::perturbedQueries(b.m, shader::Sources{testsupport::sourceRoot()},
                                          bssrdf::defaultValues(b.m), {}, q);
    EXPECT_EQ(evals.size(), size_t(bssrdf::kConditioningPatterns + 1));
    return evals;
}

} // namespace

TEST(Conditioning, OneExpMovesByItsBound) {
    const Built b("    return vec3(exp(-A * r));\n");
    for (size_t i = 0; i < b.radii.size(); ++i) {
        const double x = float(-1.0f * float(b.radii[i]));
        const double bound = (3.0 + 2.0 * std::fabs(x)) * kUlp * std::exp(x);
        // the perturbed value is computed in float: its rounding (0.5 ulp of the value) is
        // within 2 ulp of the difference
        EXPECT_NEAR(b.spread[i].x, bound, 2 * kUlp * std::exp(x)) << "r " << b.radii[i];
        EXPECT_EQ(b.spread[i].x, b.spread[i].y) << "the channels are one computation";
    }
    // the query mode (the slice's) moves the same values the same way
    const auto evals = queriedAtTheRadii(b);
    ASSERT_EQ(evals.size(), size_t(bssrdf::kConditioningPatterns + 1));
    for (size_t i = 0; i < b.radii.size(); ++i) {
        double d = 0;
        for (size_t k = 1; k < evals.size(); ++k)
            d = std::max(d, std::fabs(evals[k][i].x - evals[0][i].x));
        EXPECT_EQ(d, b.spread[i].x) << "r " << b.radii[i];
    }
}

TEST(Conditioning, ADifferenceOfTwoExpsMovesByTheSumOfTheirBounds) {
    const Built b("    return vec3(exp(-A * r) - exp(-B * r));\n");
    int atTheSum = 0, compared = 0;
    for (size_t i = 1; i < b.radii.size(); ++i) {
        const float r = float(b.radii[i]);
        const double x1 = -1.0f * r, x2 = -1.001f * r;
        const double t1 = std::exp(x1), t2 = std::exp(x2);
        const double worst =
            (3.0 + 2.0 * std::fabs(x1)) * kUlp * t1 + (3.0 + 2.0 * std::fabs(x2)) * kUlp * t2;
        const double rounding = 2 * kUlp * t1; // float rounding of the perturbed terms
        EXPECT_LE(b.spread[i].x, worst + rounding) << "r " << r;
        ++compared;
        atTheSum += b.spread[i].x >= worst - rounding;
        // the cancellation: the spread is many times the difference's own float error
        if (r > 10) {
            EXPECT_GT(b.spread[i].x, 50 * kUlp * std::fabs(b.profile.value[i].x)) << "r " << r;
        }
    }
    // each radius meets the opposite signs unless all 8 seeds give one sign (2^-7)
    EXPECT_GE(atTheSum, compared * 9 / 10) << atTheSum << " of " << compared;
}

TEST(Conditioning, AModelWithoutTranscendentalFunctionsHasNoSpread) {
    const Built b("    return vec3(1.0 / (1.0 + r * r));\n");
    for (size_t i = 0; i < b.radii.size(); ++i)
        EXPECT_EQ(b.spread[i], glm::dvec3(0.0)) << "r " << b.radii[i];
}

// pow(0, y > 0) is 0 and exp(-inf) is 0 (GLSL 4.50, 8.2): the perturbed functions keep those
// values under every seed, the unperturbed one included, instead of multiplying them by an
// infinite bound (0 * inf, NaN), and the pencil radius grid starts at r = 0 exactly.
TEST(Conditioning, PowAtZeroAndExpOfMinusInfinityStayZeroUnderEverySeed) {
    const Built b(
        "    float inf = uintBitsToFloat(0x7F800000u);\n"
        "    return vec3(pow(r, 1.5), exp(r > 0.0 ? -r : -inf), pow(r, A) * exp(-A * r));\n");
    ASSERT_EQ(b.radii.front(), 0.0);
    const auto evals = queriedAtTheRadii(b);
    ASSERT_EQ(evals.size(), size_t(bssrdf::kConditioningPatterns + 1));
    const size_t n = b.radii.size();
    for (size_t k = 0; k < evals.size(); ++k)
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c)
                ASSERT_TRUE(std::isfinite(evals[k][i][c]))
                    << "seed " << k << ", r " << b.radii[i] << ", channel " << c;
    for (size_t k = 0; k < evals.size(); ++k)
        EXPECT_EQ(evals[k][0], glm::dvec3(0.0)) << "seed " << k << " at r = 0";
    // elsewhere each value moves by its bound only: pow(r, 1.5) by (3 + 2|u|) ulp plus the log's
    // share, u = 1.5 log2 r, never more than 1e-5 of itself
    for (size_t i = 1; i < n; ++i) {
        const double v = std::pow(double(float(b.radii[i])), 1.5);
        EXPECT_NEAR(evals[0][i].x, v, 1e-5 * v) << "r " << b.radii[i];
        EXPECT_LE(b.spread[i].x, 1e-5 * v) << "r " << b.radii[i];
        EXPECT_GT(b.spread[i].x, 0.0) << "r " << b.radii[i];
    }
    EXPECT_EQ(b.spread[0], glm::dvec3(0.0));
}

// Two captures recorded on llvmpipe and replayed on an NVIDIA H200 (driver 580.159.04): the better
// dipole's and the multipole's pencil plots differed from the recordings by 10-22x the 1e-5
// relative floor far from the source, where their terms cancel, and the better dipole's slice by
// 79 % of it (the worst values below, as the replay reported them). The allowance made here for
// another driver covers them, and stays below the floor at the pencil plot's peak.
struct CardValue {
    const char* capture;
    const char* stage;
    size_t row; // from 1, as the replay report counts
    const char* column;
    double diff; // |the H200's value - the recorded one|
};
const CardValue kCardValues[] = {
    {"dipoles_slice_60deg", "pencil_plot.better_dipole", 477, "G", 3.66e-12},
    {"multipole_skin1", "pencil_plot.multipole", 488, "R", 4.8e-12},
    {"dipoles_slice_60deg", "slice_model.better_dipole", 181, "S6", 6.48e-12},
};

TEST(Conditioning, CoversWhatAnNvidiaCardGaveWhereTheModelsCancel) {
    testsupport::context();
    for (const CardValue& v : kCardValues) {
        SCOPED_TRACE(std::string(v.capture) + " " + v.stage);
        const fs::path dir = testsupport::sourceRoot() / "captures" / v.capture;
        const capture::Manifest m = capture::readManifest(dir);
        app::ExternalModels external;
        int traceX = -1, traceY = -1;
        auto wb = app::workbenchFromInputs(m, testsupport::sourceRoot(), external.dir, dir.string(),
                                           traceX, traceY, false);
        app::CaptureEntries out;
        out.forReplay = true;
        wb->capture(out);
        const app::CaptureEntry* p = nullptr;
        for (const auto& e : out.entries)
            if (e.stage == v.stage) p = &e;
        ASSERT_NE(p, nullptr);
        ASSERT_EQ(p->conditioning.rows.size(), p->table.rows.size()) << p->conditioningNote;
        const capture::Table recorded = capture::readCsv(dir / p->file);
        const int col = recorded.columnIndex(v.column);
        ASSERT_GE(col, 0);
        const double b = recorded.rows.at(v.row - 1).at(size_t(col));
        const double limit =
            p->relTol * std::fabs(b) + p->conditioning.rows[v.row - 1][size_t(col)];
        EXPECT_LE(v.diff, limit) << "recorded " << b;
        std::printf("%s: the card's difference %.3g of the limit %.3g (the floor alone %.3g)\n",
                    v.stage, v.diff, limit, p->relTol * std::fabs(b));
        if (std::string(v.stage).rfind("pencil_plot.", 0) != 0) continue;
        // at the peak (the first rows) the allowance is below the floor
        double peak = 0;
        for (size_t i = 1; i < 20; ++i)
            for (size_t c = 1; c <= 3; ++c)
                peak = std::max(peak, p->conditioning.rows[i][c] / std::fabs(p->table.rows[i][c]));
        EXPECT_LT(peak, p->relTol);
    }
}
