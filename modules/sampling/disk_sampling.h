// sampling/disk_sampling: disk-based probe-ray sampling with axis and channel MIS, King et al.
// 2013 (eq. 1, "Axis and Weight Multiple Importance Sampling").
//
// Sampling (one sample): an axis a ∈ {N, T, B} of the shading frame with probability P_a
// (AxisScheme: Uniform 1/3 each as in the paper, Pbrt 1/2, 1/4, 1/4 as pbrt-v3, NormalOnly
// 1, 0, 0); a channel c with probability P_c (1/3 each by default, or ∝ E_m,c: see "Channel
// probabilities" below); a point on the disk through
// P perpendicular to V_a, at radius r ~ channel c's RadialDistribution and angle 2πu, so of
// density pdf_c(r) per unit disk area (pdf_area of radial.h); the probe is the segment along
// V_a through that point, clipped to the sphere of radius R_m,c around P (half-length
// √(R_m,c² − r²)), and EVERY surface point it crosses is used.
//
// What the estimator integrates. Fix (a, c). A surface point x with |x − P| <= R_m,c lies on
// exactly one probe line of axis a (the one through its projection onto the disk, at radius
// r_a(x) = |(x − P) − ((x − P)·V_a) V_a|), and that line's segment reaches it (the segment is
// the whole chord of the sphere). Projecting a small surface patch dA(x) onto the disk along
// V_a gives dA_disk = |V_a·N_x| dA(x). So the hits of one probe, summed, turn the disk integral
// into a surface integral:
//     E_disk[ Σ_{hits x} h(x) ] = ∫_{S ∩ B(P, R_m,c)} h(x) · pdf_c(r_a(x)) · |V_a·N_x| dA(x)
// for any h; several surface points on one line (a sphere seen edge-on, the two faces of a
// thin box) are each counted once, through their own patch. Hence strategy (a, c) finds x with
// area density p_{a,c}(x) = pdf_c(r_a(x)) · |V_a·N_x| · [|x − P| <= R_m,c], and choosing (a, c)
// at random with the balance heuristic (Veach's one-sample MIS) gives the combined density
//     p(x) = Σ_a Σ_c P_a · P_c · p_{a,c}(x)
// and the estimator  F = Σ_{hits x} f(x)/p(x)  with expectation
//     E[F] = Σ_{a,c} P_a P_c ∫ p_{a,c}(x) f(x)/p(x) dA = ∫_{S, p(x) > 0} f(x) dA(x),
// i.e. ∫ f over the surface within max_c R_m,c of P (minus the points no strategy can find:
// with NormalOnly, surfaces parallel to N, such as the side faces of a box seen from its top;
// with the three axes, Σ_a (V_a·N_x)² = 1 so some |V_a·N_x| >= 1/√3 and only the radial
// cut-offs remain). For f(x) = R(|x − P|)·E(x) this is the paper's eq. 1 with the MIS of its
// second section. The per-strategy weights w_{a,c}(x) = P_a P_c p_{a,c}(x)/p(x) sum to 1.
// Because R is decreasing and r_a(x) <= |x − P|, pdf_c(r_a(x)) >= R_c(|x − P|)/E_c, so with
// the three axes f/p stays bounded: the 1/|V·N| of eq. 1 cannot blow up.
//
// Channel probabilities. Any P_c > 0 for every channel that carries energy keeps the estimator
// unbiased (the weights above sum to 1 whatever they are). The paper picks channels uniformly;
// P_c ∝ E_m,c (energyChannelProbabilities: each channel's kept energy, its diffuse reflectance
// within R_m) makes the combined density on a plane with normal-only probes
// p(x) = Σ_c R_c(r)/Σ_c E_m,c, so every sample's channel sum Σ_c f_c/p is the constant
// Σ_c E_m,c there: the channels that carry the most light get the most probes, and no channel's
// term exceeds Σ_c E_m,c·sup(f_c/R_c) (p >= P_c·pdf_c).
//
// "Every hit" and pbrt-v3's first version. pbrt-v3 first kept one of the n hits of its probe,
// chosen uniformly, and returned the MIS density divided by that n, i.e. as if the probes along
// the other axes through the kept point also found n hits. They generally do not (near the
// edge of a box with slanted sides, the probe along N through a side-face point also crosses
// the bottom, the probe along T finds the side face alone), so that number is not the density
// of the kept point: that is Σ_{a,c} P_a P_c p_{a,c}(x) / n_{a,c}(x), each strategy with its
// own count. Used only as f/pdf, it is still unbiased: keeping one of n terms at random and
// multiplying by n estimates their sum without bias, so in expectation it is the every-hit
// estimator, with more variance; it is wrong wherever the value is used as a density (MIS
// against another technique, density-based weights). Counting every hit needs no count, and
// each hit carries its true density p(x). tests/sampling/disk_geometry_test.cpp measures both
// statements.
//
// Every axis in each sample (AxisScheme::All): Veach's multi-sample MIS (thesis ch. 9.2) with
// n_a probes along axis a, n = (2, 1, 1) for (N, T, B) (pbrt's 1/2, 1/4, 1/4 as counts), and
// his power heuristic. One draw of (c, r, φ) (c with P_c, r ~ channel c, φ = 2πu) gives the
// first N probe and the T and B probes, each through the point (r cos φ, r sin φ) of its own
// disk (axes e1 = V_{a+1}, e2 = V_{a+2}); the second N probe takes the draw of the uniforms
// shifted by 1/2 (mod 1), so it has another channel or radius and the opposite angle. Each
// probe on its own is distributed exactly as a one-sample probe with its axis fixed, so it finds
// x with density p_a(x) = Σ_c P_c p_{a,c}(x) (the channel MIS inside). With weights
// w_a(x) = (n_a p_a(x))² / Σ_b (n_b p_b(x))², which sum to 1 wherever some p_b > 0, the
// multi-sample estimator and its expectation are
//     F = Σ_a (1/n_a) Σ_{j <= n_a} Σ_{hits x of probe (a, j)} w_a(x) f(x)/p_a(x)
//       = Σ_probes Σ_hits f(x) · n_a p_a(x) / Σ_b (n_b p_b(x))²,
//     E[F] = Σ_a n_a (1/n_a) ∫ p_a w_a f/p_a dA = ∫_{p > 0} f(x) dA(x),
// with p(x) = Σ_a (n_a/n) p_a(x) the density a hit is reported with (pdf()). The probes of a
// sample share their uniforms, so they are correlated; that changes the variance, not the
// expectation (the expectation of a sum is the sum of each probe's own). Each term is at most
// f/max_b(n_b p_b) <= 3f/(n p), three times the balance heuristic's term f/(n p), so it stays
// bounded wherever f/p is (see the bound above).
// Why this scheme (bench sampling, README): on the sphere the N probes estimate the
// neighbourhood of P best, and the power heuristic gives the T and B probes the regions only
// they find well (the bands around their tangent great circles, the faces near an edge)
// instead of a share everywhere; the radius inversion is done twice for four probes.
#pragma once

