// pathtrace lit-sphere tracer: exact footprint areas (Archimedes: the hemisphere's area over a
// column is πR·width), path count, per-path energy accounting, (d3) energy conservation with
// η = 1 and albedo 1 (z-test), (d1) symmetry of the image under a light along the view axis
// (mirrors x, y and the diagonal, Bonferroni-corrected z-tests) and along +x (mirror in y),
// orientation (the lit side is the bright side, pixel (0, 0) top left), bitwise determinism
// across thread counts, cancellation, input validation, and the centre of a large sphere
// against the slab tracer's total diffuse reflectance.
#include "core/core.h"
#include "core/statistics.h"
#include "pathtrace/camera.h"
#include "pathtrace/pathtrace.h"
#include "pathtrace/sphere_tracer.h"

#include "lit_sphere_media.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

using namespace pathtrace;

namespace {

using core::bonferroniZ;

using pathtrace_test::kMedia;
using pathtrace_test::med;

LitSphereSetup sphereSetup(int size, uint64_t spp, double lx, double ly, double lz) {
    LitSphereSetup s;
    s.radiusMm = 2.0;
    s.width = s.height = size;
    s.samplesPerPixel = spp;
    s.lightDir[0] = lx;
    s.lightDir[1] = ly;
    s.lightDir[2] = lz;
    s.seed = 7;
    s.threads = 0;
    return s;
}

struct MirrorStats {
    int tests = 0;
    double worst = 0;
};
// Compares every covered pixel (centre radius < rMax·R) with its image under `mirror` (pixel
// coordinates), each unordered pair once, per channel; returns the number of tests and the
// largest |z|.
MirrorStats mirrorTest(const Image& img, const LitSphereSetup& s, double rMax,
                       const std::function<void(int, int, int&, int&)>& mirror) {
    const OrthoCamera cam(s, s.radiusMm);
    MirrorStats r;
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
            int i2, j2;
            mirror(i, j, i2, j2);
            const int p = j * img.width + i, q = j2 * img.width + i2;
            if (q <= p) continue;
            const double x = cam.centreX(i), y = cam.centreY(j);
            if (std::hypot(x, y) >= rMax * s.radiusMm) continue;
            for (int c = 0; c < 3; ++c) {
                const double a = img.mean[3 * p + c], b = img.mean[3 * q + c];
                const double v = double(img.variance[3 * p + c]) + img.variance[3 * q + c];
                EXPECT_GT(v, 0.0) << "pixel " << i << "," << j;
                if (!(v > 0)) continue;
                r.worst = std::max(r.worst, std::fabs(a - b) / std::sqrt(v));
                ++r.tests;
            }
        }
    return r;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

} // namespace

// Archimedes: the sphere's area between two planes x = a and x = b is 2πR(b − a), the visible
// half πR(b − a). Every pixel column of the footprint sums to that, and the image to 2πR².
TEST(SphereFootprint, ColumnsSumToArchimedes) {
    const double R = 3.0;
    for (int size : {7, 32, 33}) {
        LitSphereSetup s;
        s.radiusMm = R;
        s.width = s.height = size;
        const OrthoCamera cam(s, R);
        double total = 0;
        for (int i = 0; i < size; ++i) {
            const double x0 = cam.centreX(i) - 0.5 * cam.dx, x1 = x0 + cam.dx;
            double col = 0;
            for (int j = 0; j < size; ++j) {
                const double y1 = cam.centreY(j) + 0.5 * cam.dy;
                col += sphereAreaOver(R, x0, x1, y1 - cam.dy, y1);
            }
            const double overlap = std::max(0.0, std::min(x1, R) - std::max(x0, -R));
            EXPECT_NEAR(col, std::numbers::pi * R * overlap, 1e-9 * R * R) << size << " col " << i;
            total += col;
        }
        EXPECT_NEAR(total, 2 * std::numbers::pi * R * R, 1e-9 * R * R);
    }
    // A pixel on the rim, against a fine midpoint rule in polar-free form (substitution-free
    // reference: 4000² midpoints of R/√(R² − x² − y²), accurate to ~1e-4 near the rim).
    const double x0 = 2.5, x1 = 3.0, y0 = 0.5, y1 = 1.0;
    double ref = 0;
    const int n = 4000;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            const double x = x0 + (a + 0.5) * (x1 - x0) / n, y = y0 + (b + 0.5) * (y1 - y0) / n;
            const double d = R * R - x * x - y * y;
            if (d > 0) ref += R / std::sqrt(d);
        }
    ref *= (x1 - x0) * (y1 - y0) / (double(n) * n);
    EXPECT_NEAR(sphereAreaOver(R, x0, x1, y0, y1), ref, 2e-3 * ref);
    // Centre pixel of a small square: ≈ the flat area.
    EXPECT_NEAR(sphereAreaOver(R, -1e-3, 1e-3, -1e-3, 1e-3), 4e-6, 1e-12);
}

