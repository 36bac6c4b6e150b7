// A model's BSSRDF on an estimate's bins (slice_model.h).
#include "pipeline/slice_model.h"

#include "pathtrace/fresnel.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace app {
namespace {

// ∫ T₂₁(μ) μ dμ over [mu0, mu1] by a fine midpoint rule (T is smooth: 4096 steps per unit
// of μ put the error far below float).
double transmittedMoment(double mu0, double mu1, double eta) {
    const int steps = std::max(16, int(4096 * (mu1 - mu0)));
    const double h = (mu1 - mu0) / steps;
    double sum = 0;
    for (int k = 0; k < steps; ++k) {
        const double mu = mu0 + (k + 0.5) * h;
        sum += (1.0 - pathtrace::fresnelDielectric(mu, eta)) * mu;
    }
    return sum * h;
}

struct Ring {
    double mu0, mu1, phi0, phi1;
};
Ring cellRange(const pathtrace::BssrdfBins& b, int cell) {
    const int ring = cell / b.dirPhiBins, sector = cell % b.dirPhiBins;
    const double dphi = 2 * std::numbers::pi / b.dirPhiBins;
    return {double(ring) / b.dirCosBins, double(ring + 1) / b.dirCosBins, sector * dphi,
            (sector + 1) * dphi};
}

size_t spatialSamples(const SliceSampling& n) {
    return size_t(n.radii) * size_t(n.angles) * 2;
}
size_t dirSamples(const pathtrace::BssrdfBins& b, bool readsWo, const SliceSampling& n) {
    return readsWo ? size_t(b.dirBins()) * size_t(n.mu) * size_t(n.phi) : 1;
}

} // namespace

double transmittedProjectedSolidAngle(double eta) {
    return 2 * std::numbers::pi * transmittedMoment(0.0, 1.0, eta);
}

double cellTransmittedProjectedSolidAngle(const pathtrace::BssrdfBins& b, int cell, double eta) {
    const Ring c = cellRange(b, cell);
    return (c.phi1 - c.phi0) * transmittedMoment(c.mu0, c.mu1, eta);
}

SliceSampling sliceSampling(const pathtrace::BssrdfBins& b, bool readsWo, size_t maxQueries) {
    SliceSampling n;
    const size_t bins = size_t(b.spatialBins());
    auto total = [&] { return bins * spatialSamples(n) * dirSamples(b, readsWo, n); };
    // halve the directional, then the spatial sub-samples, down to one per bin and cell
    while (total() > maxQueries && (n.mu > 1 || n.phi > 1)) {
        n.mu = std::max(1, n.mu / 2);
        n.phi = std::max(1, n.phi / 2);
    }
    while (total() > maxQueries && (n.radii > 1 || n.angles > 1)) {
        n.radii = std::max(1, n.radii / 2);
        n.angles = std::max(1, n.angles - 1);
    }
    return n;
}

std::vector<bssrdf::Query> sliceQueries(const pathtrace::BssrdfBins& b, double thetaIDeg,
                                        bool readsWo, const SliceSampling& n) {
    const std::vector<double> edges = b.rEdges();
    const double ti = thetaIDeg * std::numbers::pi / 180.0;
    const glm::vec3 wi(float(-std::sin(ti)), 0.0f, float(std::cos(ti)));
    const double dth = std::numbers::pi / b.thetaSBins;
    std::vector<bssrdf::Query> out;
    out.reserve(size_t(b.spatialBins()) * spatialSamples(n) * dirSamples(b, readsWo, n));
    for (int ir = 0; ir < b.rBins; ++ir)
        for (int it = 0; it < b.thetaSBins; ++it)
            for (int kr = 0; kr < n.radii; ++kr)
                for (int kt = 0; kt < n.angles; ++kt)
                    for (int half = 0; half < 2; ++half) {
                        const double r2lo = edges[size_t(ir)] * edges[size_t(ir)];
                        const double r2hi = edges[size_t(ir) + 1] * edges[size_t(ir) + 1];
                        const double r = std::sqrt(r2lo + (kr + 0.5) / n.radii * (r2hi - r2lo));
                        const double th = (it + (kt + 0.5) / n.angles) * dth;
                        const float sy = half ? -1.0f : 1.0f; // the mirror half
                        bssrdf::Query q;
                        q.xo = {float(r * std::cos(th)), sy * float(r * std::sin(th)), 0.0f};
                        q.wi = wi;
                        if (!readsWo) {
                            out.push_back(q);
                            continue;
                        }
                        for (int cell = 0; cell < b.dirBins(); ++cell) {
                            const Ring c = cellRange(b, cell);
                            for (int km = 0; km < n.mu; ++km)
                                for (int kp = 0; kp < n.phi; ++kp) {
                                    const double mu = c.mu0 + (km + 0.5) / n.mu * (c.mu1 - c.mu0);
                                    const double ph =
                                        c.phi0 + (kp + 0.5) / n.phi * (c.phi1 - c.phi0);
                                    const double st = std::sqrt(std::max(0.0, 1 - mu * mu));
                                    q.wo = {float(st * std::cos(ph)), sy * float(st * std::sin(ph)),
                                            float(mu)};
                                    out.push_back(q);
                                }
                        }
                    }
    return out;
}

ModelSlice modelSlice(const pathtrace::BssrdfBins& b, double thetaIDeg, double eta, bool readsWo,
                      const SliceSampling& n, const std::vector<double>& values) {
    const double entering =
        1.0 - pathtrace::fresnelDielectric(std::cos(thetaIDeg * std::numbers::pi / 180), eta);
    const double norm = entering / transmittedProjectedSolidAngle(eta);
    const size_t spatial = spatialSamples(n);
    const size_t cells = size_t(b.dirBins()), perCell = size_t(n.mu) * size_t(n.phi);
    std::vector<double> cellT(cells), cellCos(cells);
    for (size_t c = 0; c < cells; ++c) {
        cellT[c] = cellTransmittedProjectedSolidAngle(b, int(c), eta);
        cellCos[c] = pathtrace::cellProjectedSolidAngle(b, int(c));
    }
    ModelSlice m;
    m.R.assign(size_t(b.spatialBins()), 0.0);
    m.S.assign(size_t(b.spatialBins()) * cells, 0.0);
    size_t q = 0;
    for (size_t bin = 0; bin < m.R.size(); ++bin) {
        for (size_t k = 0; k < spatial; ++k) {
            if (!readsWo) {
                for (size_t c = 0; c < cells; ++c)
                    m.S[bin * cells + c] += values[q] * cellT[c];
                ++q;
                continue;
            }
            for (size_t c = 0; c < cells; ++c) {
                const Ring r = cellRange(b, int(c));
                const double w = (r.mu1 - r.mu0) / n.mu * (r.phi1 - r.phi0) / n.phi;
                for (size_t j = 0; j < perCell; ++j, ++q) {
                    const double mu =
                        r.mu0 + (double(j / size_t(n.phi)) + 0.5) / n.mu * (r.mu1 - r.mu0);
                    m.S[bin * cells + c] +=
                        values[q] * (1.0 - pathtrace::fresnelDielectric(mu, eta)) * mu * w;
                }
            }
        }
        for (size_t c = 0; c < cells; ++c) {
            double& s = m.S[bin * cells + c];
            s *= norm / (double(spatial) * cellCos[c]);
            m.R[bin] += s * cellCos[c];
        }
    }
    return m;
}

} // namespace app
