// pathtrace/tally: per-path sums and their finalisation into R_d(r) with standard errors.
//   Every figure X (weight left in a radial bin, total diffuse reflectance, absorbed weight,
//   roulette loss, truncated weight) is summed per path as ΣX and ΣX²; each path leaves through the
//   surface at most once, so it contributes to at most one bin. Estimates: mean X̄ = ΣX/N and
//   standard error sqrt((ΣX²/N − X̄²)/(N − 1)) (the unbiased sample variance of the mean). R_d(r) in
//   the MCML convention (Wang, Jacques & Zheng 1995, eq. 4.7): weight per annulus area π(r_{i+1}² −
//   r_i²) per incident photon, 1/mm².
#include "core/core.h"
#include "pathtrace/detail/energy_check.h"
#include "pathtrace/detail/mean_stderr.h"
#include "pathtrace/pathtrace.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numbers>
#include <string>

namespace pathtrace {

SlabTally makeTally(const SlabSettings& s) {
    SlabTally t;
    t.binSum.assign(static_cast<size_t>(s.bins), 0.0);
    t.binSumSq.assign(static_cast<size_t>(s.bins), 0.0);
    if (s.bins <= kMaxBatchedBins) t.batchSum.assign(kBatches * static_cast<size_t>(s.bins), 0.0);
    return t;
}

int binOf(double r, const SlabSettings& s) {
    if (!(r >= 0.0) || !(r < s.rMaxMm)) return -1;
    const int b = static_cast<int>(r * (s.bins / s.rMaxMm));
    return b < s.bins ? b : s.bins - 1; // r just below rMax rounding up
}

void accumulate(SlabTally& t, const PathRecord& p, const SlabSettings& s, uint64_t pathIndex) {
    ++t.paths;
    const size_t batch = detail::batchOf(pathIndex);
    ++t.batchPaths[batch];
    t.specular = p.specular;
    t.events += p.events;
    // As the walk sums a path: each bin's terms in order, then the bins in index order.
    std::map<int, double> perBin;
    double total = 0;
    for (const auto& e : p.exits)
        total += e.second;
    for (const auto& [r, w] : p.tallied) {
        const int b = binOf(r, s);
        if (b >= 0 && static_cast<size_t>(b) < t.binSum.size()) perBin[b] += w;
    }
    t.rdSum += total;
    t.rdSumSq += total * total;
    for (const auto& [b, w] : perBin) {
        t.binSum[static_cast<size_t>(b)] += w;
        t.binSumSq[static_cast<size_t>(b)] += w * w;
        if (!t.batchSum.empty()) t.batchSum[batch * t.binSum.size() + static_cast<size_t>(b)] += w;
    }
    t.absSum += p.absorbed;
    t.absSumSq += p.absorbed * p.absorbed;
    t.rouletteSum += p.rouletteLoss;
    t.rouletteSumSq += p.rouletteLoss * p.rouletteLoss;
    if (p.truncated != 0) {
        t.truncSum += p.truncated;
        t.truncSumSq += p.truncated * p.truncated;
        ++t.truncatedPaths;
    }
}

void SlabTally::merge(const SlabTally& o) {
    if (binSum.empty() && paths == 0) {
        binSum.assign(o.binSum.size(), 0.0);
        binSumSq.assign(o.binSumSq.size(), 0.0);
        batchSum.assign(o.batchSum.size(), 0.0);
    }
    if (binSum.size() != o.binSum.size() || binSumSq.size() != o.binSumSq.size())
        throw core::Error("slab tally", 0,
                          "cannot merge tallies with " + std::to_string(binSum.size()) + " and " +
                              std::to_string(o.binSum.size()) + " bins");
    if (o.paths == 0) return;
    if (paths == 0) specular = o.specular;
    paths += o.paths;
    for (size_t i = 0; i < binSum.size(); ++i) {
        binSum[i] += o.binSum[i];
        binSumSq[i] += o.binSumSq[i];
    }
    // batches only where both kept them (the GL tracer and older tables keep none)
    if (o.batchSum.size() != batchSum.size()) batchSum.clear();
    for (size_t i = 0; i < batchSum.size(); ++i)
        batchSum[i] += o.batchSum[i];
    for (size_t b = 0; b < kBatches; ++b)
        batchPaths[b] += o.batchPaths[b];
    rdSum += o.rdSum;
    rdSumSq += o.rdSumSq;
    absSum += o.absSum;
    absSumSq += o.absSumSq;
    rouletteSum += o.rouletteSum;
    rouletteSumSq += o.rouletteSumSq;
    truncSum += o.truncSum;
    truncSumSq += o.truncSumSq;
    truncatedPaths += o.truncatedPaths;
    events += o.events;
    gapSum += o.gapSum;
    gapSumSq += o.gapSumSq;
}

namespace {
// scale 1; fewer than 2 paths give an infinite standard error (detail/mean_stderr.h)
void meanStderr(double sum, double sumSq, uint64_t n, double& mean, double& err) {
    detail::meanStderr(sum, sumSq, n, 1.0, mean, err, false);
}
} // namespace

SlabResult finalize(const SlabTally& t, const SlabSettings& s) {
    if (t.binSum.size() != static_cast<size_t>(s.bins) || t.binSumSq.size() != t.binSum.size())
        throw core::Error("slab tally", 0,
                          "tally has " + std::to_string(t.binSum.size()) +
                              " bins but the settings ask for " + std::to_string(s.bins));
    SlabResult r;
    r.paths = t.paths;
    r.events = t.events;
    r.specular = t.specular;
    const size_t n = t.binSum.size();
    r.rMid.resize(n);
    r.rd.resize(n);
    r.rdStderr.resize(n);
    const double dr = s.rMaxMm / s.bins;
    auto annulusArea = [&](size_t i) { // π(r_{i+1}² − r_i²)
        const double r0 = dr * static_cast<double>(i), r1 = dr * static_cast<double>(i + 1);
        return std::numbers::pi * (r1 * r1 - r0 * r0);
    };
    for (size_t i = 0; i < n; ++i) {
        const double area = annulusArea(i);
        r.rMid[i] = 0.5 * (dr * static_cast<double>(i) + dr * static_cast<double>(i + 1));
        double mean, err;
        meanStderr(t.binSum[i], t.binSumSq[i], t.paths, mean, err);
        r.rd[i] = mean / area;
        r.rdStderr[i] = err / area;
    }
    r.rdBatches = detail::batchMeans(t.batchSum, t.batchPaths, n,
                                     [&](size_t i) { return 1.0 / annulusArea(i); });
    meanStderr(t.rdSum, t.rdSumSq, t.paths, r.totalRd, r.totalRdStderr);
    meanStderr(t.absSum, t.absSumSq, t.paths, r.absorbed, r.absorbedStderr);
    meanStderr(t.rouletteSum, t.rouletteSumSq, t.paths, r.rouletteNet, r.rouletteNetStderr);
    meanStderr(t.truncSum, t.truncSumSq, t.paths, r.truncated, r.truncatedStderr);
    r.truncatedPaths = t.truncatedPaths;
    if (t.gapSumSq > 0)
        meanStderr(t.gapSum, t.gapSumSq, t.paths, r.connectionGap, r.connectionGapStderr);
    return r;
}

std::string energyProblem(const SlabResult& r) {
    if (r.paths < 2) return {};
    if (r.connectionGapStderr > 0 &&
        std::fabs(r.connectionGap) > kEnergyZ * r.connectionGapStderr) {
        char b[240];
        std::snprintf(b, sizeof b,
                      "energy check failed: the connections' flux differs from the walk's exits "
                      "by %.3g +- %.2g per path (z = %.1f)",
                      r.connectionGap, r.connectionGapStderr,
                      r.connectionGap / r.connectionGapStderr);
        return b;
    }
    return detail::energyProblem({"specular + R_d + absorbed + truncated + roulette",
                                  r.specular + r.totalRd + r.absorbed + r.truncated + r.rouletteNet,
                                  1.0, r.rouletteNet, r.rouletteNetStderr, r.truncated,
                                  r.totalRdStderr, r.truncatedPaths, "R_d", ""});
}

} // namespace pathtrace
