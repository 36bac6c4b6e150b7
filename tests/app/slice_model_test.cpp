// A model on an estimate's bins (app/pipeline/slice_model.h), without GL: the queries' geometry,
// the Fresnel normalisation against an independent quadrature, exactness of the bin averages where
// the midpoint rule is exact, and the directional average within the midpoint rule's error
// bound.
#include "pathtrace/fresnel.h"
#include "pipeline/slice_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

constexpr double kPi = std::numbers::pi;

pathtrace::BssrdfBins bins() {
    pathtrace::BssrdfBins b;
    b.rBins = 5;
    b.rMaxMm = 4.0;
    b.thetaSBins = 6;
    b.dirCosBins = 2;
    b.dirPhiBins = 4;
    return b;
}

// ∫ T(θ) cos θ sin θ dθ dφ over the hemisphere by Simpson's rule in θ (not the code's rule).
double transmittedSimpson(double eta) {
    const int n = 2000;
    const double h = (kPi / 2) / n;
    auto f = [&](double t) {
        return (1 - pathtrace::fresnelDielectric(std::cos(t), eta)) * std::cos(t) * std::sin(t);
    };
    double s = f(0) + f(kPi / 2);
    for (int k = 1; k < n; ++k)
        s += (k % 2 ? 4 : 2) * f(k * h);
    return 2 * kPi * s * h / 3;
}

} // namespace

TEST(SliceModel, FresnelNormalisationMatchesAnIndependentQuadrature) {
    for (double eta : {1.0, 1.3, 1.5}) {
        SCOPED_TRACE(eta);
        EXPECT_NEAR(app::transmittedProjectedSolidAngle(eta), transmittedSimpson(eta), 1e-6);
        const pathtrace::BssrdfBins b = bins();
        double sum = 0;
        for (int c = 0; c < b.dirBins(); ++c)
            sum += app::cellTransmittedProjectedSolidAngle(b, c, eta);
        EXPECT_NEAR(sum, app::transmittedProjectedSolidAngle(eta), 1e-9);
    }
    EXPECT_NEAR(app::transmittedProjectedSolidAngle(1.0), kPi, 1e-9); // no interface
}

TEST(SliceModel, QueriesLieInTheirBinsOnBothHalvesWithTheBeamsDirection) {
    const pathtrace::BssrdfBins b = bins();
    const app::SliceSampling n;
    const double ti = 60;
    const auto q = app::sliceQueries(b, ti, false, n);
    const size_t per = size_t(n.radii * n.angles * 2);
    ASSERT_EQ(q.size(), size_t(b.spatialBins()) * per);
    const auto edges = b.rEdges();
    for (size_t i = 0; i < q.size(); ++i) {
        const int bin = int(i / per), ir = bin / b.thetaSBins, it = bin % b.thetaSBins;
        const double r = std::hypot(q[i].xo.x, q[i].xo.y);
        EXPECT_GT(r, edges[size_t(ir)] - 1e-5);
        EXPECT_LT(r, edges[size_t(ir) + 1] + 1e-5);
        const double th = std::atan2(std::abs(q[i].xo.y), q[i].xo.x) * 180 / kPi;
        EXPECT_GE(th, it * 30.0 - 1e-3);
        EXPECT_LE(th, (it + 1) * 30.0 + 1e-3);
        EXPECT_EQ(q[i].xo.z, 0.0f);
        // toward the light, the beam travelling toward +x
        EXPECT_NEAR(q[i].wi.x, -std::sin(ti * kPi / 180), 1e-6);
        EXPECT_NEAR(q[i].wi.z, std::cos(ti * kPi / 180), 1e-6);
    }
    // with directions: a point on the lower half has its exit direction mirrored as well
    const auto qd = app::sliceQueries(b, ti, true, n);
    size_t mirrored = 0;
    for (size_t i = 0; i + 1 < qd.size(); ++i) {
        const auto& a = qd[i];
        // the query of the same sub-sample on the other half comes one directional block later
        const size_t block = size_t(b.dirBins() * n.mu * n.phi);
        if (i + block >= qd.size() || a.xo.y <= 0) continue;
        const auto& m = qd[i + block];
        if (m.xo.y < 0) {
            EXPECT_FLOAT_EQ(m.xo.y, -a.xo.y);
            EXPECT_FLOAT_EQ(m.wo.y, -a.wo.y);
            EXPECT_FLOAT_EQ(m.wo.x, a.wo.x);
            ++mirrored;
        }
    }
    EXPECT_GT(mirrored, 0u);
}

