// rel_err and its standard error (relative_error.h has the definitions).
#include "core/relative_error.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace core {

namespace {
RelativeError failed(std::string why, int bin) {
    RelativeError e;
    e.value = e.se = e.squared = std::numeric_limits<double>::quiet_NaN();
    e.problem = std::move(why);
    e.badBin = bin;
    return e;
}
} // namespace

RelativeError relativeError(const std::vector<ErrorBin>& bins,
                            const std::vector<double>& batchFraction) {
    double W = 0, sum = 0;
    for (size_t i = 0; i < bins.size(); ++i) {
        const ErrorBin& b = bins[i];
        if (!(b.weight > 0)) continue;
        if (!(std::isfinite(b.ref) && b.ref > 0 && std::isfinite(b.refSe)))
            return failed("the reference has no paths in a bin of the range", int(i));
        if (!std::isfinite(b.model))
            return failed("the model is not finite in a bin of the range", int(i));
        const double x = b.model / b.ref, c = b.refSe / b.ref;
        W += b.weight;
        sum += b.weight * ((x - 1) * (x - 1) - c * c * (3 * x * x - 2 * x));
    }
    if (!(W > 0)) return failed("no reference bins in the range", -1);
    // Var t_i = g²c² + 2q²c⁴ with g = −2x(x − 1) + c²(12x² − 6x), q = 3x² − 2x; (x − 1)² in g²
    // taken as t_i, its unbiased estimate (x̂ − 1)² would count the noise twice
    double var = 0, floor = 0;
    for (const ErrorBin& b : bins) {
        if (!(b.weight > 0)) continue;
        const double x = b.model / b.ref, c = b.refSe / b.ref, k = b.weight / W;
        const double c2 = c * c, t = (x - 1) * (x - 1) - c2 * (3 * x * x - 2 * x);
        const double h = 12 * x * x - 6 * x, q = 3 * x * x - 2 * x;
        const double g2 = 4 * x * x * t - 4 * x * (x - 1) * c2 * h + c2 * c2 * h * h;
        var += k * k * (g2 * c2 + 2 * q * q * c2 * c2);
        floor += k * k * 2 * q * q * c2 * c2;
    }
    const size_t B = batchFraction.size();
    bool batched = B >= 2;
    for (const ErrorBin& b : bins)
        batched = batched && (!(b.weight > 0) || b.batch.size() == B);
    if (batched) { // the linear part from the batches' spread: the bins' covariance counts
        std::vector<double> L(B, 0.0);
        double chi2 = 0;
        for (const ErrorBin& b : bins) {
            if (!(b.weight > 0)) continue;
            const double x = b.model / b.ref, c = b.refSe / b.ref, k = b.weight / W;
            const double c2 = c * c, q = 3 * x * x - 2 * x;
            // g with |x − 1| taken as √t, as in g² above (x̂ − 1 would count the noise twice)
            const double t = (x - 1) * (x - 1) - c2 * q;
            const double d = std::copysign(std::sqrt(std::max(t, 0.0)), x - 1);
            const double g = -2 * x * d + c2 * (12 * x * x - 6 * x);
            for (size_t j = 0; j < B; ++j)
                L[j] += k * g * (b.batch[j] - b.ref) / b.ref;
            chi2 += k * k * 2 * q * q * c2 * c2;
        }
        double mean = 0, spread = 0;
        for (size_t j = 0; j < B; ++j)
            mean += batchFraction[j] * L[j];
        for (size_t j = 0; j < B; ++j)
            spread += batchFraction[j] * (L[j] - mean) * (L[j] - mean);
        var = spread / double(B - 1) + chi2;
    }
    var = std::max(var, floor);
    const double e2 = sum / W, seE2 = std::sqrt(var);
    RelativeError e;
    e.squared = e2;
    e.value = std::sqrt(std::max(e2, 0.0));
    e.se = std::sqrt(e.value * e.value + seE2) - e.value;
    return e;
}

double logOverlap(double lo, double hi, double a, double b) {
    const double l = std::max(lo, a), h = std::min(hi, b);
    return l > 0 && h > l ? std::log(h / l) : 0.0;
}

