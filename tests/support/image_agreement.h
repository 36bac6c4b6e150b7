// Shared by the tests of BSSRDF-integrated images (integrate, lit spheres, the Monte Carlo
// render, the integrate command): two independent Monte Carlo images of the same quantity
// compared per pixel and channel by z = |a − b| / √(var_a + var_b), with a Bonferroni limit at
// family-wise `alpha` over every value tested. Tested: the values of at least `peakFraction` of
// the channel's brightest in `b` (with a finite, positive variance). Below that — the far side of
// a terminator — a pixel is made of the profile's tail alone, where disk sampling gives up what
// lies beyond R_m (at most eps of a plane's energy, integrate/integrate.h) and every
// estimator's variance estimate is unreliable at test sample counts.
#pragma once

#include "core/statistics.h"
#include "litsphere/litsphere.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace testsupport {

struct Agreement {
    size_t tested = 0;
    double maxZ = 0, threshold = 0;
};

inline Agreement agreePerPixel(const litsphere::Image& a, const litsphere::Image& b,
                               double peakFraction = 1e-3, double alpha = 1e-3) {
    double peak[3] = {0, 0, 0};
    for (size_t i = 0; i < b.mean.size(); ++i)
        peak[i % 3] = std::max(peak[i % 3], double(b.mean[i]));
    std::vector<double> z;
    for (size_t i = 0; i < a.mean.size() && i < b.mean.size(); ++i) {
        const double v = double(a.variance[i]) + double(b.variance[i]);
        if (!(b.mean[i] >= peakFraction * peak[i % 3] && v > 0 && std::isfinite(v))) continue;
        z.push_back(std::abs(double(a.mean[i]) - double(b.mean[i])) / std::sqrt(v));
    }
    Agreement g;
    g.tested = z.size();
    g.threshold = core::bonferroniZ(alpha, double(std::max<size_t>(1, z.size())));
    for (double x : z)
        g.maxZ = std::max(g.maxZ, x);
    return g;
}

} // namespace testsupport