TEST(SliceModel, RadialModelGivesTheBinAverageTimesTheEnteringPower) {
    // f = a + c r² is linear in r², where the equal-area midpoint rule is exact
    const pathtrace::BssrdfBins b = bins();
    const app::SliceSampling n;
    const double eta = 1.4, ti = 30, a = 2.0, c = 0.25;
    const auto q = app::sliceQueries(b, ti, false, n);
    std::vector<double> v(q.size());
    for (size_t i = 0; i < q.size(); ++i)
        v[i] = a + c * (double(q[i].xo.x) * q[i].xo.x + double(q[i].xo.y) * q[i].xo.y);
    const app::ModelSlice m = app::modelSlice(b, ti, eta, false, n, v);
    const double t12 = 1 - pathtrace::fresnelDielectric(std::cos(ti * kPi / 180), eta);
    const auto edges = b.rEdges();
    for (int ir = 0; ir < b.rBins; ++ir) {
        // area average of a + c r² over the ring: a + c (r0² + r1²) / 2
        const double r0 = edges[size_t(ir)], r1 = edges[size_t(ir) + 1];
        const double avg = a + c * (r0 * r0 + r1 * r1) / 2;
        for (int it = 0; it < b.thetaSBins; ++it) {
            const size_t bin = size_t(ir * b.thetaSBins + it);
            EXPECT_NEAR(m.R[bin], t12 * avg, 1e-5 * t12 * avg) << ir << "," << it;
            // the cells share the exitance as the transmitted projected solid angles do
            double sum = 0;
            for (int cell = 0; cell < b.dirBins(); ++cell) {
                const double s = m.S[bin * size_t(b.dirBins()) + size_t(cell)];
                sum += s * pathtrace::cellProjectedSolidAngle(b, cell);
                EXPECT_NEAR(
                    s,
                    t12 * avg * app::cellTransmittedProjectedSolidAngle(b, cell, eta) /
                        (pathtrace::cellProjectedSolidAngle(b, cell) * transmittedSimpson(eta)),
                    1e-5 * s);
            }
            EXPECT_NEAR(sum, m.R[bin], 1e-12 * m.R[bin]);
        }
    }
}

TEST(SliceModel, DirectionalModelIsAveragedWithinTheMidpointRulesBound) {
    // η = 1 (T = 1): f = 1 + cos θo. S of a cell = (1/π) ∫ μ (1 + μ) dμ dφ / ∫ μ dμ dφ; the
    // midpoint rule in μ with n steps of h misses ∫ μ² by at most (μ1 − μ0) h² / 12.
    const pathtrace::BssrdfBins b = bins();
    const app::SliceSampling n;
    const auto q = app::sliceQueries(b, 0, true, n);
    std::vector<double> v(q.size());
    for (size_t i = 0; i < q.size(); ++i)
        v[i] = 1.0 + q[i].wo.z;
    const app::ModelSlice m = app::modelSlice(b, 0, 1.0, true, n, v);
    for (int cell = 0; cell < b.dirBins(); ++cell) {
        const int ring = cell / b.dirPhiBins;
        const double m0 = double(ring) / b.dirCosBins, m1 = double(ring + 1) / b.dirCosBins;
        const double first = (m1 * m1 - m0 * m0) / 2, second = (m1 * m1 * m1 - m0 * m0 * m0) / 3;
        const double exact = (first + second) / (kPi * first);
        const double h = (m1 - m0) / n.mu;
        const double bound = (m1 - m0) * h * h / 12 / (kPi * first) + 1e-6 * exact; // + float
        for (int bin = 0; bin < b.spatialBins(); ++bin)
            EXPECT_NEAR(m.S[size_t(bin * b.dirBins() + cell)], exact, bound) << cell;
    }
}

TEST(SliceModel, BigTablesUseFewerSubSamples) {
    auto total = [](const pathtrace::BssrdfBins& b, const app::SliceSampling& n) {
        return size_t(b.spatialBins()) * size_t(n.radii * n.angles * 2) *
               size_t(b.dirBins() * n.mu * n.phi);
    };
    const size_t cap = size_t(1) << 21;
    pathtrace::BssrdfBins b = bins();
    b.rBins = 50;
    b.thetaSBins = 24;
    b.dirCosBins = 4;
    b.dirPhiBins = 8;
    const app::SliceSampling n = app::sliceSampling(b, true, cap);
    EXPECT_LE(total(b, n), cap);
    EXPECT_LT(n.mu * n.phi, app::SliceSampling{}.mu * app::SliceSampling{}.phi);
    // past what one sample per bin and cell can hold: one sample each
    b.rBins = 200;
    b.thetaSBins = 90;
    b.dirCosBins = 8;
    b.dirPhiBins = 16;
    const app::SliceSampling one = app::sliceSampling(b, true, cap);
    EXPECT_EQ(one.radii * one.angles * one.mu * one.phi, 1);
    // the defaults stand for a small table
    const app::SliceSampling d = app::sliceSampling(bins(), true, cap);
    EXPECT_EQ(total(bins(), d), total(bins(), app::SliceSampling{}));
}
