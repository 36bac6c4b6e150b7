// bssrdf::profileProblem: NaN, ±Inf and negative profile values are counted per kind with the
// radii and channels where they occur; a valid profile (zeros included) has no problem.
#include "bssrdf/program.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

bssrdf::Profile ramp(size_t n) {
    bssrdf::Profile p;
    for (size_t i = 0; i < n; ++i) {
        p.r.push_back(0.1 * double(i));
        p.value.push_back(glm::dvec3(1.0 / (1.0 + double(i))));
    }
    return p;
}

} // namespace

TEST(ProfileCheck, ValidProfilesHaveNoProblem) {
    EXPECT_EQ(bssrdf::profileProblem(ramp(10)), "");
    auto p = ramp(4);
    p.value[3] = glm::dvec3(0.0); // zero is a valid reflectance
    EXPECT_EQ(bssrdf::profileProblem(p), "");
    EXPECT_EQ(bssrdf::profileProblem(bssrdf::Profile{}), "");
}

TEST(ProfileCheck, CountsEachKindWithItsRadiiAndChannels) {
    auto p = ramp(10);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    p.value[0].x = nan; // r = 0
    p.value[1].x = nan; // r = 0.1
    p.value[1].z = nan; // same radius, second channel: one radius
    p.value[4].y = -inf;
    p.value[7].y = -1e-3; // r = 0.7
    p.value[9].y = -2.0;  // r = 0.9
    p.value[9].z = -2.0;
    EXPECT_EQ(bssrdf::profileProblem(p),
              "R(r) is NaN at 2 of 10 radii (r 0 to 0.1 mm, channels R B); infinite at 1 of 10 "
              "radii (r 0.4 to 0.4 mm, channel G); negative at 2 of 10 radii (r 0.7 to 0.9 mm, "
              "channels G B)");
}
