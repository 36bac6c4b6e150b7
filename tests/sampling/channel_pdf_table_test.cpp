// sampling/channel_pdf_table: the three channels' pdfs in one lookup are TabulatedRadial::pdfArea
// of each channel (1e-12 relative: the slope is divided once there, per lookup here; exact 0
// beyond R_m,c and the table), on the profile grid and on other radii; only tables that share
// their radii are joined; and DiskSampler's density through the joint table is the sum of its
// strategies' densities P_a·P_c·p_{a,c}(x) (1e-12 relative) at random probe hits on a sphere
// and a box, for every axis scheme and for unequal channel probabilities.
#include "sampling_support.h"

#include "mesh/mesh.h"
#include "pathtrace/rng.h"
#include "sampling/analytic_surfaces.h"
#include "sampling/channel_pdf_table.h"
#include "sampling/disk_sampling.h"
#include "sampling/gaussian_lobes.h"
#include "sampling/mesh_surface.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace sampling;
using namespace samplingtest;

namespace {

void expectSameAsEachChannel(const std::array<TabulatedRadial, 3>& ch, const char* what) {
    const auto joint = ChannelPdfTable::of(pointers(ch));
    ASSERT_TRUE(joint.has_value()) << what;
    const double rLast = ch[0].radii().back();
    pathtrace::Pcg32 rng(17, 3);
    std::vector<double> radii = ch[0].radii(); // every grid radius, then random ones
    for (int i = 0; i < 200000; ++i) {
        const double u = rng.uniform();
        radii.push_back(rLast * 1.05 * u * u);
    }
    radii.insert(radii.end(), {-1.0, ch[0].radiusMax(), ch[2].radiusMax(), rLast, 2 * rLast});
    for (double r : radii) {
        const glm::dvec3 p = joint->pdfArea(r);
        for (int c = 0; c < 3; ++c) {
            const double q = ch[c].pdfArea(r);
            if (q == 0) {
                ASSERT_EQ(p[c], 0.0) << what << " r " << r << " channel " << c;
            } else {
                ASSERT_NEAR(p[c] / q, 1.0, 1e-12) << what << " r " << r << " channel " << c;
            }
        }
    }
}
} // namespace

TEST(DiskChannelPdfTable, EqualsEachChannelsPdfOnTheProfileGrid) {
    expectSameAsEachChannel(skinChannels(), "profile grid");
}

TEST(DiskChannelPdfTable, EqualsEachChannelsPdfOnOtherRadii) {
    // uneven radii (not r_k = rMax (k/(K−1))²): the binary search
    std::vector<double> radii{0.0};
    for (int k = 1; k < 3000; ++k)
        radii.push_back(radii.back() + 0.002 + 0.03 * double(k % 7) / 7.0);
    std::vector<glm::dvec3> v;
    for (double r : radii)
        v.push_back({dipoleRd(0.74, 0.032, 1.3, r), dipoleRd(0.88, 0.17, 1.3, r),
                     dipoleRd(1.01, 0.48, 1.3, r)});
    expectSameAsEachChannel(tabulateChannels(radii, v), "uneven radii");
}

TEST(DiskChannelPdfTable, OnlyTablesOnSharedRadiiAreJoined) {
    const auto ch = skinChannels();
    const GaussianLobes g({{1.0, 0.5}});
    EXPECT_FALSE(ChannelPdfTable::of({&ch[0], &g, &ch[2]}).has_value());
    EXPECT_FALSE(ChannelPdfTable::of({nullptr, nullptr, nullptr}).has_value());
    EXPECT_TRUE(ChannelPdfTable::of({&ch[0], nullptr, &ch[2]}).has_value());
    const Table t = dipoleTable(skin1(), 50.0); // other radii
    const auto other = tabulateChannels(t.radii, t.values);
    EXPECT_FALSE(ChannelPdfTable::of({&ch[0], &other[1], &ch[2]}).has_value());
    // a channel without one has pdf 0
    const auto two = ChannelPdfTable::of({&ch[0], nullptr, &ch[2]});
    EXPECT_EQ(two->pdfArea(0.5)[1], 0.0);
    EXPECT_GT(two->pdfArea(0.5)[0], 0.0);
}

TEST(DiskChannelPdfTable, DiskDensityIsTheSumOfItsStrategies) {
    const auto ch = skinChannels();
    const SphereSurface sphere({0, 0, 0}, 6);
    const MeshSurface box(mesh::makeBox(40, 40, 4));
    const std::pair<const Surface*, Frame> cases[] = {
        {&sphere, Frame::fromNormal(glm::dvec3(0, 0.6, 0.8) * 6.0, {0, 0.6, 0.8})},
        {&box, Frame::fromNormal({19, 18.5, 2}, {0, 0, 1})}};
    for (const std::array<double, 3>& cp :
         {std::array<double, 3>{1, 1, 1}, std::array<double, 3>{0.6, 0.3, 0.1},
          std::array<double, 3>{0, 1, 2}}) {
        for (AxisScheme scheme : {AxisScheme::Uniform, AxisScheme::Pbrt, AxisScheme::NormalOnly}) {
            const DiskSampler ds(pointers(ch), axisProbabilities(scheme), cp);
            for (const auto& [surface, f] : cases) {
                pathtrace::Pcg32 rng(5, 6);
                int checked = 0;
                std::vector<SurfaceHit> hits;
                for (int i = 0; i < 20000; ++i) {
                    const Probe p =
                        ds.probe(f, rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform());
                    hits.clear();
                    ds.probeHits(*surface, f, p, hits);
                    for (const auto& h : hits) {
                        double sum = 0;
                        for (int a = 0; a < 3; ++a)
                            for (int c = 0; c < 3; ++c)
                                sum += ds.axisProbability(a) * ds.channelProbability(c) *
                                       ds.strategyPdf(f, a, c, h.point.x, h.point.n);
                        const double p = ds.pdf(f, h.point.x, h.point.n);
                        ASSERT_GT(sum, 0);
                        ASSERT_NEAR(p / sum, 1.0, 1e-12) << axisSchemeName(scheme);
                        ++checked;
                    }
                }
                EXPECT_GT(checked, 5000);
            }
        }
    }
}
