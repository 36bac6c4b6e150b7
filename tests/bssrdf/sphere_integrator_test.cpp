// The BSSRDF-integrated lit sphere (thesis 3.5, bssrdf/sphere_integrator.h) on the GPU:
//   (a) its Monte Carlo mean agrees (z-test) with an independent double-precision quadrature
//       of the same integral, the dipole R_d of Jensen et al. 2001 written again in C++;
//   (b) with the light on the view axis the image is rotationally symmetric (mirrored and
//       transposed pixels agree by z-test);
//   (c) pixels off the disk are exactly 0; the variance of the mean falls as 1/N and the mean
//       converges;
//   (d) the same seed gives the identical image; splitting the samples differently changes
//       only float rounding; a model parameter reaches the shader;
// and: rows run top to bottom; bad setups are rejected; the per-dispatch float sums are
// compensated; the sampler (hash + uniform area mapping) passes a chi-square test; the
// throughput on a 128x128 image is printed (never asserted).
#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "bssrdf/sphere_integrator.h"
#include "core/statistics.h"
#include "pathtrace/fresnel.h"
#include "pathtrace/lit_sphere.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace {

using Image = pathtrace::Image;

struct Dipole {
    bssrdf::Model model;
    gl::Program program;
};

const Dipole& dipole() {
    static Dipole d = [] {
        testsupport::context();
        Dipole r;
        r.model = bssrdf::loadModel(testsupport::sourceRoot() / "materials/dipole.bssrdf",
                                    "materials/dipole.bssrdf");
        shader::Sources src{testsupport::sourceRoot()};
        r.program = bssrdf::buildModelProgram(r.model, "sphere_bssrdf.comp", src);
        return r;
    }();
    return d;
}

// A material whose profile is broad next to the sphere (1/σtr ≈ 2–3.6 mm vs R = 5 mm), so
// uniform area sampling converges quickly and the quadrature is easy; channels differ.
bssrdf::Builtins testMaterial() {
    bssrdf::Builtins b;
    b.sigmaA = {0.05f, 0.1f, 0.02f};
    b.sigmaS = {1.0f, 0.7f, 1.3f};
    b.g = 0.0f;
    b.ior = 1.3f;
    b.scale = 1.0f;
    return b;
}

pathtrace::LitSphereSetup testSetup(int side, double lx, double ly, double lz, uint64_t seed) {
    pathtrace::LitSphereSetup s;
    s.radiusMm = 5.0;
    s.lightDir[0] = lx;
    s.lightDir[1] = ly;
    s.lightDir[2] = lz;
    s.width = s.height = side;
    s.seed = seed;
    return s;
}

Image render(const pathtrace::LitSphereSetup& s, const bssrdf::Builtins& b, int steps,
             int samplesPerStep, float multiplier = 1.0f) {
    const Dipole& d = dipole();
    bssrdf::ParamValues values = bssrdf::defaultValues(d.model);
    values["Multiplier"] = {multiplier, 0.0f, 0.0f};
    bssrdf::SphereIntegrator integ;
    integ.reset(s);
    for (int i = 0; i < steps; ++i)
        integ.step(d.program.id(), d.model, values, b, samplesPerStep);
    EXPECT_EQ(integ.samplesPerPixelDone(), uint64_t(steps) * uint64_t(samplesPerStep));
    return integ.image();
}

// Two-sided z threshold for `tests` comparisons at family-wise error `alpha` (Bonferroni),
// never below 3.5.
double zThreshold(size_t tests, double alpha = 0.005) {
    return std::max(3.5, core::bonferroniZ(alpha, static_cast<double>(tests)));
}