TEST(SphereTracer, PathCountAndFootprints) {
    const LitSphereSetup s = sphereSetup(16, 3, 0, 0, 1);
    const PixelGeometry g = sphereFootprints(s);
    const OrthoCamera cam(s, s.radiusMm);
    uint64_t covered = 0;
    for (int j = 0; j < 16; ++j)
        for (int i = 0; i < 16; ++i) {
            const bool in = std::hypot(cam.centreX(i), cam.centreY(j)) < s.radiusMm;
            covered += in;
            EXPECT_EQ(g.footprint[j * 16 + i] > 0, in);
            if (in) {
                EXPECT_GE(g.footprint[j * 16 + i], cam.dx * cam.dy * (1 - 1e-12));
            }
        }
    EXPECT_EQ(litSpherePaths(s), 3 * covered);
}

// Per channel: incident = specular + exited + absorbed + truncated + roulette + leaked, as sums
// over paths (each path's identity holds up to rounding); incident is exactly πR² W. The net
// roulette loss is 0 in expectation (z-test) whatever the event limit, since the weight
// roulette's survivors stay bounded; with the default limit nothing is truncated and the
// channel's own energy check passes, with a limit of 3 events much is truncated and the check
// says so.
TEST(SphereTracer, EnergyAccounting) {
    LitSphereSetup s = sphereSetup(12, 50, 0.3, -0.2, 1);
    for (uint32_t limit : {TraceOptions{}.termination.maxEvents, 3u}) {
        ImageStats st;
        TraceOptions o;
        o.termination.maxEvents = limit;
        const Image img = traceLitSphere(kMedia, s, {}, nullptr, o, &st);
        EXPECT_EQ(img.samples, litSpherePaths(s));
        EXPECT_EQ(st.paths, img.samples);
        const double R = s.radiusMm;
        EXPECT_DOUBLE_EQ(st.sourceAreaMm2, std::numbers::pi * R * R);
        for (int c = 0; c < 3; ++c) {
            const ChannelStats& k = st.channel[c];
            EXPECT_DOUBLE_EQ(k.incident, std::numbers::pi * R * R);
            EXPECT_EQ(k.leaks, 0u);
            const double sum =
                k.specular + k.exited + k.absorbed + k.truncated + k.rouletteNet + k.leaked;
            EXPECT_NEAR(sum, k.incident, 1e-9 * k.incident) << "channel " << c;
            EXPECT_LT(std::fabs(k.rouletteNet), bonferroniZ(1e-3, 6) * k.rouletteNetStderr)
                << "channel " << c;
            if (limit == 3) {
                EXPECT_GT(k.truncatedPaths, 0u);
                EXPECT_NE(energyProblem(k).find("truncated"), std::string::npos);
            } else {
                EXPECT_EQ(k.truncatedPaths, 0u);
                EXPECT_EQ(energyProblem(k), "") << "channel " << c;
            }
            EXPECT_GT(k.specular, 0);
            EXPECT_GT(k.events, 0u);
        }
    }
}

// (d3) σa = 0 (albedo 1), η = 1 (no Fresnel): every path enters with weight 1, is never
// absorbed and no roulette fires (the weight stays 1 > rouletteWeight; no path comes near
// the event limit), so each path leaves with exactly weight 1: the exited power equals the incident
// power πR² to rounding (the z-score (exited − πR²)/stderr is 0/0: the check is the exact
// equality). With η = 1.3 the specular part is the loss at entry, and grazing entries (F > 0.9)
// start below the roulette weight: exited + specular + roulette = incident per path, and the
// roulette's net loss is 0 in expectation: z-test of exited + specular against πR².
TEST(SphereTracer, EnergyConservedWithoutAbsorption) {
    for (double eta : {1.0, 1.3}) {
        const std::array<Medium, 3> media = {med(0.0, 1.5, 0.3, eta), med(0.0, 3.0, 0.0, eta),
                                             med(0.0, 0.7, -0.4, eta)};
        LitSphereSetup s = sphereSetup(16, 400, 0.2, 0.5, 0.7);
        s.radiusMm = 1.5;
        const double incident = std::numbers::pi * s.radiusMm * s.radiusMm;
        ImageStats st;
        traceLitSphere(media, s, {}, nullptr, {}, &st);
        for (int c = 0; c < 3; ++c) {
            const ChannelStats& k = st.channel[c];
            EXPECT_EQ(k.absorbed, 0.0);
            EXPECT_EQ(k.leaks, 0u);
            EXPECT_NEAR(k.exited + k.specular + k.rouletteNet, incident, 1e-12 * incident) << c;
            if (eta == 1.0) {
                EXPECT_EQ(k.specular, 0.0);
                EXPECT_EQ(k.rouletteNet, 0.0);
                EXPECT_NEAR(k.exited, incident, 1e-12 * incident) << c;
            } else {
                EXPECT_GT(k.specular, 0.0);
                if (k.rouletteNetStderr == 0.0) { // no roulette fired: exact
                    EXPECT_EQ(k.rouletteNet, 0.0);
                } else {
                    const double z = (k.exited + k.specular - incident) / k.rouletteNetStderr;
                    EXPECT_LT(std::fabs(z), bonferroniZ(1e-3, 3)) << "channel " << c;
                }
            }
        }
    }
}

