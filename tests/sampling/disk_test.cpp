// sampling/disk_sampling, the parts that need no long runs: the frame, the axis schemes, the
// four probes of every axis in each sample, every hit of a probe (sphere: two; thin box: top
// and bottom), the MIS weights of random hits on a sphere and a box summing to 1 (one-sample
// balance and multi-sample power heuristic), and the plane: with NormalOnly and one channel every
// sample is exactly the kept energy (zero variance), and with channels chosen ∝ their kept energy
// every sample's channel sum is the total kept energy; with the three axes and channel MIS (1/3
// each or ∝ energy) the mean is the kept energy of each channel within Monte Carlo error (z-test,
// Bonferroni, family-wise 1e-3 per test).
#include "sampling_support.h"

#include "mesh/mesh.h"
#include "pathtrace/rng.h"
#include "sampling/analytic_surfaces.h"
#include "sampling/disk_sampling.h"
#include "sampling/gaussian_lobes.h"
#include "sampling/mesh_surface.h"
#include "sampling/stratified.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sampling;
using namespace samplingtest;

namespace {
// f_c(x) = R_c(|x − P|) for |x − P| <= R_m,c, else 0: on the plane its integral is E_m,c.
struct CutProfile {
    const DiskSampler* ds;
    glm::dvec3 p;
    glm::dvec3 operator()(const glm::dvec3& x, const glm::dvec3&) const {
        const double d = glm::length(x - p);
        glm::dvec3 f(0.0);
        for (int c = 0; c < 3; ++c)
            if (ds->channel(c) && d <= ds->channel(c)->radiusMax())
                f[c] = ds->channel(c)->profile(d);
        return f;
    }
};
// The two stratified uniforms of sample s as the integrator draws them (stratified.h): its
// Latin-hypercube block from stream `blockSeed` at the block's first sample (kept in `strata`),
// the jitter from stream `jitterSeed`.
std::pair<double, double> integratorUniforms(int s, uint64_t blockSeed, uint64_t jitterSeed,
                                             BlockStrata<2>& strata) {
    if (s % kBlockSamples == 0) {
        pathtrace::Pcg32 prng = pathtrace::Pcg32::forPath(blockSeed, uint64_t(s / kBlockSamples));
        strata = BlockStrata<2>::draw(prng);
    }
    pathtrace::Pcg32 rng = pathtrace::Pcg32::forPath(jitterSeed, uint64_t(s));
    const int k = s % kBlockSamples;
    const double u0 = strata.u(0, k, rng.uniform());
    return {u0, strata.u(1, k, rng.uniform())};
}
} // namespace