#include "sampling/channel_pdf_table.h"
#include "sampling/frame.h"
#include "sampling/radial.h"
#include "sampling/surface.h"

#include <glm/vec3.hpp>

#include <array>
#include <optional>
#include <utility>
#include <vector>

namespace sampling {

// One axis per sample (Uniform, Pbrt, NormalOnly) or every axis in each sample (All).
enum class AxisScheme { Uniform, Pbrt, NormalOnly, All };
// Names of the schemes (settings, command line).
constexpr auto enumNames(AxisScheme) {
    return std::array{
        std::pair{AxisScheme::Uniform, "uniform"}, std::pair{AxisScheme::Pbrt, "pbrt"},
        std::pair{AxisScheme::NormalOnly, "normal"}, std::pair{AxisScheme::All, "all"}};
}
// P_a for a = N, T, B (All: n_a/n, its share of the probes, 1/2, 1/4, 1/4).
std::array<double, 3> axisProbabilities(AxisScheme s);
// P_c ∝ E_m,c (keptEnergy) of each channel that is not nullptr (0 for nullptr), normalised;
// the uniform 1/3 each when no channel has finite energy > 0.
std::array<double, 3>
energyChannelProbabilities(const std::array<const RadialDistribution*, 3>& channels);
const char* axisSchemeName(AxisScheme s);

// One probe segment: org + t·dir, t in [0, length], dir = V_axis.
struct Probe {
    int axis = 0, channel = 0;
    double radius = 0;   // r on the disk
    glm::dvec3 org{0.0}; // disk point − half·dir
    glm::dvec3 dir{0, 0, 1};
    double length = 0; // 2·√(R_m,c² − r²)
};

class DiskSampler {
  public:
    // One distribution per channel (not owned; they may be the same object). Probabilities
    // must be finite and >= 0 with a positive sum (they are normalised); a channel of
    // probability 0 may be nullptr. Throws core::Error("disk sampler", 0, …) otherwise.
    DiskSampler(std::array<const RadialDistribution*, 3> channels,
                std::array<double, 3> axisProbabilities,
                std::array<double, 3> channelProbabilities = {1.0 / 3, 1.0 / 3, 1.0 / 3});
    // The scheme's axes (All: every axis per sample, probes()) and the given channels'.
    DiskSampler(std::array<const RadialDistribution*, 3> channels, AxisScheme scheme,
                std::array<double, 3> channelProbabilities = {1.0 / 3, 1.0 / 3, 1.0 / 3});

