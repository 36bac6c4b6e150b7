// Reciprocity of the estimated BSSRDF (slow): S(x_i, ω_i; x_o, ω_o) = S(x_o, −ω_o; x_i, −ω_i).
// On the plane the bins allow an exact check when the exit positions and azimuths are
// integrated whole (one θs bin, one azimuth sector): light entering at θi = a and leaving into
// the ring of cos θo around cos b, at distance r, is the reverse of light entering at b and
// leaving at a, at the same r, since the map (θs, φo) → (θs − φo, −φo) that reverses a pair is
// a bijection of the full annulus × azimuth. The cell averages S over its ring with weight
// cos θo, so each incidence angle is taken at the weighted centroid of its partner ring,
// μ̄ = (2/3)(μ₁³ − μ₀³)/(μ₁² − μ₀²), leaving a second-order averaging error (≈ 1e-4 relative
// here) far below the statistical one. Tested for two ring pairs, g 0 and 0.8, η 1.3, by
// z-tests with a Bonferroni limit over every r bin.
#include "core/statistics.h"
#include "pathtrace/bssrdf_estimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace pathtrace;

namespace {
double centroid(int ring, int rings) {
    const double m0 = double(ring) / rings, m1 = double(ring + 1) / rings;
    return (2.0 / 3.0) * (m1 * m1 * m1 - m0 * m0 * m0) / (m1 * m1 - m0 * m0);
}
double deg(double rad) {
    return rad * 180.0 / std::numbers::pi;
}
} // namespace

TEST(BssrdfReciprocity, SwappingIncidenceAndExitGivesTheSameS) {
    const int rings = 10;
    const std::pair<int, int> pairs[] = {{8, 4}, {6, 2}};
    int tests = 0;
    for (double g : {0.0, 0.8}) {
        const Medium m{0.05, 1.0, g, 1.3};
        EstimateSettings s;
        s.bins.rBins = 4;
        s.bins.rMaxMm = 2.0;
        s.bins.thetaSBins = 1;
        s.bins.dirCosBins = rings;
        s.bins.dirPhiBins = 1;
        s.paths = 150000;
        s.seed = 21;
        for (const auto& [ra, rb] : pairs) {
            // angle a sits at ring ra's centroid and exits into ring rb, and the reverse
            s.thetaIDeg = {deg(std::acos(centroid(ra, rings))),
                           deg(std::acos(centroid(rb, rings)))};
            const BssrdfSlice a =
                finalize(estimateChunks(m, s, 0, 0, chunkCount(s)), s.bins, s.thetaIDeg[0], m);
            const BssrdfSlice b =
                finalize(estimateChunks(m, s, 1, 0, chunkCount(s)), s.bins, s.thetaIDeg[1], m);
            const double zMax = core::bonferroniZ(1e-3, 2.0 * 2 * s.bins.rBins);
            for (int ir = 0; ir < s.bins.rBins; ++ir) {
                const size_t ia = size_t(ir * rings + rb), ib = size_t(ir * rings + ra);
                const double z = (a.S[ia] - b.S[ib]) / std::hypot(a.SStderr[ia], b.SStderr[ib]);
                EXPECT_LT(std::fabs(z), zMax)
                    << "g " << g << " rings " << ra << "/" << rb << " r bin " << ir << ": "
                    << a.S[ia] << " +- " << a.SStderr[ia] << " vs " << b.S[ib] << " +- "
                    << b.SStderr[ib];
                EXPECT_LT(a.SStderr[ia], 0.05 * a.S[ia]) << "too noisy to test anything";
                ++tests;
            }
        }
    }
    EXPECT_EQ(tests, 16);
}
