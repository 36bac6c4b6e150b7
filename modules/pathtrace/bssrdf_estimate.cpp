// pathtrace/bssrdf_estimate: bin geometry, validation, the threaded chunk run and the
// finalisation of the oblique-incidence BSSRDF estimate (see bssrdf_estimate.h; the walk and
// the estimators are in bssrdf_walk.cpp).
#include "pathtrace/bssrdf_estimate.h"

#include "core/core.h"
#include "core/text.h"
#include "pathtrace/detail/bssrdf_chunk.h"
#include "pathtrace/detail/chunk_runner.h"
#include "pathtrace/detail/energy_check.h"
#include "pathtrace/detail/mean_stderr.h"
#include "pathtrace/fresnel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace pathtrace {
namespace {} // namespace

std::vector<double> BssrdfBins::rEdges() const {
    std::vector<double> e(size_t(rBins) + 1, rStartMm);
    if (spacing == RadialSpacing::Uniform || rBins == 1) {
        for (int i = 0; i <= rBins; ++i)
            e[size_t(i)] = rStartMm + (rMaxMm - rStartMm) * i / rBins;
    } else if (rStartMm > 0) { // geometric from rStart to rMax
        for (int i = 0; i <= rBins; ++i)
            e[size_t(i)] = rStartMm * std::pow(rMaxMm / rStartMm, double(i) / double(rBins));
    } else {
        const double r1 = rMinMm > 0 ? rMinMm : rMaxMm / 1000;
        // e_1 = r1, e_n = rMax, geometric in between.
        for (int i = 1; i <= rBins; ++i)
            e[size_t(i)] = r1 * std::pow(rMaxMm / r1, double(i - 1) / double(rBins - 1));
    }
    e.back() = rMaxMm;
    return e;
}

namespace {
double areaBetween(const std::vector<double>& e, int ir, int thetaSBins) {
    const double r0 = e[size_t(ir)], r1 = e[size_t(ir) + 1];
    return (r1 * r1 - r0 * r0) * (std::numbers::pi / thetaSBins);
}
} // namespace

double binArea(const BssrdfBins& b, int ir) {
    return areaBetween(b.rEdges(), ir, b.thetaSBins);
}

double cellProjectedSolidAngle(const BssrdfBins& b, int ic) {
    const int ring = ic / b.dirPhiBins;
    const double mu0 = double(ring) / b.dirCosBins, mu1 = double(ring + 1) / b.dirCosBins;
    return (2 * std::numbers::pi / b.dirPhiBins) * 0.5 * (mu1 * mu1 - mu0 * mu0);
}

int cellOf(const BssrdfBins& b, double cosThetaO, double phiO) {
    const int ring = std::clamp(int(cosThetaO * b.dirCosBins), 0, b.dirCosBins - 1);
    double phi = phiO < 0 ? phiO + 2 * std::numbers::pi : phiO;
    const int sector =
        std::clamp(int(phi / (2 * std::numbers::pi) * b.dirPhiBins), 0, b.dirPhiBins - 1);
    return ring * b.dirPhiBins + sector;
}

void validate(const EstimateSettings& s) {
    const std::string what = "estimate settings";
    auto fail = [&](const std::string& msg) { throw core::Error(what, 0, msg); };
    if (s.thetaIDeg.empty()) fail("theta_i: give at least one incidence angle");
    for (double t : s.thetaIDeg)
        if (!(std::isfinite(t) && t >= 0 && t < 90))
            fail("theta_i must lie in [0, 90) degrees, got " + core::formatNumber(t));
    const BssrdfBins& b = s.bins;
    auto count = [&](const char* name, int n, int max) {
        if (n < 1) fail(std::string(name) + " must be >= 1, got " + std::to_string(n));
        if (n > max)
            fail(std::string(name) + ": absurd bin count " + std::to_string(n) + " (> " +
                 std::to_string(max) + ")");
    };
    count("r_bins", b.rBins, 10000);
    count("theta_s_bins", b.thetaSBins, 10000);
    count("dir_cos_bins", b.dirCosBins, 1000);
    count("dir_phi_bins", b.dirPhiBins, 1000);
    const double cells = double(b.rBins) * b.thetaSBins * b.dirCosBins * b.dirPhiBins;
    if (cells > 4e6)
        fail("bins: " + core::formatNumber(cells) +
             " cells (r x theta_s x directions) is more than the 4e6 a table may hold");
    if (!(std::isfinite(b.rMaxMm) && b.rMaxMm > 0))
        fail("r_max must be a finite length > 0 mm, got " + core::formatNumber(b.rMaxMm));
    if (!(std::isfinite(b.rStartMm) && b.rStartMm >= 0 && b.rStartMm < b.rMaxMm))
        fail("r_start must lie in [0, r_max), got " + core::formatNumber(b.rStartMm));
    if (b.spacing == RadialSpacing::Log && b.rStartMm == 0 && b.rMinMm != 0 &&
        !(std::isfinite(b.rMinMm) && b.rMinMm > 0 && b.rMinMm < b.rMaxMm))
        fail("r_min must lie in (0, r_max) for log spacing, got " + core::formatNumber(b.rMinMm));
    if (s.paths == 0) fail("paths must be >= 1");
    if (s.paths > 10000000000000ull)
        fail("paths: absurd path count " + std::to_string(s.paths) + " (> 10^13)");
    if (s.threads < 0) fail("threads must be >= 0 (0: all hardware threads)");
    validate(s.termination, what);
    validate(s.splitting, what);
    validate(s.exits, what);
}

