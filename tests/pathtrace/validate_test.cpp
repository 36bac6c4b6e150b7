// pathtrace validation (f): each bad input gives core::Error whose message names the field;
// the edges that are valid (σa = 0, g near ±1, η < 1) pass.
#include "core/core.h"
#include "pathtrace/pathtrace.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

using namespace pathtrace;

namespace {
const double kNan = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

// Runs f and expects core::Error whose message contains `field`.
void expectError(const std::function<void()>& f, const std::string& field) {
    try {
        f();
        ADD_FAILURE() << "no error for " << field;
    } catch (const core::Error& e) {
        EXPECT_NE(e.message().find(field), std::string::npos)
            << "message '" << e.message() << "' does not name " << field;
    }
}
void badMedium(void (*edit)(Medium&), const std::string& field) {
    Medium m;
    edit(m);
    expectError([&] { validate(m); }, field);
    SlabSettings s;
    s.paths = 10;
    expectError([&] { runSlab(m, s); }, field); // the entry points validate too
    expectError([&] { tracePath(m, s, 0); }, field);
}
void badSettings(void (*edit)(SlabSettings&), const std::string& field) {
    SlabSettings s;
    edit(s);
    expectError([&] { validate(s); }, field);
    expectError([&] { runSlab(Medium{}, s); }, field);
}
} // namespace

TEST(Validate, MediumFields) {
    badMedium([](Medium& m) { m.sigmaA = -0.1; }, "sigma_a");
    badMedium([](Medium& m) { m.sigmaA = kNan; }, "sigma_a");
    badMedium([](Medium& m) { m.sigmaA = kInf; }, "sigma_a");
    badMedium([](Medium& m) { m.sigmaS = 0; }, "sigma_s");
    badMedium([](Medium& m) { m.sigmaS = -1; }, "sigma_s");
    badMedium([](Medium& m) { m.sigmaS = kNan; }, "sigma_s");
    badMedium([](Medium& m) { m.sigmaS = kInf; }, "sigma_s");
    badMedium([](Medium& m) { m.g = 1; }, "g must");
    badMedium([](Medium& m) { m.g = -1; }, "g must");
    badMedium([](Medium& m) { m.g = 1.5; }, "g must");
    badMedium([](Medium& m) { m.g = kNan; }, "g must");
    badMedium([](Medium& m) { m.eta = 0; }, "eta");
    badMedium([](Medium& m) { m.eta = -1.3; }, "eta");
    badMedium([](Medium& m) { m.eta = kNan; }, "eta");
    badMedium([](Medium& m) { m.eta = kInf; }, "eta");
}

TEST(Validate, ErrorNamesTheWhat) {
    Medium m;
    m.sigmaA = -1;
    try {
        validate(m, "red channel");
        FAIL();
    } catch (const core::Error& e) {
        EXPECT_EQ(e.file(), "red channel");
    }
}

TEST(Validate, SettingsFields) {
    badSettings([](SlabSettings& s) { s.rMaxMm = 0; }, "rMax");
    badSettings([](SlabSettings& s) { s.rMaxMm = -3; }, "rMax");
    badSettings([](SlabSettings& s) { s.rMaxMm = kNan; }, "rMax");
    badSettings([](SlabSettings& s) { s.rMaxMm = kInf; }, "rMax");
    badSettings([](SlabSettings& s) { s.bins = 0; }, "bins");
    badSettings([](SlabSettings& s) { s.bins = -5; }, "bins");
    badSettings([](SlabSettings& s) { s.bins = 10000001; }, "more bins than memory allows");
    badSettings([](SlabSettings& s) { s.paths = 0; }, "paths");
    badSettings([](SlabSettings& s) { s.paths = 10000000000001ull; }, "absurd path count");
    badSettings([](SlabSettings& s) { s.threads = -1; }, "threads");
    badSettings([](SlabSettings& s) { s.termination.maxEvents = 0; }, "maxEvents");
    badSettings([](SlabSettings& s) { s.termination.rouletteWeight = 0; }, "rouletteWeight");
    badSettings([](SlabSettings& s) { s.termination.rouletteWeight = 1; }, "rouletteWeight");
    badSettings([](SlabSettings& s) { s.termination.rouletteSurvival = 0; }, "rouletteSurvival");
    badSettings([](SlabSettings& s) { s.termination.rouletteSurvival = kNan; }, "rouletteSurvival");
}

TEST(Validate, ValidEdgesPass) {
    Medium m;
    m.sigmaA = 0; // albedo 1 is valid
    EXPECT_NO_THROW(validate(m));
    m.g = 0.999;
    EXPECT_NO_THROW(validate(m));
    m.g = -0.999;
    m.eta = 0.7; // a medium optically thinner than outside
    EXPECT_NO_THROW(validate(m));
    SlabSettings s;
    s.bins = 10000000;
    s.paths = 10000000000000ull;
    EXPECT_NO_THROW(validate(s));
    // An η < 1 medium runs (total internal reflection happens outside, never inside).
    SlabSettings small;
    small.paths = 2000;
    small.threads = 1;
    const SlabResult r = runSlab(m, small);
    EXPECT_EQ(r.paths, 2000u);
    EXPECT_NEAR(r.specular + r.totalRd + r.absorbed + r.truncated + r.rouletteNet, 1.0, 1e-9);
}