BinNodes areaAverageNodes(double lo, double hi) {
    static constexpr double t[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                    0.8611363115940526};
    static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                    0.3478548451374538};
    BinNodes n;
    const double m = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
    const double area = 0.5 * (hi * hi - lo * lo); // ∫ r dr
    for (int k = 0; k < 4; ++k) {
        n.r[size_t(k)] = m + h * t[k];
        n.w[size_t(k)] = area > 0 ? w[k] * h * n.r[size_t(k)] / area : 0.25;
    }
    return n;
}

RelativeError radialRelativeError(const std::vector<double>& edges,
                                  const std::vector<RadialSeries>& series, double from, double to) {
    // Groups of bins [first, last] of one series: a bin without paths or noisier than
    // kRelErrMaxBinNoise joins the next (or, at the end of the range, the previous) into one bin
    // whose means are area-weighted, its variance summed with the squared area fractions.
    struct Group {
        size_t series, first, last;
        double area, refSum, varSum, modelSum;
        std::vector<double> batchSum; // Σ a·R^b per batch (when every series has batches)
    };
    const std::vector<double>& fraction =
        series.empty() ? std::vector<double>{} : series[0].batches.fraction;
    bool batched = !fraction.empty();
    for (const RadialSeries& s : series) {
        batched = batched && s.batches.fraction.size() == fraction.size() &&
                  s.batches.mean.size() == fraction.size();
        for (size_t b = 0; batched && b < s.batches.mean.size(); ++b)
            batched = s.batches.mean[b].size() == s.ref.size();
    }
    std::vector<Group> groups;
    auto areaOf = [&](size_t i) { return edges[i + 1] * edges[i + 1] - edges[i] * edges[i]; };
    for (size_t k = 0; k < series.size(); ++k) {
        const RadialSeries& s = series[k];
        const size_t n = s.ref.size();
        if (edges.size() != n + 1 || s.refSe.size() != n || s.model.size() != n)
            throw Error("rel_err", 0, "bin edges, reference and model differ in length");
        auto add = [&](Group& g, size_t i) {
            const double a = areaOf(i);
            g.last = i;
            g.area += a;
            g.refSum += s.ref[i] * a;
            g.varSum += s.refSe[i] * s.refSe[i] * a * a;
            g.modelSum += s.model[i] * a;
            if (!batched) return;
            g.batchSum.resize(fraction.size(), 0.0);
            for (size_t b = 0; b < fraction.size(); ++b)
                g.batchSum[b] += s.batches.mean[b][i] * a;
        };
        const size_t begin = groups.size();
        bool pending = false; // the last group is still too noisy
        for (size_t i = 0; i < n; ++i) {
            if (!(logOverlap(edges[i], edges[i + 1], from, to) > 0)) continue;
            if (!pending) groups.push_back(Group{k, i, i, 0, 0, 0, 0, {}});
            add(groups.back(), i);
            const Group& g = groups.back();
            pending = !(g.refSum > 0 && std::sqrt(g.varSum) <= kRelErrMaxBinNoise * g.refSum);
        }
        if (pending && groups.size() > begin + 1) { // the range ends in noisy bins
            const Group last = groups.back();
            groups.pop_back();
            for (size_t i = last.first; i <= last.last; ++i)
                add(groups.back(), i);
        }
    }
    std::vector<ErrorBin> bins;
    for (const Group& g : groups) {
        std::vector<double> batch = g.batchSum;
        for (double& x : batch)
            x /= g.area;
        bins.push_back(
            {series[g.series].weight * logOverlap(edges[g.first], edges[g.last + 1], from, to),
             g.modelSum / g.area, g.refSum / g.area, std::sqrt(g.varSum) / g.area,
             std::move(batch)});
    }
    RelativeError e = relativeError(bins, batched ? fraction : std::vector<double>{});
    if (e.badBin >= 0) {
        const Group& g = groups[size_t(e.badBin)];
        e.problem +=
            std::string(series.size() > 1 ? " (series " + std::to_string(g.series) + "," : " (") +
            "r = " + formatNumber(edges[g.first], 4) + " to " + formatNumber(edges[g.last + 1], 4) +
            " mm)";
    }
    return e;
}

RelativeError radialRelativeError(const std::vector<double>& edges, const std::vector<double>& ref,
                                  const std::vector<double>& refSe,
                                  const std::vector<double>& model, double from, double to,
                                  const BatchMeans& refBatches) {
    return radialRelativeError(edges, {RadialSeries{ref, refSe, model, 1.0, refBatches}}, from, to);
}

} // namespace core