// ---- independent CPU reference ------------------------------------------------------------------
// Jensen, Marschner, Levoy & Hanrahan 2001, eq. 4 (thesis eq. 2.37 with its α′/4π prefactor; the
// thesis prints a stray σ′t under the virtual-source term): the diffuse reflectance profile per
// unit power entering, 1/mm², at distance r (mm).
struct DipoleChannel {
    double sigmaTr, alphaP, zr, zv;
    DipoleChannel(double sigmaA, double sigmaS, double g, double eta) {
        const double sigmaSp = sigmaS * (1 - g), sigmaTp = sigmaSp + sigmaA;
        const double fdr = -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta; // eq. 2.30
        const double a = (1 + fdr) / (1 - fdr);
        sigmaTr = std::sqrt(3 * sigmaA * sigmaTp);
        alphaP = sigmaSp / sigmaTp;
        zr = 1 / sigmaTp;             // real source at one reduced mean free path
        zv = zr + 4.0 / 3.0 * a * zr; // mirrored about the extrapolated boundary 2AD
    }
    double rd(double r) const {
        const double dr = std::sqrt(r * r + zr * zr), dv = std::sqrt(r * r + zv * zv);
        const double real = zr * (sigmaTr * dr + 1) * std::exp(-sigmaTr * dr) / (dr * dr * dr);
        const double virt = zv * (sigmaTr * dv + 1) * std::exp(-sigmaTr * dv) / (dv * dv * dv);
        return alphaP / (4 * std::numbers::pi) * (real + virt);
    }
};

