// sampling/disk_sampling: see disk_sampling.h.
#include "sampling/disk_sampling.h"

#include "core/core.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sampling {
namespace {

// Normalised copy of p; throws unless finite, >= 0, with a positive sum.
std::array<double, 3> normalised(const std::array<double, 3>& p, const char* what) {
    double sum = 0;
    for (double v : p) {
        if (!(std::isfinite(v) && v >= 0))
            throw core::Error("disk sampler", 0,
                              std::string(what) + " probabilities must be finite and >= 0");
        sum += v;
    }
    if (!(sum > 0))
        throw core::Error("disk sampler", 0, std::string(what) + " probabilities sum to 0");
    return {p[0] / sum, p[1] / sum, p[2] / sum};
}

// The index i of weight > 0 whose interval [Σ_{j<i} w_j, Σ_{j<=i} w_j) holds u (weights summing
// to 1; the last of weight > 0 takes a u within rounding of 1), and in `rest` the remainder of u
// within that interval rescaled to [0, 1): uniform, and independent of the choice.
template <size_t N> int pickRescaled(const std::array<double, N>& w, double u, double& rest) {
    double cum = 0, lo = 0, width = 1;
    int pick = 0;
    for (size_t j = 0; j < N; ++j) {
        if (!(w[j] > 0)) continue;
        pick = int(j);
        lo = cum;
        width = w[j];
        cum += w[j];
        if (u < cum) break;
    }
    rest = std::clamp((u - lo) / width, 0.0, std::nextafter(1.0, 0.0));
    return pick;
}

// pickRescaled without the remainder.
int choose(const std::array<double, 3>& p, double u) {
    double rest = 0;
    return pickRescaled(p, u, rest);
}

// Σ_b (n_b p_b)², the power heuristic's denominator.
double powerSum(const std::array<double, 3>& n, const std::array<double, 3>& pa) {
    double sum = 0;
    for (size_t b = 0; b < 3; ++b)
        sum += (n[b] * pa[b]) * (n[b] * pa[b]);
    return sum;
}

} // namespace

std::array<double, 3> axisProbabilities(AxisScheme s) {
    switch (s) {
    case AxisScheme::Uniform:
        return {1.0 / 3, 1.0 / 3, 1.0 / 3};
    case AxisScheme::Pbrt:
    case AxisScheme::All: // n_a/n of n = (2, 1, 1)
        return {0.5, 0.25, 0.25};
    case AxisScheme::NormalOnly:
        return {1.0, 0.0, 0.0};
    }
    return {1.0, 0.0, 0.0};
}

std::array<double, 3>
energyChannelProbabilities(const std::array<const RadialDistribution*, 3>& channels) {
    std::array<double, 3> p{0, 0, 0};
    double sum = 0;
    for (int c = 0; c < 3; ++c) {
        if (!channels[c]) continue;
        const double e = channels[c]->keptEnergy();
        if (std::isfinite(e) && e > 0) p[c] = e;
        sum += p[c];
    }
    if (!(sum > 0 && std::isfinite(sum))) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
    return {p[0] / sum, p[1] / sum, p[2] / sum};
}

const char* axisSchemeName(AxisScheme s) {
    switch (s) {
    case AxisScheme::Uniform:
        return "uniform";
    case AxisScheme::Pbrt:
        return "pbrt";
    case AxisScheme::NormalOnly:
        return "normal";
    case AxisScheme::All:
        return "all";
    }
    return "?";
}

DiskSampler::DiskSampler(std::array<const RadialDistribution*, 3> channels,
                         std::array<double, 3> axisP, std::array<double, 3> channelP)
    : m_channels(channels), m_axisP(normalised(axisP, "axis")),
      m_chanP(normalised(channelP, "channel")) {
    for (int c = 0; c < 3; ++c) {
        if (m_chanP[c] == 0) continue;
        if (!m_channels[c])
            throw core::Error("disk sampler", 0,
                              "channel " + std::to_string(c) +
                                  " has a probability > 0 but no distribution");
        const double rm = m_channels[c]->radiusMax();
        m_rm2[c] = rm * rm;
        m_radiusMax = std::max(m_radiusMax, rm);
    }
    std::array<const RadialDistribution*, 3> used{};
    for (int c = 0; c < 3; ++c)
        if (m_chanP[c] > 0) used[c] = m_channels[c];
    m_joint = ChannelPdfTable::of(used);
}