TEST(DiskSampling, FrameIsOrthonormal) {
    pathtrace::Pcg32 rng(1, 2);
    for (int i = 0; i < 1000; ++i) {
        const glm::dvec3 n(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        const Frame f = Frame::fromNormal(glm::dvec3(0.0), i == 0 ? glm::dvec3(0, 0, -1) : n);
        EXPECT_NEAR(glm::length(f.t), 1, 1e-14);
        EXPECT_NEAR(glm::length(f.b), 1, 1e-14);
        EXPECT_NEAR(glm::dot(f.n, f.t), 0, 1e-14);
        EXPECT_NEAR(glm::dot(f.n, f.b), 0, 1e-14);
        EXPECT_NEAR(glm::dot(f.t, f.b), 0, 1e-14);
        EXPECT_NEAR(glm::dot(glm::cross(f.t, f.b), f.n), 1, 1e-14);
    }
}

TEST(DiskSampling, AxisSchemes) {
    using A = std::array<double, 3>;
    EXPECT_EQ(axisProbabilities(AxisScheme::Uniform), (A{1.0 / 3, 1.0 / 3, 1.0 / 3}));
    EXPECT_EQ(axisProbabilities(AxisScheme::Pbrt), (A{0.5, 0.25, 0.25}));
    EXPECT_EQ(axisProbabilities(AxisScheme::NormalOnly), (A{1, 0, 0}));
    EXPECT_EQ(axisProbabilities(AxisScheme::All), (A{0.5, 0.25, 0.25})); // n_a/n
    // the probe picks axes and channels in proportion (and never one of probability 0)
    const GaussianLobes g({{1, 1}});
    const DiskSampler ds({&g, &g, nullptr}, {0.5, 0.25, 0.25}, {0.75, 0.25, 0});
    const Frame f;
    int axis[3] = {}, chan[3] = {};
    for (int i = 0; i < 1000; ++i) {
        const Probe p = ds.probe(f, (i + 0.5) / 1000, (i + 0.5) / 1000, 0.5, 0.25);
        ++axis[p.axis];
        ++chan[p.channel];
    }
    EXPECT_EQ(axis[0], 500);
    EXPECT_EQ(axis[1], 250);
    EXPECT_EQ(chan[0], 750);
    EXPECT_EQ(chan[2], 0);
    EXPECT_EQ(ds.probe(f, 1 - 0x1p-53, 1 - 0x1p-53, 0, 0).channel, 1);
}

// probe(f, uStrategy, uAngle), fed as the integrator feeds it (Latin-hypercube blocks): the
// nine strategies in proportion P_a·P_c and each strategy's radii from its channel's
// distribution, one Pearson chi-square over (strategy, radius bin) cells, the expected counts
// from the channels' cdf.
TEST(DiskSampling, TwoUniformProbeFollowsStrategiesAndRadii) {
    const auto ch = skinChannels();
    const DiskSampler ds(pointers(ch), axisProbabilities(AxisScheme::Pbrt),
                         energyChannelProbabilities(pointers(ch)));
    const Frame f = Frame::fromNormal({1, 2, 3}, {0.3, -0.2, 0.9});
    constexpr int kBins = 20, kN = 400000;
    std::vector<double> obs(9 * kBins, 0), exp(9 * kBins, 0);
    BlockStrata<2> strata;
    for (int s = 0; s < kN; ++s) {
        const auto [u0, u1] = integratorUniforms(s, 31, 32, strata);
        const Probe p = ds.probe(f, u0, u1);
        const double rm = ch[p.channel].radiusMax();
        ASSERT_LE(p.radius, rm);
        const int bin = std::min(kBins - 1, int(std::sqrt(p.radius / rm) * kBins));
        obs[size_t((3 * p.axis + p.channel) * kBins + bin)] += 1;
        // the disk point at radius r, perpendicular to the axis
        const glm::dvec3 mid = p.org + 0.5 * p.length * p.dir;
        ASSERT_NEAR(glm::length(mid - f.p), p.radius, 1e-9);
        ASSERT_EQ(p.dir, f.axis(p.axis));
    }
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) {
            const double rm = ch[c].radiusMax();
            for (int b = 0; b < kBins; ++b) {
                const double lo = rm * std::pow(double(b) / kBins, 2),
                             hi = rm * std::pow((b + 1.0) / kBins, 2);
                exp[size_t((3 * a + c) * kBins + b)] = kN * ds.axisProbability(a) *
                                                       ds.channelProbability(c) *
                                                       (ch[c].cdf(hi) - ch[c].cdf(lo));
            }
        }
    const auto chi = pttest::chiSquare(obs, exp);
    EXPECT_GT(chi.pValue, 1e-3) << "chi2 " << chi.stat << " dof " << chi.dof;
    EXPECT_GE(chi.dof, 150);
    // a channel of probability 0 is never chosen, u within rounding of 1 takes the last one
    const GaussianLobes g({{1, 1}});
    const DiskSampler two({&g, &g, nullptr}, {0.5, 0.25, 0.25}, {0.75, 0.25, 0});
    EXPECT_EQ(two.probe(f, 1 - 0x1p-53, 0.5).axis, 2);
    EXPECT_EQ(two.probe(f, 1 - 0x1p-53, 0.5).channel, 1);
}