// (d1) Light along the view axis: the image is rotationally symmetric about the image centre;
// compare every pixel with its mirrors (−x, y), (x, −y) and (y, x).
TEST(SphereTracer, SymmetricUnderAxialLight) {
    const LitSphereSetup s = sphereSetup(24, 300, 0, 0, 1);
    const Image img = traceLitSphere(kMedia, s);
    const int n = s.width;
    const MirrorStats mx = mirrorTest(img, s, 0.95, [n](int i, int j, int& i2, int& j2) {
        i2 = n - 1 - i;
        j2 = j;
    });
    const MirrorStats my = mirrorTest(img, s, 0.95, [n](int i, int j, int& i2, int& j2) {
        i2 = i;
        j2 = n - 1 - j;
    });
    // (x, y) → (y, x): column i' with x' = y, row j' with y' = x.
    const MirrorStats md = mirrorTest(img, s, 0.95, [n](int i, int j, int& i2, int& j2) {
        i2 = n - 1 - j;
        j2 = n - 1 - i;
    });
    const int m = mx.tests + my.tests + md.tests;
    ASSERT_GT(m, 500);
    const double zMax = bonferroniZ(1e-3, m);
    EXPECT_LT(mx.worst, zMax);
    EXPECT_LT(my.worst, zMax);
    EXPECT_LT(md.worst, zMax);
    RecordProperty("worst_mirror_z", std::to_string(std::max({mx.worst, my.worst, md.worst})) +
                                         " of " + std::to_string(m));
}

// Light along +x: mirror symmetry y ↔ −y only; the +x side (right) is the bright one. Light
// along +y: the top rows (y > 0, row 0 at the top) are the bright ones.
TEST(SphereTracer, MirrorSymmetryAndOrientationUnderSideLight) {
    const LitSphereSetup s = sphereSetup(24, 300, 1, 0, 0);
    const Image img = traceLitSphere(kMedia, s);
    const int n = s.width;
    const MirrorStats my = mirrorTest(img, s, 0.95, [n](int i, int j, int& i2, int& j2) {
        i2 = i;
        j2 = n - 1 - j;
    });
    ASSERT_GT(my.tests, 300);
    EXPECT_LT(my.worst, bonferroniZ(1e-3, my.tests));
    auto half = [&](const Image& im, bool columns, bool first, int c) {
        double sum = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const int k = columns ? i : j;
                if ((k < n / 2) == first) sum += im.mean[3 * (j * n + i) + c];
            }
        return sum;
    };
    for (int c = 0; c < 3; ++c)
        EXPECT_GT(half(img, true, false, c), 1.5 * half(img, true, true, c)) << c;
    const Image top = traceLitSphere(kMedia, sphereSetup(16, 50, 0, 1, 0));
    for (int c = 0; c < 3; ++c) {
        double upper = 0, lower = 0;
        for (int j = 0; j < 16; ++j)
            for (int i = 0; i < 16; ++i)
                (j < 8 ? upper : lower) += top.mean[3 * (j * 16 + i) + c];
        EXPECT_GT(upper, 1.5 * lower) << c;
    }
}

TEST(SphereTracer, DeterministicAcrossThreadCounts) {
    LitSphereSetup s = sphereSetup(20, 50, 0.5, 0.5, 0.7);
    s.threads = 1;
    const Image a = traceLitSphere(kMedia, s);
    s.threads = 2;
    const Image b = traceLitSphere(kMedia, s);
    s.threads = 3;
    const Image c = traceLitSphere(kMedia, s);
    EXPECT_GT(a.samples, 2 * kImageChunkPaths); // several chunks
    EXPECT_TRUE(sameBits(a.mean, b.mean));
    EXPECT_TRUE(sameBits(a.variance, b.variance));
    EXPECT_TRUE(sameBits(a.mean, c.mean));
    EXPECT_TRUE(sameBits(a.variance, c.variance));
    s.seed = 8;
    const Image d = traceLitSphere(kMedia, s);
    EXPECT_FALSE(sameBits(a.mean, d.mean));
}