DiskSampler::DiskSampler(std::array<const RadialDistribution*, 3> channels, AxisScheme scheme,
                         std::array<double, 3> channelP)
    : DiskSampler(channels, axisProbabilities(scheme), channelP) {
    if (scheme == AxisScheme::All) {
        m_everyAxis = true;
        m_axisN = {2, 1, 1}; // ∝ axisProbabilities(All)
    }
}

int DiskSampler::probes(const Frame& f, double uStrategy, double uAngle,
                        std::array<Probe, 4>& out) const {
    if (!m_everyAxis) {
        out[0] = probe(f, uStrategy, uAngle);
        return 1;
    }
    // One draw: the channel by P_c, the remainder of uStrategy, rescaled, the radius.
    double uRadius = 0;
    const int channel = pickRescaled(m_chanP, uStrategy, uRadius);
    const double radius = m_channels[channel]->sample(uRadius);
    for (int a = 0; a < 3; ++a)
        out[size_t(a)] = diskProbe(f, a, channel, radius, uAngle);
    // the second N probe: the uniforms shifted by 1/2 (uniform, and within a Latin-hypercube
    // block the shifted strata are again one per stratum)
    const double uStrategy2 = std::fmod(uStrategy + 0.5, 1.0),
                 uAngle2 = std::fmod(uAngle + 0.5, 1.0);
    const int channel2 = pickRescaled(m_chanP, uStrategy2, uRadius);
    out[3] = diskProbe(f, 0, channel2, m_channels[channel2]->sample(uRadius), uAngle2);
    return 4;
}

std::array<double, 3> DiskSampler::multiSampleWeights(const Frame& f, const glm::dvec3& x,
                                                      const glm::dvec3& nx) const {
    const std::array<double, 3> pa = axisPdfs(f, x, nx);
    const double sum = powerSum(m_axisN, pa);
    if (!(sum > 0)) return {0, 0, 0};
    std::array<double, 3> w{};
    for (size_t a = 0; a < 3; ++a)
        w[a] = (m_axisN[a] * pa[a]) * (m_axisN[a] * pa[a]) / sum;
    return w;
}

double DiskSampler::weightOverPdf(const Frame& f, const Probe& p, const glm::dvec3& x,
                                  const glm::dvec3& nx) const {
    if (!m_everyAxis) {
        const double pdf = this->pdf(f, x, nx);
        return pdf > 0 ? 1 / pdf : 0;
    }
    // (1/n_a)·w_a/p_a = n_a p_a / Σ_b (n_b p_b)²
    const std::array<double, 3> pa = axisPdfs(f, x, nx);
    const double sum = powerSum(m_axisN, pa);
    return sum > 0 ? m_axisN[size_t(p.axis)] * pa[size_t(p.axis)] / sum : 0;
}

Probe DiskSampler::probe(const Frame& f, double uStrategy, double uAngle) const {
    // the nine strategies (a, c) in the order N, T, B × channel 0, 1, 2
    std::array<double, 9> w{};
    for (size_t j = 0; j < 9; ++j)
        w[j] = m_axisP[j / 3] * m_chanP[j % 3];
    double uRadius = 0;
    const int j = pickRescaled(w, uStrategy, uRadius);
    const int axis = j / 3, channel = j % 3;
    return diskProbe(f, axis, channel, m_channels[channel]->sample(uRadius), uAngle);
}

Probe DiskSampler::probe(const Frame& f, double uAxis, double uChannel, double uRadius,
                         double uAngle) const {
    const int channel = choose(m_chanP, uChannel);
    return diskProbe(f, choose(m_axisP, uAxis), channel, m_channels[channel]->sample(uRadius),
                     uAngle);
}