struct Vec3 {
    double x, y, z;
};
Vec3 operator*(double s, Vec3 v) {
    return {s * v.x, s * v.y, s * v.z};
}
Vec3 operator+(Vec3 a, Vec3 b) {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
}
double dot(Vec3 a, Vec3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
Vec3 normalised(Vec3 v) {
    return (1 / std::sqrt(dot(v, v))) * v;
}
Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// Hit normal of pixel (i, j) (lit_sphere.h), or nothing when the centre ray misses.
std::optional<Vec3> hitNormal(const pathtrace::LitSphereSetup& s, int i, int j) {
    const double k = s.extent() / s.radiusMm;
    const double qx = (2 * (i + 0.5) / s.width - 1) * k, qy = (1 - 2 * (j + 0.5) / s.height) * k;
    const double q2 = qx * qx + qy * qy;
    if (q2 >= 1) return std::nullopt;
    return Vec3{qx, qy, std::sqrt(1 - q2)};
}

// M(xo) of lit_sphere.h by a product midpoint rule in spherical coordinates (θ, φ) about
// n(xo): θ = π t² (points gather where R_d peaks, smooth in t), φ uniform (periodic).
std::array<double, 3> quadrature(const pathtrace::LitSphereSetup& s, const bssrdf::Builtins& b,
                                 Vec3 no, int nt, int nphi) {
    const double R = s.radiusMm, pi = std::numbers::pi;
    const Vec3 light = normalised({s.lightDir[0], s.lightDir[1], s.lightDir[2]});
    const Vec3 helper = std::fabs(no.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 t1 = normalised(cross(no, helper)), t2 = cross(no, t1);
    std::array<DipoleChannel, 3> ch = {DipoleChannel(b.sigmaA[0], b.sigmaS[0], b.g, b.ior),
                                       DipoleChannel(b.sigmaA[1], b.sigmaS[1], b.g, b.ior),
                                       DipoleChannel(b.sigmaA[2], b.sigmaS[2], b.g, b.ior)};
    std::array<double, 3> m{0, 0, 0};
    const double dt = 1.0 / nt, dphi = 2 * pi / nphi;
    for (int a = 0; a < nt; ++a) {
        const double t = (a + 0.5) * dt, theta = pi * t * t;
        const double jac = R * R * std::sin(theta) * 2 * pi * t * dt * dphi; // dA
        const double r = 2 * R * std::sin(0.5 * theta);                      // chord |xi − xo|
        const double rd[3] = {ch[0].rd(r), ch[1].rd(r), ch[2].rd(r)};
        for (int c = 0; c < nphi; ++c) {
            const double phi = (c + 0.5) * dphi;
            const Vec3 ni =
                std::cos(theta) * no + std::sin(theta) * (std::cos(phi) * t1 + std::sin(phi) * t2);
            const double cosI = dot(ni, light);
            if (cosI <= 0) continue;
            const double w = (1 - pathtrace::fresnelDielectric(cosI, b.ior)) * cosI * jac;
            for (int k = 0; k < 3; ++k)
                m[k] += rd[k] * w;
        }
    }
    return m;
}

size_t at(const Image& img, int i, int j, int c) {
    return 3 * (static_cast<size_t>(j) * static_cast<size_t>(img.width) + static_cast<size_t>(i)) +
           static_cast<size_t>(c);
}

} // namespace

TEST(SphereIntegrator, MeanMatchesIndependentQuadrature) {
    const auto setup = testSetup(32, 0.6, 0.3, 1.0, 7);
    const auto b = testMaterial();
    core::Stopwatch clock;
    const Image img = render(setup, b, 64, 4096);
    std::printf("[ info     ] GPU: %d spp x %dx%d in %.2f s\n", 64 * 4096, setup.width,
                setup.height, clock.ms() * 1e-3);
    // centre, lit side, towards the rim on the far side, near the terminator, the rim
    const std::vector<std::array<int, 2>> pixels = {{16, 16}, {22, 12}, {6, 22}, {5, 25}, {1, 16}};
    const double z = zThreshold(pixels.size() * 3);
    clock.reset();
    for (const auto& [i, j] : pixels) {
        auto no = hitNormal(setup, i, j);
        ASSERT_TRUE(no) << i << "," << j;
        const auto ref = quadrature(setup, b, *no, 200, 200);
        const auto fine = quadrature(setup, b, *no, 400, 400);
        for (int c = 0; c < 3; ++c) {
            const double mean = img.mean[at(img, i, j, c)];
            const double se = std::sqrt(double(img.variance[at(img, i, j, c)]));
            std::printf("[ info     ] (%2d,%2d) c%d quad %.6g (Δfine %.2g) gpu %.6g ± %.2g "
                        "(%.2f%%) z %.2f\n",
                        i, j, c, fine[c], fine[c] - ref[c], mean, se, 100 * se / mean,
                        (mean - fine[c]) / se);
            // the quadrature has converged far below the statistical error...
            EXPECT_LT(std::fabs(fine[c] - ref[c]), 0.05 * se);
            // ...the test has power: a 5 % error would show (e.g. a missing Fresnel factor)...
            EXPECT_LT(se, 0.05 * fine[c] / z);
            // ...and the GPU estimate agrees with it
            EXPECT_LT(std::fabs(mean - fine[c]), z * se) << i << "," << j << " channel " << c;
        }
    }
    std::printf("[ info     ] quadrature in %.2f s\n", clock.ms() * 1e-3);
}

TEST(SphereIntegrator, LightOnViewAxisGivesRotationallySymmetricImage) {
    const auto setup = testSetup(32, 0.0, 0.0, 1.0, 11);
    const Image img = render(setup, testMaterial(), 16, 4096);
    struct Pair {
        int i, j, k, l;
    };
    std::vector<Pair> pairs;
    const int w = setup.width, h = setup.height;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            if (!hitNormal(setup, i, j)) continue;
            if (w - 1 - i > i) pairs.push_back({i, j, w - 1 - i, j}); // mirror in x
            if (h - 1 - j > j) pairs.push_back({i, j, i, h - 1 - j}); // mirror in y
            if (j > i) pairs.push_back({i, j, j, i});                 // transpose
        }
    ASSERT_GT(pairs.size(), 900u);
    const double z = zThreshold(pairs.size() * 3);
    double worst = 0;
    for (const auto& p : pairs)
        for (int c = 0; c < 3; ++c) {
            const size_t a = at(img, p.i, p.j, c), b = at(img, p.k, p.l, c);
            const double se = std::sqrt(double(img.variance[a]) + double(img.variance[b]));
            ASSERT_GT(se, 0);
            const double d = std::fabs(double(img.mean[a]) - double(img.mean[b])) / se;
            worst = std::max(worst, d);
            EXPECT_LT(d, z) << "(" << p.i << "," << p.j << ") vs (" << p.k << "," << p.l
                            << ") channel " << c;
        }
    std::printf("[ info     ] %zu pairs, worst |z| %.2f (threshold %.2f)\n", pairs.size(), worst,
                z);
}