TEST(SphereTracer, CancelKeepsACompletedPrefix) {
    LitSphereSetup s =
        sphereSetup(32, 3000, 0, 0, 1); // ~2.4M paths: seconds, cancelled after 50 ms
    s.threads = 2;
    std::atomic<bool> cancel{false};
    const Image img = traceLitSphere(
        kMedia, s, [&](uint64_t) { cancel = true; }, &cancel);
    EXPECT_LT(img.samples, litSpherePaths(s));
    EXPECT_EQ(img.samples % kImageChunkPaths, 0u);
    std::atomic<bool> early{true};
    const Image none = traceLitSphere(kMedia, s, {}, &early);
    EXPECT_EQ(none.samples, 0u);
    EXPECT_EQ(none.mean.size(), 3u * 32 * 32);
}

TEST(SphereTracer, ValidatesInputs) {
    auto expectError = [](const std::function<void()>& f, const std::string& word) {
        try {
            f();
            ADD_FAILURE() << "no error, expected one mentioning '" << word << "'";
        } catch (const core::Error& e) {
            EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
        }
    };
    LitSphereSetup s = sphereSetup(8, 1, 0, 0, 1);
    s.radiusMm = 0;
    expectError([&] { traceLitSphere(kMedia, s); }, "radius");
    s = sphereSetup(8, 1, 0, 0, 0);
    expectError([&] { traceLitSphere(kMedia, s); }, "light");
    s = sphereSetup(0, 1, 0, 0, 1);
    expectError([&] { traceLitSphere(kMedia, s); }, "size");
    s = sphereSetup(8, 0, 0, 0, 1);
    expectError([&] { traceLitSphere(kMedia, s); }, "samples");
    s = sphereSetup(8, 1, 0, 0, 1);
    auto bad = kMedia;
    bad[1].g = 1.0;
    expectError([&] { traceLitSphere(bad, s); }, "green");
    TraceOptions o;
    o.termination.rouletteWeight = 0;
    expectError([&] { traceLitSphere(kMedia, s, {}, nullptr, o); }, "rouletteWeight");
}

// A sphere much larger than the diffusion length (l_d = 1.7 mm, R = 960 mm), lit and seen
// along z: near the centre the surface is locally a slab under irradiance cos θ, so M there is
// the slab's total diffuse reflectance R_d (MCML convention: per incident power, Fresnel entry
// loss included) times cos θ, whose area average over a pixel is pixel area / footprint. The
// curvature raises M by O(l_d/R) (measured: +1.4 % at R = 60 mm, +0.5 % at 240 mm, +0.3 ± 0.3 %
// at 960 mm); allowance 0.5 %.
TEST(SphereTracer, CentreOfLargeSphereMatchesSlabTotalReflectance) {
    const Medium m = med(0.1, 1.0, 0.0, 1.3);
    LitSphereSetup s = sphereSetup(16, 6000, 0, 0, 1);
    s.radiusMm = 960.0;
    ImageStats st;
    const Image img = traceLitSphere({m, m, m}, s, {}, nullptr, {}, &st);
    const OrthoCamera cam(s, s.radiusMm);
    double sum = 0, var = 0, footprint = 0;
    int k = 0;
    for (int j = 7; j <= 8; ++j)
        for (int i = 7; i <= 8; ++i) {
            footprint += st.pixels.footprint[j * 16 + i];
            for (int c = 0; c < 3; ++c) {
                sum += img.mean[3 * (j * 16 + i) + c];
                var += img.variance[3 * (j * 16 + i) + c];
                ++k;
            }
        }
    const double mean = sum / k, err = std::sqrt(var) / k;
    const double cosAverage = 4 * cam.dx * cam.dy / footprint;
    SlabSettings ss;
    ss.paths = 400000;
    ss.bins = 1;
    ss.rMaxMm = 1e6;
    const SlabResult r = runSlab(m, ss);
    const double expected = r.totalRd * cosAverage;
    EXPECT_LT(std::fabs(mean - expected),
              4 * std::hypot(err, r.totalRdStderr * cosAverage) + 0.005 * expected)
        << "sphere centre " << mean << " +- " << err << ", slab R_d " << r.totalRd << " +- "
        << r.totalRdStderr << " x cos " << cosAverage;
    RecordProperty("sphere_centre", std::to_string(mean) + " +- " + std::to_string(err));
    RecordProperty("slab_total_rd_times_cos", std::to_string(expected));
}