BssrdfTally makeTally(const BssrdfBins& b) {
    BssrdfTally t;
    t.binSum.resize(size_t(b.spatialBins()));
    t.binSumSq.resize(size_t(b.spatialBins()));
    if (b.spatialBins() <= kMaxBatchedBins) t.batchSum.resize(kBatches * size_t(b.spatialBins()));
    if (b.dirBins() > 1) {
        t.dirSum.resize(size_t(b.spatialBins()) * size_t(b.dirBins()));
        t.dirSumSq.resize(t.dirSum.size());
    }
    return t;
}

void BssrdfTally::merge(const BssrdfTally& o) {
    if (o.binSum.size() != binSum.size() || o.dirSum.size() != dirSum.size())
        throw core::Error("merge", 0, "tallies of different bins cannot be merged");
    paths += o.paths;
    for (size_t i = 0; i < binSum.size(); ++i) {
        binSum[i].add(o.binSum[i]);
        binSumSq[i].add(o.binSumSq[i]);
    }
    for (size_t i = 0; i < dirSum.size(); ++i) {
        dirSum[i].add(o.dirSum[i]);
        dirSumSq[i].add(o.dirSumSq[i]);
    }
    // batches only where both kept them (a table written before them has none)
    if (o.batchSum.size() != batchSum.size()) batchSum.clear();
    for (size_t i = 0; i < batchSum.size(); ++i)
        batchSum[i].add(o.batchSum[i]);
    for (size_t b = 0; b < kBatches; ++b)
        batchPaths[b] += o.batchPaths[b];
    for (auto [a, b] : {std::pair{&exitSum, &o.exitSum},
                        {&exitSumSq, &o.exitSumSq},
                        {&absSum, &o.absSum},
                        {&absSumSq, &o.absSumSq},
                        {&rouletteSum, &o.rouletteSum},
                        {&rouletteSumSq, &o.rouletteSumSq},
                        {&truncSum, &o.truncSum},
                        {&truncSumSq, &o.truncSumSq},
                        {&energySum, &o.energySum},
                        {&energySumSq, &o.energySumSq},
                        {&events, &o.events}})
        a->add(*b);
    truncatedPaths += o.truncatedPaths;
}