TEST(SphereIntegrator, OffDiskIsZeroAndEstimateConverges) {
    const auto setup = testSetup(32, 0.6, 0.3, 1.0, 5);
    const auto b = testMaterial();
    const Dipole& d = dipole();
    const auto values = bssrdf::defaultValues(d.model);
    bssrdf::SphereIntegrator integ;
    integ.reset(setup);
    integ.step(d.program.id(), d.model, values, b, 16384); // four dispatches
    const Image first = integ.image();
    integ.step(d.program.id(), d.model, values, b, 3 * 16384);
    const Image last = integ.image();
    EXPECT_EQ(integ.samplesPerPixelDone(), 65536u);
    EXPECT_EQ(last.samples, 65536u * 32u * 32u);
    ASSERT_EQ(last.width, 32);
    ASSERT_EQ(last.height, 32);
    ASSERT_EQ(last.mean.size(), 32u * 32u * 3u);
    ASSERT_EQ(last.variance.size(), 32u * 32u * 3u);

    double varFirst = 0, varLast = 0;
    size_t hits = 0, misses = 0;
    std::vector<size_t> inside;
    for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 32; ++i) {
            const double k = setup.extent() / setup.radiusMm;
            const double qx = (2 * (i + 0.5) / 32 - 1) * k, qy = (1 - 2 * (j + 0.5) / 32) * k;
            const double q2 = qx * qx + qy * qy;
            for (int c = 0; c < 3; ++c) {
                const size_t a = at(last, i, j, c);
                if (q2 > 1 + 1e-6) {
                    EXPECT_EQ(last.mean[a], 0.0f) << i << "," << j;
                    EXPECT_EQ(last.variance[a], 0.0f) << i << "," << j;
                    misses += c == 0;
                } else if (q2 < 1 - 1e-6) {
                    // every point of this sphere gets some light through the medium
                    EXPECT_GT(last.mean[a], 0.0f) << i << "," << j;
                    EXPECT_GT(last.variance[a], 0.0f) << i << "," << j;
                    varFirst += first.variance[a];
                    varLast += last.variance[a];
                    inside.push_back(a);
                    hits += c == 0;
                }
            }
        }
    EXPECT_GT(misses, 100u);
    EXPECT_GT(hits, 500u);
    // 4x the samples: the variance of the mean shrinks 4x (summed over pixels, the estimate
    // of the ratio is good to a few %)
    const double ratio = varFirst / varLast;
    std::printf("[ info     ] variance of the mean, 16384 -> 65536 spp: ratio %.3f\n", ratio);
    EXPECT_GT(ratio, 4.0 / 1.1);
    EXPECT_LT(ratio, 4.0 * 1.1);
    // the mean converges: m_N − m_4N = ¾ (m_N − m_rest) has variance ¾ Var(m_N)
    const double z = zThreshold(inside.size());
    double worst = 0;
    for (size_t a : inside) {
        const double dz = (double(first.mean[a]) - double(last.mean[a])) /
                          std::sqrt(0.75 * double(first.variance[a]));
        worst = std::max(worst, std::fabs(dz));
        EXPECT_LT(std::fabs(dz), z) << a;
    }
    std::printf("[ info     ] mean N vs 4N: worst |z| %.2f (threshold %.2f)\n", worst, z);
}