    // The probe of axis uAxis, channel uChannel, radius uRadius, angle uAngle (each in [0, 1)).
    Probe probe(const Frame& f, double uAxis, double uChannel, double uRadius, double uAngle) const;
    // The same distribution from two uniforms: uStrategy picks the strategy (a, c) with
    // probability P_a·P_c (the nine in the order N, T, B × channel 0, 1, 2) and, rescaled to
    // [0, 1) within that strategy's interval, the radius. A stratified uStrategy (stratified.h)
    // thus stratifies the strategies' counts and each strategy's radii at once.
    Probe probe(const Frame& f, double uStrategy, double uAngle) const;
    // The probes of one sample, written to out[0 … n−1], n = probesPerSample(): the one probe
    // of probe(f, uStrategy, uAngle), or with AxisScheme::All the N, T, B probes of the draw
    // (uStrategy, uAngle) and the N probe of the draw shifted by 1/2 (see "Every axis in each
    // sample" above; uStrategy picks the channel with P_c and, rescaled, the radius).
    int probes(const Frame& f, double uStrategy, double uAngle, std::array<Probe, 4>& out) const;
    int probesPerSample() const { return m_everyAxis ? 4 : 1; }
    // What a hit x of probe `p` of one sample adds to the estimator, per unit f(x):
    // 1/p(x) with one axis per sample (balance heuristic), n_a p_a(x)/Σ_b (n_b p_b(x))² with
    // every axis (power heuristic); 0 where p(x) = 0.
    double weightOverPdf(const Frame& f, const Probe& p, const glm::dvec3& x,
                         const glm::dvec3& nx) const;
    // With every axis in each sample: the power-heuristic weights w_a(x), a = N, T, B (summing
    // to 1; all 0 where p(x) = 0).
    std::array<double, 3> multiSampleWeights(const Frame& f, const glm::dvec3& x,
                                             const glm::dvec3& nx) const;
    // p_{a,c}(x) without the selection probabilities (see above).
    double strategyPdf(const Frame& f, int axis, int channel, const glm::dvec3& x,
                       const glm::dvec3& nx) const;
    // p_a(x) = Σ_c P_c p_{a,c}(x) for a = N, T, B: the density of a probe along axis a (0 for
    // an axis of probability 0).
    std::array<double, 3> axisPdfs(const Frame& f, const glm::dvec3& x, const glm::dvec3& nx) const;
    // The combined area density p(x) = Σ_a P_a p_a(x). With tabulated channels on shared radii
    // (channel_pdf_table.h) the three channels of an axis come from one lookup; the value is
    // the sum of the strategies' densities up to rounding.
    double pdf(const Frame& f, const glm::dvec3& x, const glm::dvec3& nx) const;
    // w_{a,c}(x) of the one-sample balance heuristic, [axis][channel]; all 0 where p(x) = 0.
    std::array<std::array<double, 3>, 3> misWeights(const Frame& f, const glm::dvec3& x,
                                                    const glm::dvec3& nx) const;
    // max_c R_m,c over channels of probability > 0: the integration domain's radius.
    double radiusMax() const { return m_radiusMax; }
    double axisProbability(int a) const { return m_axisP[a]; }
    double channelProbability(int c) const { return m_chanP[c]; }
    const RadialDistribution* channel(int c) const { return m_channels[c]; }