Probe DiskSampler::diskProbe(const Frame& f, int axis, int channel, double radius,
                             double uAngle) const {
    Probe p;
    p.axis = axis;
    p.channel = channel;
    const RadialDistribution& d = *m_channels[p.channel];
    p.radius = radius;
    // The disk's own axes: the other two of (N, T, B), in cyclic order.
    const glm::dvec3& v = f.axis(p.axis);
    const glm::dvec3& e1 = f.axis((p.axis + 1) % 3);
    const glm::dvec3& e2 = f.axis((p.axis + 2) % 3);
    const double phi = 2 * std::numbers::pi * uAngle;
    const glm::dvec3 onDisk = f.p + p.radius * (std::cos(phi) * e1 + std::sin(phi) * e2);
    const double rm = d.radiusMax();
    const double half = std::sqrt(std::max(0.0, (rm - p.radius) * (rm + p.radius)));
    p.dir = v;
    p.org = onDisk - half * v;
    p.length = 2 * half;
    return p;
}

void DiskSampler::probeHits(const Surface& s, const Frame& f, const Probe& p,
                            std::vector<SurfaceHit>& out) const {
    const size_t first = out.size();
    s.intersectAll(p.org, p.dir, 0.0, p.length, out);
    const double rm2 = m_rm2[p.channel];
    out.erase(std::remove_if(out.begin() + std::ptrdiff_t(first), out.end(),
                             [&](const SurfaceHit& h) {
                                 const glm::dvec3 d = h.point.x - f.p;
                                 return !(glm::dot(d, d) <= rm2);
                             }),
              out.end());
}

double DiskSampler::strategyPdf(const Frame& f, int axis, int channel, const glm::dvec3& x,
                                const glm::dvec3& nx) const {
    if (m_chanP[channel] == 0) return 0;
    const glm::dvec3 d = x - f.p;
    const double d2 = glm::dot(d, d);
    if (!(d2 <= m_rm2[channel])) return 0;
    const glm::dvec3& v = f.axis(axis);
    const double along = glm::dot(d, v);
    const double r = std::sqrt(std::max(0.0, d2 - along * along)); // <= |d| as computed
    return m_channels[channel]->pdfArea(r) * std::fabs(glm::dot(v, nx));
}

std::array<double, 3> DiskSampler::axisPdfs(const Frame& f, const glm::dvec3& x,
                                            const glm::dvec3& nx) const {
    std::array<double, 3> pa{0, 0, 0};
    if (m_joint) { // strategyPdf's arithmetic, the three channels of an axis in one lookup
        const glm::dvec3 d = x - f.p;
        const double d2 = glm::dot(d, d);
        glm::dvec3 w(0.0); // P_c·[|x − P| <= R_m,c]
        for (int c = 0; c < 3; ++c)
            if (m_chanP[c] > 0 && d2 <= m_rm2[c]) w[c] = m_chanP[c];
        if (w == glm::dvec3(0.0)) return pa;
        for (int a = 0; a < 3; ++a) {
            if (m_axisP[a] == 0) continue;
            const glm::dvec3& v = f.axis(a);
            const double along = glm::dot(d, v);
            const double r = std::sqrt(std::max(0.0, d2 - along * along));
            pa[a] = std::fabs(glm::dot(v, nx)) * glm::dot(w, m_joint->pdfArea(r));
        }
        return pa;
    }
    for (int a = 0; a < 3; ++a) {
        if (m_axisP[a] == 0) continue;
        for (int c = 0; c < 3; ++c)
            if (m_chanP[c] > 0) pa[a] += m_chanP[c] * strategyPdf(f, a, c, x, nx);
    }
    return pa;
}

double DiskSampler::pdf(const Frame& f, const glm::dvec3& x, const glm::dvec3& nx) const {
    const std::array<double, 3> pa = axisPdfs(f, x, nx);
    return m_axisP[0] * pa[0] + m_axisP[1] * pa[1] + m_axisP[2] * pa[2];
}

std::array<std::array<double, 3>, 3> DiskSampler::misWeights(const Frame& f, const glm::dvec3& x,
                                                             const glm::dvec3& nx) const {
    std::array<std::array<double, 3>, 3> w{};
    const double p = pdf(f, x, nx);
    if (!(p > 0)) return w;
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c)
            if (m_axisP[a] > 0 && m_chanP[c] > 0)
                w[a][c] = m_axisP[a] * m_chanP[c] * strategyPdf(f, a, c, x, nx) / p;
    return w;
}

} // namespace sampling