TEST(SphereIntegrator, OrientationTopRowFirst) {
    // a non-square image: rows and columns are not interchangeable
    auto setup = testSetup(40, 0.0, 1.0, 0.3, 3);
    setup.height = 24;
    const auto b = testMaterial();
    const Image up = render(setup, b, 1, 1024);
    ASSERT_EQ(up.width, 40);
    ASSERT_EQ(up.height, 24);
    // light from +y (up): the top of the disk is lit, the bottom is dark
    for (int c = 0; c < 3; ++c)
        EXPECT_GT(up.mean[at(up, 20, 2, c)], 10 * up.mean[at(up, 20, 21, c)]);
    setup.lightDir[0] = 1.0;
    setup.lightDir[1] = 0.0;
    const Image right = render(setup, b, 1, 1024);
    for (int c = 0; c < 3; ++c)
        EXPECT_GT(right.mean[at(right, 37, 12, c)], 10 * right.mean[at(right, 2, 12, c)]);
}

TEST(SphereIntegrator, SameSeedSameImageAndSplitsAgree) {
    const auto setup = testSetup(32, 0.6, 0.3, 1.0, 42);
    const auto b = testMaterial();
    const Image a = render(setup, b, 2, 2000);
    const Image again = render(setup, b, 2, 2000);
    ASSERT_EQ(a.mean.size(), again.mean.size());
    EXPECT_EQ(0, std::memcmp(a.mean.data(), again.mean.data(), a.mean.size() * sizeof(float)));
    EXPECT_EQ(0, std::memcmp(a.variance.data(), again.variance.data(),
                             a.variance.size() * sizeof(float)));

    // the same samples in one dispatch: equal up to float rounding of the dispatch sums
    const Image whole = render(setup, b, 1, 4000);
    size_t nonzero = 0;
    for (size_t i = 0; i < a.mean.size(); ++i) {
        EXPECT_NEAR(whole.mean[i], a.mean[i], 1e-5 * a.mean[i]) << i;
        EXPECT_NEAR(whole.variance[i], a.variance[i], 1e-4 * a.variance[i]) << i;
        nonzero += a.mean[i] != 0;
    }
    EXPECT_GT(nonzero, 1500u);

    // another seed draws other samples
    auto other = setup;
    other.seed = 43;
    const Image b2 = render(other, b, 2, 2000);
    size_t differ = 0;
    for (size_t i = 0; i < a.mean.size(); ++i)
        differ += a.mean[i] != b2.mean[i];
    EXPECT_EQ(differ, nonzero);

    // a model parameter reaches the shader: Multiplier 2 doubles every sample exactly
    const Image twice = render(setup, b, 2, 2000, 2.0f);
    for (size_t i = 0; i < a.mean.size(); ++i) {
        EXPECT_EQ(twice.mean[i], 2 * a.mean[i]) << i;
        EXPECT_EQ(twice.variance[i], 4 * a.variance[i]) << i;
    }

    // reset starts over
    const Dipole& d = dipole();
    bssrdf::SphereIntegrator integ;
    integ.reset(setup);
    integ.step(d.program.id(), d.model, bssrdf::defaultValues(d.model), b, 1000);
    integ.reset(setup);
    EXPECT_EQ(integ.samplesPerPixelDone(), 0u);
    EXPECT_EQ(integ.image().samples, 0u);
    for (int k = 0; k < 2; ++k)
        integ.step(d.program.id(), d.model, bssrdf::defaultValues(d.model), b, 2000);
    const Image reset = integ.image();
    EXPECT_EQ(0, std::memcmp(a.mean.data(), reset.mean.data(), a.mean.size() * sizeof(float)));
}

