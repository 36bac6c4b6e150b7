// A model's analytic radial sampler (`::begin sample`: SampleRadius, PdfRadius, MaxRadius;
// materials/README.md), evaluated on the GPU on dense grids, checked, and turned into the CPU
// distribution sampling::InverseCdfRadial (detail/model_samplers.h). Per channel c, with
// R = MaxRadius(c):
//   - R finite and > 0;
//   - PdfRadius(r, c) (the density of the RADIUS, ∫0^R PdfRadius dr = 1) on kPdfPoints + 1 radii
//     r_i = R (i/kPdfPoints)² (dense near 0, where profiles vary most), finite and >= 0, and
//     ∫0^R PdfRadius dr = 1 within kNormTolerance by the trapezoid rule on those radii (for a
//     smooth pdf the rule is accurate to ~1e-8 there: the tolerance is the float evaluation's
//     and the author's, not the quadrature's);
//   - SampleRadius(ξ, c) at ξ_j = j/kSampleKnots, j = 0 … kSampleKnots (ξ = 1 included: it is
//     the largest radius), finite, >= 0 and <= R (1 + kBeyondTolerance, float rounding);
//   - the inverse: |CDF(SampleRadius(ξ_j)) − ξ_j| <= kInverseTolerance at every knot, CDF the
//     integral of the piecewise-linear PdfRadius above (normalised by its trapezoid sum);
//   - agreement with the tabulated profile (profile_agreement.cpp): PdfRadius(r)/(2πr) against
//     R(r)/E_c on the radii above.
// The first failure is a core::Error(model path, line of `::begin sample`, "channel X: …").
// The CPU distribution is SampleRadius on the ξ knots (sample, pdf and cdf exactly consistent,
// inverse_cdf_radial.h), cut at R; the check above ties it to PdfRadius.
#include "integrate/detail/model_samplers.h"

#include "core/core.h"
#include "core/text.h"
#include "sampling/inverse_cdf_radial.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace integrate::detail {

namespace {
constexpr int kPdfPoints = 16384;
constexpr int kSampleKnots = 65536;
constexpr double kNormTolerance = 1e-3;
constexpr double kInverseTolerance = 1e-3;
constexpr double kBeyondTolerance = 1e-5;

// ∫0^r of the piecewise-linear pdf p on the radii `x` with cumulative sums `cum`.
double cdfAt(const std::vector<double>& x, const std::vector<double>& p,
             const std::vector<double>& cum, double r) {
    if (!(r > 0)) return 0;
    if (r >= x.back()) return cum.back();
    const size_t last = x.size() - 2;
    size_t k = std::min(last, size_t(std::sqrt(r / x.back()) * double(x.size() - 1)));
    while (k > 0 && r < x[k])
        --k;
    while (k < last && r >= x[k + 1])
        ++k;
    const double t = r - x[k], h = x[k + 1] - x[k];
    const double pt = h > 0 ? p[k] + (p[k + 1] - p[k]) * (t / h) : p[k];
    return cum[k] + 0.5 * t * (p[k] + pt);
}

// The checks of one channel; returns the CPU distribution.
std::unique_ptr<sampling::RadialDistribution>
checkChannel(int c, double rMax, const std::vector<double>& r, const std::vector<double>& pdf,
             std::vector<double> samples, const sampling::TabulatedRadial& table, double energyLoss,
             const bssrdf::Model& m) {
    auto error = [&](const std::string& msg) {
        return core::Error(m.path, m.sample->beginLine, channelLabel(c) + msg);
    };
    if (!(std::isfinite(rMax) && rMax > 0))
        throw error("MaxRadius must be finite and > 0 (it returns " + core::formatNumber(rMax, 6) +
                    ")");
    for (size_t i = 0; i < pdf.size(); ++i) {
        const std::string at = " at r = " + core::formatNumber(r[i], 6) + " mm";
        if (std::isnan(pdf[i])) throw error("PdfRadius is NaN" + at);
        if (std::isinf(pdf[i])) throw error("PdfRadius is infinite" + at);
        if (pdf[i] < 0)
            throw error("PdfRadius is negative (" + core::formatNumber(pdf[i], 6) + ")" + at);
    }
    std::vector<double> cum(r.size(), 0.0);
    for (size_t i = 0; i + 1 < r.size(); ++i)
        cum[i + 1] = cum[i] + 0.5 * (r[i + 1] - r[i]) * (pdf[i] + pdf[i + 1]);
    const double integral = cum.back();
    if (!(std::abs(integral - 1) <= kNormTolerance))
        throw error(
            "PdfRadius is the density of the radius, so its integral over [0, MaxRadius = " +
            core::formatNumber(rMax, 6) + " mm] must be 1 (within " +
            core::formatNumber(kNormTolerance, 6) + "); it is " + core::formatNumber(integral, 6));
    for (size_t j = 0; j < samples.size(); ++j) {
        const double xi = double(j) / double(samples.size() - 1), s = samples[j];
        const std::string at = " at xi = " + core::formatNumber(xi, 6);
        if (std::isnan(s)) throw error("SampleRadius is NaN" + at);
        if (std::isinf(s)) throw error("SampleRadius is infinite" + at);
        if (s < 0)
            throw error("SampleRadius is negative (" + core::formatNumber(s, 6) + " mm)" + at);
        if (s > rMax * (1 + kBeyondTolerance))
            throw error("SampleRadius returns " + core::formatNumber(s, 6) + " mm" + at +
                        ", beyond MaxRadius = " + core::formatNumber(rMax, 6) + " mm");
        samples[j] = std::min(s, rMax);
    }
    double worst = -1;
    size_t worstAt = 0;
    for (size_t j = 0; j < samples.size(); ++j) {
        const double xi = double(j) / double(samples.size() - 1);
        const double d = std::abs(cdfAt(r, pdf, cum, samples[j]) / integral - xi);
        if (d > worst) {
            worst = d;
            worstAt = j;
        }
    }
    if (worst > kInverseTolerance) {
        const double xi = double(worstAt) / double(samples.size() - 1);
        throw error("SampleRadius is not the inverse of the CDF of PdfRadius: at xi = " +
                    core::formatNumber(xi, 6) + " it returns r = " +
                    core::formatNumber(samples[worstAt], 6) + " mm, where the CDF is " +
                    core::formatNumber(cdfAt(r, pdf, cum, samples[worstAt]) / integral, 6) +
                    " (tolerance " + core::formatNumber(kInverseTolerance, 6) + ")");
    }
    std::vector<double> area(r.size(), 0.0);
    for (size_t i = 0; i < r.size(); ++i)
        area[i] = r[i] > 0 ? pdf[i] / (2 * std::numbers::pi * r[i]) : 0.0;
    if (std::string p = agreementProblem(table, rMax, r, area, energyLoss); !p.empty())
        throw error("the sampler does not describe the model's profile: " + p);
    try {
        return std::make_unique<sampling::InverseCdfRadial>(samples, rMax, table, c, m.path);
    } catch (const core::Error& e) { // e.g. every radius the same
        throw error("SampleRadius: " + e.message());
    }
}
} // namespace