// probes() of AxisScheme::All, fed as the integrator feeds it: four probes per sample, N, T,
// B sharing channel and radius, each through the point (r cos φ, r sin φ) of its own disk, and
// a second N probe of the uniforms shifted by 1/2; for each of the two draws, the channels in
// proportion P_c and each channel's radii from its distribution (Pearson chi-square over
// (channel, radius bin), one per draw); the one-sample schemes give the one probe of probe().
TEST(DiskSampling, EveryAxisProbesShareOneDraw) {
    const auto ch = skinChannels();
    const auto cp = energyChannelProbabilities(pointers(ch));
    const DiskSampler ds(pointers(ch), AxisScheme::All, cp);
    EXPECT_EQ(ds.probesPerSample(), 4);
    EXPECT_EQ(ds.axisProbability(0), 0.5);
    EXPECT_EQ(ds.axisProbability(1), 0.25);
    EXPECT_EQ(ds.axisProbability(2), 0.25);
    const Frame f = Frame::fromNormal({1, 2, 3}, {0.3, -0.2, 0.9});
    constexpr int kBins = 20, kN = 200000;
    std::array<std::vector<double>, 2> obs{std::vector<double>(3 * kBins, 0),
                                           std::vector<double>(3 * kBins, 0)};
    BlockStrata<2> strata;
    std::array<Probe, 4> ps;
    for (int s = 0; s < kN; ++s) {
        const auto [u0, u1] = integratorUniforms(s, 41, 42, strata);
        ASSERT_EQ(ds.probes(f, u0, u1, ps), 4);
        for (int i = 0; i < 4; ++i) {
            const Probe& p = ps[size_t(i)];
            const int a = i == 3 ? 0 : i;
            const double phi = 2 * std::numbers::pi * (i == 3 ? std::fmod(u1 + 0.5, 1.0) : u1);
            ASSERT_EQ(p.axis, a);
            ASSERT_EQ(p.dir, f.axis(a));
            if (i < 3) {
                ASSERT_EQ(p.channel, ps[0].channel);
                ASSERT_EQ(p.radius, ps[0].radius);
            }
            const glm::dvec3 mid = p.org + 0.5 * p.length * p.dir;
            const glm::dvec3 want = f.p + p.radius * (std::cos(phi) * f.axis((a + 1) % 3) +
                                                      std::sin(phi) * f.axis((a + 2) % 3));
            ASSERT_NEAR(glm::length(mid - want), 0, 1e-9);
            const double rm = ch[p.channel].radiusMax();
            ASSERT_LE(p.radius, rm);
            ASSERT_NEAR(p.length, 2 * std::sqrt(rm * rm - p.radius * p.radius), 1e-9);
            if (i == 0 || i == 3) {
                const int bin = std::min(kBins - 1, int(std::sqrt(p.radius / rm) * kBins));
                obs[i == 0 ? 0 : 1][size_t(p.channel * kBins + bin)] += 1;
            }
        }
    }
    std::vector<double> exp(3 * kBins, 0);
    for (int c = 0; c < 3; ++c) {
        const double rm = ch[c].radiusMax();
        for (int b = 0; b < kBins; ++b) {
            const double lo = rm * std::pow(double(b) / kBins, 2),
                         hi = rm * std::pow((b + 1.0) / kBins, 2);
            exp[size_t(c * kBins + b)] = kN * cp[size_t(c)] * (ch[c].cdf(hi) - ch[c].cdf(lo));
        }
    }
    for (int d = 0; d < 2; ++d) {
        const auto chi = pttest::chiSquare(obs[size_t(d)], exp);
        EXPECT_GT(chi.pValue, 1e-3) << "draw " << d << " chi2 " << chi.stat << " dof " << chi.dof;
        EXPECT_GE(chi.dof, 50);
    }
    // the one-sample schemes: one probe, probe()'s
    const DiskSampler one(pointers(ch), AxisScheme::Pbrt, cp);
    EXPECT_EQ(one.probesPerSample(), 1);
    ASSERT_EQ(one.probes(f, 0.7, 0.2, ps), 1);
    const Probe q = one.probe(f, 0.7, 0.2);
    EXPECT_EQ(ps[0].axis, q.axis);
    EXPECT_EQ(ps[0].channel, q.channel);
    EXPECT_EQ(ps[0].org, q.org);
}