TEST(SphereIntegrator, RejectsBadSetupAndIgnoresEmptySteps) {
    const Dipole& d = dipole();
    bssrdf::SphereIntegrator integ;
    // before reset and for no samples: nothing happens
    integ.step(d.program.id(), d.model, bssrdf::defaultValues(d.model), testMaterial(), 10);
    EXPECT_EQ(integ.samplesPerPixelDone(), 0u);
    EXPECT_EQ(integ.image().width, 0);
    auto s = testSetup(8, 0, 0, 1, 1);
    integ.reset(s);
    integ.step(d.program.id(), d.model, bssrdf::defaultValues(d.model), testMaterial(), 0);
    EXPECT_EQ(integ.samplesPerPixelDone(), 0u);
    const Image empty = integ.image();
    EXPECT_EQ(empty.width, 8);
    EXPECT_EQ(empty.mean, std::vector<float>(8 * 8 * 3, 0.0f));

    auto bad = s;
    bad.radiusMm = 0;
    EXPECT_THROW(integ.reset(bad), core::Error);
    bad = s;
    bad.radiusMm = std::nan("");
    EXPECT_THROW(integ.reset(bad), core::Error);
    bad = s;
    bad.width = 0;
    EXPECT_THROW(integ.reset(bad), core::Error);
    bad = s;
    bad.lightDir[2] = 0;
    EXPECT_THROW(integ.reset(bad), core::Error);
    // a rejected setup keeps the previous one
    EXPECT_EQ(integ.setup().width, 8);
}

// The float sums of one dispatch are Kahan-compensated: one dispatch of 1024 samples gives
// what 1024 dispatches of one sample (each exact in float, added in double) give, to about one
// rounding, where a plain float sum would drift by ~sqrt(1024) roundings.
TEST(SphereIntegrator, DispatchSumsAreCompensated) {
    const auto setup = testSetup(8, 0.6, 0.3, 1.0, 77);
    const Image one = render(setup, testMaterial(), 1, 1024);
    const Image many = render(setup, testMaterial(), 1024, 1);
    double worst = 0, worstSq = 0;
    for (size_t i = 0; i < one.mean.size(); ++i) {
        if (many.mean[i] == 0) continue;
        worst = std::max(worst, std::fabs(double(one.mean[i]) / double(many.mean[i]) - 1));
        worstSq =
            std::max(worstSq, std::fabs(double(one.variance[i]) / double(many.variance[i]) - 1));
    }
    std::printf("[ info     ] worst relative difference: mean %.3g variance %.3g\n", worst,
                worstSq);
    // llvmpipe: 9e-8 and 1.2e-7 compensated, 1e-6 for both with a plain float sum
    EXPECT_LT(worst, 3e-7);
    EXPECT_LT(worstSq, 5e-7);
}

// Chi-square test of the sampler: a model that counts the samples falling in one bin of a
// 16 (z) x 16 (φ) grid on the lit hemisphere (IOR 1, so f = 4πR² · Bssrdf · cos θi = the bin's
// indicator). Each pixel and channel counts a different bin (chosen from the bits of xo), so
// every (pixel, channel) is a binomial count with p = 1/512 from its own stream.
TEST(SphereIntegrator, SamplerChiSquare) {
    const std::string text = R"(analytic
::begin shader
vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) {
    vec3 n = normalize(Xi);
    uint h = floatBitsToUint(Xo.x) * 2654435761u ^ floatBitsToUint(Xo.y) * 2246822519u;
    uint base = (h ^ (h >> 15u)) % 256u;
    int zb = min(int(n.z * 16.0), 15);
    int pb = min(int((atan(n.y, n.x) + PI) / (2.0 * PI) * 16.0), 15);
    uint bin = uint(zb * 16 + pb);
    vec3 hit = vec3(bin == base, bin == (base + 1u) % 256u, bin == (base + 2u) % 256u);
    return hit / (dot(n, Wi) * 4.0 * PI * dot(Xi, Xi));
}
::end shader
)";
    testsupport::context();
    const bssrdf::Model m = bssrdf::parseModel(text, "tests/bins.bssrdf");
    shader::Sources src{testsupport::sourceRoot()};
    const gl::Program program = bssrdf::buildModelProgram(m, "sphere_bssrdf.comp", src);
    auto b = testMaterial();
    b.ior = 1.0f;
    const auto setup = testSetup(32, 0.0, 0.0, 1.0, 21);
    bssrdf::SphereIntegrator integ;
    integ.reset(setup);
    const int n = 65536;
    integ.step(program.id(), m, {}, b, n);
    const Image img = integ.image();
    const double p = 1.0 / 512, expected = n * p;
    double chi2 = 0;
    size_t dof = 0;
    for (int j = 0; j < setup.height; ++j)
        for (int i = 0; i < setup.width; ++i) {
            if (!hitNormal(setup, i, j)) continue;
            for (int c = 0; c < 3; ++c) {
                const double count = img.mean[at(img, i, j, c)] * double(n);
                EXPECT_NEAR(count, std::round(count), 0.05) << i << "," << j; // f is 0 or 1
                chi2 += (count - expected) * (count - expected) / (expected * (1 - p));
                ++dof;
            }
        }
    ASSERT_GT(dof, 1900u);
    // χ² with `dof` degrees of freedom: mean dof, standard deviation sqrt(2 dof)
    const double zc = (chi2 - double(dof)) / std::sqrt(2.0 * double(dof));
    std::printf("[ info     ] chi2 %.1f, dof %zu, z %.2f\n", chi2, dof, zc);
    EXPECT_LT(std::fabs(zc), 4.0);
}