Distributions analyticDistributions(GLuint pencilProgram, const bssrdf::Model& m,
                                    const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                                    const std::array<sampling::TabulatedRadial, 3>& table,
                                    double energyLoss) {
    using bssrdf::SamplerFunction;
    std::vector<bssrdf::SamplerQuery> q;
    for (int c = 0; c < 3; ++c)
        q.push_back({SamplerFunction::MaxRadius, 0.0, c});
    const std::vector<double> rMax = bssrdf::evaluateSampler(pencilProgram, m, values, b, q);
    q.clear();
    std::array<std::vector<double>, 3> radii;
    for (int c = 0; c < 3; ++c) {
        const double rm = std::isfinite(rMax[size_t(c)]) ? rMax[size_t(c)] : 0.0;
        for (int i = 0; i <= kPdfPoints; ++i) {
            const double f = double(i) / kPdfPoints;
            radii[size_t(c)].push_back(double(float(rm * f * f))); // as the GPU sees it
            q.push_back({SamplerFunction::PdfRadius, radii[size_t(c)].back(), c});
        }
        for (int j = 0; j <= kSampleKnots; ++j)
            q.push_back({SamplerFunction::SampleRadius, double(j) / kSampleKnots, c});
    }
    const std::vector<double> v = bssrdf::evaluateSampler(pencilProgram, m, values, b, q);
    Distributions out;
    const size_t perChannel = size_t(kPdfPoints + 1) + size_t(kSampleKnots + 1);
    for (int c = 0; c < 3; ++c) {
        const auto first = v.begin() + std::ptrdiff_t(size_t(c) * perChannel);
        const std::vector<double> pdf(first, first + kPdfPoints + 1);
        std::vector<double> samples(first + kPdfPoints + 1, first + std::ptrdiff_t(perChannel));
        out[size_t(c)] = checkChannel(c, rMax[size_t(c)], radii[size_t(c)], pdf, std::move(samples),
                                      table[size_t(c)], energyLoss, m);
    }
    return out;
}

} // namespace integrate::detail