    // The hits of one probe that the estimator uses: every hit with |x − P| <= R_m,c (the test
    // of the density's indicator, in the same arithmetic), appended to `out`.
    void probeHits(const Surface& s, const Frame& f, const Probe& p,
                   std::vector<SurfaceHit>& out) const;

  private:
    Probe diskProbe(const Frame& f, int axis, int channel, double radius, double uAngle) const;

    std::array<const RadialDistribution*, 3> m_channels;
    std::array<double, 3> m_axisP{}, m_chanP{};
    std::array<double, 3> m_rm2{}; // R_m,c², 0 for unused channels
    double m_radiusMax = 0;
    bool m_everyAxis = false;               // AxisScheme::All
    std::array<double, 3> m_axisN{1, 1, 1}; // n_a of AxisScheme::All
    std::optional<ChannelPdfTable> m_joint; // the used channels' pdfs in one table, if tables
};

// One sample of the disk estimator F = Σ_{probes} Σ_{hits x} f(x, N_x)·weightOverPdf (see
// above) at the frame's point: four uniforms from rng.uniform() (one axis per sample: axis,
// channel, radius, angle; every axis: the first and last), `scratch` reused between calls (no
// allocation once it has grown). f(const glm::dvec3& x, const glm::dvec3& nx) -> glm::dvec3.
template <class Rng, class F>
glm::dvec3 estimateDisk(const DiskSampler& ds, const Surface& s, const Frame& f, Rng& rng,
                        F&& integrand, std::vector<SurfaceHit>& scratch) {
    const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform(), u3 = rng.uniform();
    std::array<Probe, 4> probes;
    int n = 1;
    if (ds.probesPerSample() == 1)
        probes[0] = ds.probe(f, u0, u1, u2, u3);
    else
        n = ds.probes(f, u0, u3, probes);
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i) {
        scratch.clear();
        ds.probeHits(s, f, probes[size_t(i)], scratch);
        for (const SurfaceHit& h : scratch) {
            const double k = ds.weightOverPdf(f, probes[size_t(i)], h.point.x, h.point.n);
            if (k > 0) sum += integrand(h.point.x, h.point.n) * k;
        }
    }
    return sum;
}

template <class Rng, class F>
glm::dvec3 estimateDisk(const DiskSampler& ds, const Surface& s, const Frame& f, Rng& rng,
                        F&& integrand) {
    std::vector<SurfaceHit> scratch;
    return estimateDisk(ds, s, f, rng, integrand, scratch);
}

// One sample of uniform area sampling, area·f(x, N_x) with x uniform on the shape (three
// uniforms from rng.uniform()).
template <class Rng, class F>
glm::dvec3 estimateUniformArea(const AreaSampler& a, Rng& rng, F&& integrand) {
    const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    const SurfacePoint p = a.sampleArea(u0, u1, u2);
    return a.area() * integrand(p.x, p.n);
}

} // namespace sampling