// Throughput on this device (printed, never asserted): 128x128, the default-size image.
TEST(SphereIntegrator, ReportsThroughput) {
    const auto setup = testSetup(128, 0.6, 0.3, 1.0, 9);
    const Dipole& d = dipole();
    const auto values = bssrdf::defaultValues(d.model);
    bssrdf::SphereIntegrator integ;
    integ.reset(setup);
    integ.step(d.program.id(), d.model, values, testMaterial(), 64); // warm-up
    core::Stopwatch clock;
    integ.step(d.program.id(), d.model, values, testMaterial(), 2048);
    const double s = clock.ms() * 1e-3;
    const double samples = 2048.0 * 128 * 128;
    std::printf("[ info     ] 128x128 x 2048 spp: %.2f s, %.1f M samples/s (%s)\n", s,
                samples / s * 1e-6, testsupport::context().renderer().c_str());
    EXPECT_EQ(integ.samplesPerPixelDone(), 2048u + 64u);
}

// A model with loops of its own (quantized diffusion: 40 lobes per evaluation) uses up Mesa
// llvmpipe's 65535 loop iterations per invocation within one large dispatch; the integrator sees
// the cut (a sentinel loop after the samples) and takes fewer samples per dispatch, so the
// image is the one of small dispatches, which the limit never reaches (within float rounding:
// the per-dispatch float sums are split differently). Without the check it was ~1/2.75 of it.
TEST(SphereIntegrator, ModelLoopsThatExhaustTheDriversLoopLimitAreSplitIntoSmallerDispatches) {
    testsupport::context();
    const bssrdf::Model m =
        bssrdf::loadModel(testsupport::sourceRoot() / "materials/quantized_diffusion.bssrdf",
                          "materials/quantized_diffusion.bssrdf");
    shader::Sources src{testsupport::sourceRoot()};
    gl::Program prog = bssrdf::buildModelProgram(m, "sphere_bssrdf.comp", src);
    const bssrdf::ParamValues values = bssrdf::defaultValues(m);
    const pathtrace::LitSphereSetup s = testSetup(4, 0.3, 0.2, 0.93, 5);
    bssrdf::SphereIntegrator big, small;
    big.reset(s);
    big.step(prog.id(), m, values, testMaterial(), 4096); // one request: the integrator splits it
    small.reset(s);
    for (int i = 0; i < 32; ++i)
        small.step(prog.id(), m, values, testMaterial(), 128); // 128 × 40 lobes: far below
    const Image a = big.image(), b = small.image();
    ASSERT_EQ(a.mean.size(), b.mean.size());
    size_t lit = 0;
    for (size_t i = 0; i < a.mean.size(); ++i) {
        if (b.mean[i] == 0) continue;
        ++lit;
        EXPECT_NEAR(a.mean[i], b.mean[i], 1e-4 * std::abs(b.mean[i])) << i;
    }
    EXPECT_GT(lit, 0u);
}