TEST(DiskSampling, ProbeGeometry) {
    const GaussianLobes g({{1, 2}});
    const DiskSampler ds({&g, &g, &g}, AxisScheme::Uniform);
    const Frame f = Frame::fromNormal({1, 2, 3}, {0.3, -0.2, 0.9});
    pathtrace::Pcg32 rng(5, 6);
    for (int i = 0; i < 1000; ++i) {
        const Probe p = ds.probe(f, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
        const glm::dvec3 mid = p.org + 0.5 * p.length * p.dir;
        const glm::dvec3 end = p.org + p.length * p.dir;
        EXPECT_NEAR(glm::length(mid - f.p), p.radius, 1e-12);        // disk point at radius r
        EXPECT_NEAR(glm::dot(mid - f.p, p.dir), 0, 1e-12);           // on the disk's plane
        EXPECT_NEAR(glm::length(p.org - f.p), g.radiusMax(), 1e-12); // chord of the sphere
        EXPECT_NEAR(glm::length(end - f.p), g.radiusMax(), 1e-12);
        EXPECT_EQ(p.dir, f.axis(p.axis));
    }
}

TEST(DiskSampling, EveryHitOfAProbe) {
    // Sphere of radius 1: a probe along T at height 0.9 below the top crosses it twice.
    const SphereSurface s({0, 0, 0}, 1);
    std::vector<SurfaceHit> hits;
    s.intersectAll({-2, 0, 0.9}, {1, 0, 0}, 0, 4, hits);
    ASSERT_EQ(hits.size(), 2u);
    EXPECT_NEAR(std::fabs(hits[0].point.x.x), std::sqrt(1 - 0.81), 1e-14);
    EXPECT_NEAR(hits[0].point.x.x + hits[1].point.x.x, 0, 1e-14);
    hits.clear();
    s.intersectAll({-2, 0, 0.9}, {1, 0, 0}, 0, 2, hits); // segment ends inside: one
    EXPECT_EQ(hits.size(), 1u);
    // Thin box 4 × 4 × 0.2 (Embree): a vertical probe finds top and bottom, a horizontal one
    // the two side faces, each once, at the exact distances.
    const MeshSurface box(mesh::makeBox(4, 4, 0.2));
    EXPECT_NEAR(box.area(), 2 * 16 + 4 * 0.8, 1e-6); // float vertices
    hits.clear();
    box.intersectAll({0.3, -0.7, -5}, {0, 0, 1}, 0, 10, hits);
    ASSERT_EQ(hits.size(), 2u);
    double tsum = 0;
    for (const auto& h : hits) {
        tsum += h.t;
        EXPECT_NEAR(std::fabs(h.point.n.z), 1, 0);
        EXPECT_NEAR(h.point.x.z, h.point.n.z * 0.1, 1e-7);
    }
    EXPECT_NEAR(tsum, 10, 1e-6);
    hits.clear();
    box.intersectAll({-3, 0.5, 0.05}, {1, 0, 0}, 0, 6, hits);
    EXPECT_EQ(hits.size(), 2u);
    hits.clear();
    box.intersectAll({-3, 0.5, 0.05}, {1, 0, 0}, 0, 2.5, hits); // stops inside the box
    EXPECT_EQ(hits.size(), 1u);
    hits.clear();
    box.intersectAll({-3, 0.5, 0.5}, {1, 0, 0}, 0, 6, hits); // passes above
    EXPECT_EQ(hits.size(), 0u);
}

TEST(DiskSampling, MisWeightsOfAHitSumToOne) {
    const auto ch = skinChannels();
    const SphereSurface sphere({0, 0, 0}, 6);
    const MeshSurface box(mesh::makeBox(40, 40, 4));
    const std::pair<const Surface*, Frame> cases[] = {
        {&sphere, Frame::fromNormal(glm::dvec3(0, 0.6, 0.8) * 6.0, {0, 0.6, 0.8})},
        {&box, Frame::fromNormal({19, 18.5, 2}, {0, 0, 1})}};
    for (AxisScheme scheme :
         {AxisScheme::Uniform, AxisScheme::Pbrt, AxisScheme::NormalOnly, AxisScheme::All}) {
        const DiskSampler ds(pointers(ch), scheme);
        for (const auto& [surface, f] : cases) {
            pathtrace::Pcg32 rng(9, 10);
            int checked = 0;
            std::vector<SurfaceHit> hits;
            for (int i = 0; i < 20000; ++i) {
                const Probe p =
                    ds.probe(f, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
                hits.clear();
                ds.probeHits(*surface, f, p, hits);
                for (const auto& h : hits) {
                    const auto w = ds.misWeights(f, h.point.x, h.point.n);
                    double sum = 0;
                    for (const auto& row : w)
                        for (double v : row) {
                            EXPECT_GE(v, 0);
                            sum += v;
                        }
                    ASSERT_NEAR(sum, 1.0, 1e-12) << axisSchemeName(scheme);
                    // the strategy that found the hit could have found it
                    EXPECT_GT(w[p.axis][p.channel], 0) << axisSchemeName(scheme);
                    // the multi-sample power weights (AxisScheme::All's), and the factor of f:
                    // n_a p_a/Σ_b (n_b p_b)², with n ∝ P_a; 1/p(x) with one axis per sample
                    const auto wm = ds.multiSampleWeights(f, h.point.x, h.point.n);
                    ASSERT_NEAR(wm[0] + wm[1] + wm[2], 1.0, 1e-12) << axisSchemeName(scheme);
                    EXPECT_GT(wm[size_t(p.axis)], 0) << axisSchemeName(scheme);
                    const auto pa = ds.axisPdfs(f, h.point.x, h.point.n);
                    const double pdf = ds.pdf(f, h.point.x, h.point.n);
                    EXPECT_NEAR(ds.axisProbability(0) * pa[0] + ds.axisProbability(1) * pa[1] +
                                    ds.axisProbability(2) * pa[2],
                                pdf, 1e-12 * pdf);
                    const double k = ds.weightOverPdf(f, p, h.point.x, h.point.n);
                    if (scheme == AxisScheme::All) {
                        // (1/n_a)·w_a/p_a: the multi-sample estimator's term
                        const double na = p.axis == 0 ? 2 : 1;
                        EXPECT_NEAR(k, wm[size_t(p.axis)] / (na * pa[size_t(p.axis)]), 1e-12 * k);
                    } else {
                        EXPECT_NEAR(k, 1 / pdf, 1e-12 * k);
                    }
                    ++checked;
                }
            }
            EXPECT_GT(checked, 5000);
        }
    }
}

TEST(DiskSampling, PlaneNormalOnlyIsExact) {
    const auto ch = skinChannels();
    const PlaneSurface plane({0, 0, 0}, {0, 0, 1});
    const Frame f = Frame::fromNormal({0, 0, 0}, {0, 0, 1});
    // one channel: every sample is E_m of that channel
    for (int c = 0; c < 3; ++c) {
        std::array<double, 3> cp{0, 0, 0};
        cp[c] = 1;
        const DiskSampler ds(pointers(ch), axisProbabilities(AxisScheme::NormalOnly), cp);
        pathtrace::Pcg32 rng(3, uint64_t(c));
        for (int i = 0; i < 2000; ++i) {
            const glm::dvec3 e = estimateDisk(ds, plane, f, rng, CutProfile{&ds, f.p});
            ASSERT_NEAR(e[c] / ch[c].keptEnergy(), 1.0, 1e-9) << "channel " << c;
        }
    }
    // three channels with P_c ∝ E_m,c (energyChannelProbabilities): every sample's channel sum
    // is Σ_c E_m,c
    {
        const auto cp = energyChannelProbabilities(pointers(ch));
        double sumE = 0;
        for (int c = 0; c < 3; ++c) {
            sumE += ch[c].keptEnergy();
            EXPECT_NEAR(cp[c],
                        ch[c].keptEnergy() /
                            (ch[0].keptEnergy() + ch[1].keptEnergy() + ch[2].keptEnergy()),
                        1e-15);
        }
        const DiskSampler ds(pointers(ch), axisProbabilities(AxisScheme::NormalOnly), cp);
        pathtrace::Pcg32 rng(3, 7);
        for (int i = 0; i < 2000; ++i) {
            const glm::dvec3 e = estimateDisk(ds, plane, f, rng, CutProfile{&ds, f.p});
            ASSERT_NEAR((e[0] + e[1] + e[2]) / sumE, 1.0, 1e-9);
        }
        EXPECT_EQ(energyChannelProbabilities({&ch[0], nullptr, nullptr})[1], 0.0);
        EXPECT_EQ(energyChannelProbabilities({&ch[0], nullptr, nullptr})[0], 1.0);
    }
    // three channels of one profile (channel MIS over identical pdfs): exact in all three
    const GaussianLobes g({{0.7, 0.3}, {0.3, 4.0}});
    const DiskSampler ds({&g, &g, &g}, AxisScheme::NormalOnly);
    pathtrace::Pcg32 rng(4, 4);
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec3 e = estimateDisk(ds, plane, f, rng, CutProfile{&ds, f.p});
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(e[c] / g.keptEnergy(), 1.0, 1e-9);
    }
}

// The four axis schemes on a plane, tables and lobes: mean = E_m,c per channel (z-test).
TEST(DiskSampling, PlaneReproducesTheKeptEnergy) {
    const auto ch = skinChannels();
    const GaussianLobes g0({{0.233, 0.0064}, {0.1, 0.0484}, {0.118, 0.187}, {0.358, 1.99}});
    const GaussianLobes g1({{0.455, 0.0064}, {0.336, 0.0484}, {0.198, 0.187}});
    const GaussianLobes g2({{0.649, 0.0064}, {0.344, 0.0484}, {0.007, 0.567}});
    const std::array<std::array<const RadialDistribution*, 3>, 2> sets = {
        pointers(ch), std::array<const RadialDistribution*, 3>{&g0, &g1, &g2}};
    const PlaneSurface plane({1, 2, 3}, {0.2, 0.3, 1});
    const Frame f = Frame::fromNormal({1, 2, 3}, {0.2, 0.3, 1});
    const double zMax = core::bonferroniZ(1e-3, 2 * 4 * 3);
    int set = 0;
    for (const auto& dists : sets) {
        for (AxisScheme scheme :
             {AxisScheme::Uniform, AxisScheme::Pbrt, AxisScheme::NormalOnly, AxisScheme::All}) {
            const DiskSampler ds(dists, scheme);
            pathtrace::Pcg32 rng = pathtrace::Pcg32::forPath(21, uint64_t(4 * set + int(scheme)));
            Accumulator acc;
            std::vector<SurfaceHit> scratch;
            for (int i = 0; i < 200000; ++i)
                acc.add(estimateDisk(ds, plane, f, rng, CutProfile{&ds, f.p}, scratch));
            for (int c = 0; c < 3; ++c) {
                const double z = (acc.mean[c] - dists[c]->keptEnergy()) / acc.stderrOfMean()[c];
                EXPECT_LT(std::fabs(z), zMax)
                    << axisSchemeName(scheme) << " set " << set << " channel " << c << " mean "
                    << acc.mean[c] << " expected " << dists[c]->keptEnergy();
                EXPECT_GT(acc.stderrOfMean()[c], 0); // channel MIS over different pdfs: noisy
            }
        }
        ++set;
    }
}

// The same with channels chosen in proportion to their kept energy (the integrator's choice):
// mean = E_m,c per channel (z-test, Bonferroni over these 24 comparisons).
TEST(DiskSampling, PlaneReproducesTheKeptEnergyWithEnergyChannelProbabilities) {
    const auto ch = skinChannels();
    const GaussianLobes g0({{0.233, 0.0064}, {0.1, 0.0484}, {0.118, 0.187}, {0.358, 1.99}});
    const GaussianLobes g1({{0.455, 0.0064}, {0.336, 0.0484}, {0.198, 0.187}});
    const GaussianLobes g2({{0.649, 0.0064}, {0.344, 0.0484}, {0.007, 0.567}});
    const std::array<std::array<const RadialDistribution*, 3>, 2> sets = {
        pointers(ch), std::array<const RadialDistribution*, 3>{&g0, &g1, &g2}};
    const PlaneSurface plane({1, 2, 3}, {0.2, 0.3, 1});
    const Frame f = Frame::fromNormal({1, 2, 3}, {0.2, 0.3, 1});
    const double zMax = core::bonferroniZ(1e-3, 2 * 4 * 3);
    int set = 0;
    for (const auto& dists : sets) {
        for (AxisScheme scheme :
             {AxisScheme::Uniform, AxisScheme::Pbrt, AxisScheme::NormalOnly, AxisScheme::All}) {
            const DiskSampler ds(dists, scheme, energyChannelProbabilities(dists));
            pathtrace::Pcg32 rng = pathtrace::Pcg32::forPath(22, uint64_t(4 * set + int(scheme)));
            Accumulator acc;
            std::vector<SurfaceHit> scratch;
            for (int i = 0; i < 200000; ++i)
                acc.add(estimateDisk(ds, plane, f, rng, CutProfile{&ds, f.p}, scratch));
            for (int c = 0; c < 3; ++c) {
                const double z = (acc.mean[c] - dists[c]->keptEnergy()) / acc.stderrOfMean()[c];
                EXPECT_LT(std::fabs(z), zMax)
                    << axisSchemeName(scheme) << " set " << set << " channel " << c << " mean "
                    << acc.mean[c] << " expected " << dists[c]->keptEnergy();
                EXPECT_GT(acc.stderrOfMean()[c], 0);
            }
        }
        ++set;
    }
}