BssrdfSlice finalize(const BssrdfTally& t, const BssrdfBins& b, double thetaIDeg, const Medium& m) {
    BssrdfSlice r;
    r.thetaIDeg = thetaIDeg;
    r.specular =
        fresnelDielectric(std::max(std::cos(thetaIDeg * std::numbers::pi / 180), 1e-300), m.eta);
    r.paths = t.paths;
    const int nS = b.spatialBins(), nD = b.dirBins();
    const std::vector<double> edges = b.rEdges();
    r.R.resize(size_t(nS));
    r.RStderr.resize(size_t(nS));
    for (int i = 0; i < nS; ++i) {
        const double area = areaBetween(edges, i / b.thetaSBins, b.thetaSBins);
        detail::meanStderr(t.binSum[size_t(i)].value(), t.binSumSq[size_t(i)].value(), t.paths,
                           1.0 / area, r.R[size_t(i)], r.RStderr[size_t(i)], false);
    }
    std::vector<double> batchSums;
    for (const detail::ExactSum& x : t.batchSum)
        batchSums.push_back(x.value());
    r.RBatches = detail::batchMeans(batchSums, t.batchPaths, size_t(nS), [&](size_t i) {
        return 1.0 / areaBetween(edges, int(i) / b.thetaSBins, b.thetaSBins);
    });
    if (nD > 1) {
        r.S.resize(t.dirSum.size());
        r.SStderr.resize(t.dirSum.size());
        for (size_t k = 0; k < t.dirSum.size(); ++k) {
            const int bin = int(k / size_t(nD)), cell = int(k % size_t(nD));
            const double scale = 1.0 / (areaBetween(edges, bin / b.thetaSBins, b.thetaSBins) *
                                        cellProjectedSolidAngle(b, cell));
            detail::meanStderr(t.dirSum[k].value(), t.dirSumSq[k].value(), t.paths, scale, r.S[k],
                               r.SStderr[k], false);
        }
    }
    auto ms = [&](const detail::ExactSum& s, const detail::ExactSum& s2, double& mean,
                  double& err) {
        detail::meanStderr(s.value(), s2.value(), t.paths, 1.0, mean, err, false);
    };
    ms(t.exitSum, t.exitSumSq, r.totalRd, r.totalRdStderr);
    ms(t.absSum, t.absSumSq, r.absorbed, r.absorbedStderr);
    ms(t.rouletteSum, t.rouletteSumSq, r.rouletteNet, r.rouletteNetStderr);
    ms(t.truncSum, t.truncSumSq, r.truncated, r.truncatedStderr);
    ms(t.energySum, t.energySumSq, r.energyDiff, r.energyDiffStderr);
    r.truncatedPaths = t.truncatedPaths;
    r.eventsPerPath = t.paths ? t.events.value() / double(t.paths) : 0;
    return r;
}

std::string energyProblem(const BssrdfSlice& s, ScatterOrders orders) {
    if (s.paths < 2) return {};
    if (s.energyDiffStderr > 0 && std::fabs(s.energyDiff) > kEnergyZ * s.energyDiffStderr) {
        char b[240];
        std::snprintf(b, sizeof b,
                      "energy check failed: the connections' flux differs from the walk's exits "
                      "by %.3g +- %.2g per path (z = %.1f)",
                      s.energyDiff, s.energyDiffStderr, s.energyDiff / s.energyDiffStderr);
        return b;
    }
    if (orders != ScatterOrders::All) return {};
    return detail::energyProblem({"specular + R + absorbed + truncated + roulette",
                                  s.specular + s.totalRd + s.absorbed + s.truncated + s.rouletteNet,
                                  1.0, s.rouletteNet, s.rouletteNetStderr, s.truncated,
                                  s.totalRdStderr, s.truncatedPaths, "R", ""});
}

uint64_t chunkCount(const EstimateSettings& s) {
    return (s.paths + kChunkPaths - 1) / kChunkPaths;
}

std::pair<uint64_t, uint64_t> shardChunks(const EstimateSettings& s, uint64_t k, uint64_t n) {
    const uint64_t c = chunkCount(s);
    // floor(k·c/n) without overflow: c < 2^40 and n is small in practice, but use 128 bits.
    auto at = [&](uint64_t i) { return uint64_t((unsigned __int128)(c)*i / n); };
    return {at(k), at(k + 1)};
}

BssrdfTally estimateChunks(const Medium& m, const EstimateSettings& s, size_t angleIndex,
                           uint64_t firstChunk, uint64_t lastChunk,
                           const std::function<void(uint64_t)>& progress,
                           const std::atomic<bool>* cancel) {
    validate(m);
    validate(s);
    if (angleIndex >= s.thetaIDeg.size()) throw core::Error("estimate", 0, "no such angle");
    BssrdfTally t = makeTally(s.bins);
    lastChunk = std::min(lastChunk, chunkCount(s));
    if (firstChunk >= lastChunk) return t;
    const uint64_t firstPath = firstChunk * kChunkPaths;
    const uint64_t paths = std::min(s.paths, lastChunk * kChunkPaths) - firstPath;
    std::vector<detail::ChunkTally> ring;
    const detail::ChunkCallbacks callbacks{
        .allocate = [&](size_t slots) { ring.resize(slots); },
        .trace =
            [&](size_t slot, uint64_t first, uint64_t count, const std::atomic<bool>* abort) {
                return detail::traceBssrdfChunk(m, s, angleIndex, firstPath + first, count,
                                                ring[slot], abort);
            },
        .merge = [&](size_t slot, uint64_t) { ring[slot].addTo(t); },
    };
    detail::runChunks(paths, kChunkPaths, s.threads, callbacks, progress, cancel);
    return t;
}

} // namespace pathtrace
