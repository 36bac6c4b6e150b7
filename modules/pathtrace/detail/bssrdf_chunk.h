// pathtrace/detail/bssrdf_chunk: the per-chunk tally of the oblique-incidence walk (sums in
// doubles formed path by path within one chunk, then added exactly into a BssrdfTally) and the
// one compiled copy of the walk (bssrdf_walk.cpp), by chunk or by single path.
#pragma once

#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/detail/mean_stderr.h"
#include "pathtrace/rng.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace pathtrace::detail {

// Connection roulette distance d₀ in mean free paths (connectVertex in bssrdf_walk.cpp; the GL
// walk gets it as a uniform).
inline constexpr double kRouletteMfp = 2.0;

// The seed of the path streams of incidence angle `angleIndex` (the CPU walk's PCG32 streams and
// the GL walk's Philox streams are both keyed by it and the path index).
inline uint64_t bssrdfStreamSeed(uint64_t seed, size_t angleIndex) {
    return angleIndex == 0 ? seed : splitmix64(seed ^ (0x9e3779b97f4a7c15ull * angleIndex));
}

// Sums of one chunk in doubles, formed path by path.
struct ChunkTally {
    uint64_t paths = 0;
    std::vector<double> binSum, binSumSq, dirSum, dirSumSq;
    std::vector<double> batchSum; // kBatches × spatial bins (empty beyond kMaxBatchedBins)
    std::array<uint64_t, kBatches> batchPaths{};
    double exitSum = 0, exitSumSq = 0, absSum = 0, absSumSq = 0, rouletteSum = 0, rouletteSumSq = 0,
           truncSum = 0, truncSumSq = 0, energySum = 0, energySumSq = 0, events = 0;
    uint64_t truncatedPaths = 0;

    // `batches`: keep the batch sums (a single path's record needs none)
    void reset(const BssrdfBins& b, bool batches = true) {
        *this = ChunkTally{};
        binSum.assign(size_t(b.spatialBins()), 0.0);
        binSumSq.assign(size_t(b.spatialBins()), 0.0);
        if (batches && b.spatialBins() <= kMaxBatchedBins)
            batchSum.assign(kBatches * size_t(b.spatialBins()), 0.0);
        if (b.dirBins() > 1) {
            dirSum.assign(size_t(b.spatialBins()) * size_t(b.dirBins()), 0.0);
            dirSumSq.assign(dirSum.size(), 0.0);
        }
    }
    void addTo(BssrdfTally& t) const {
        t.paths += paths;
        for (size_t i = 0; i < binSum.size(); ++i) {
            t.binSum[i].add(binSum[i]);
            t.binSumSq[i].add(binSumSq[i]);
        }
        for (size_t i = 0; i < dirSum.size(); ++i) {
            t.dirSum[i].add(dirSum[i]);
            t.dirSumSq[i].add(dirSumSq[i]);
        }
        for (size_t i = 0; i < batchSum.size() && i < t.batchSum.size(); ++i)
            t.batchSum[i].add(batchSum[i]);
        for (size_t b = 0; b < kBatches; ++b)
            t.batchPaths[b] += batchPaths[b];
        t.exitSum.add(exitSum);
        t.exitSumSq.add(exitSumSq);
        t.absSum.add(absSum);
        t.absSumSq.add(absSumSq);
        t.rouletteSum.add(rouletteSum);
        t.rouletteSumSq.add(rouletteSumSq);
        t.truncSum.add(truncSum);
        t.truncSumSq.add(truncSumSq);
        t.energySum.add(energySum);
        t.energySumSq.add(energySumSq);
        t.events.add(events);
        t.truncatedPaths += truncatedPaths;
    }
};

// Traces one path of angle `angleIndex` and returns its accounting (tracePath).
PathRecord traceBssrdfPath(const Medium& m, const EstimateSettings& s, size_t angleIndex,
                           uint64_t path);

// Traces paths [first, first + count) of angle `angleIndex` into `t` (reset first). Returns the
// paths traced: fewer than `count` only when `cancel` (checked every 64 paths) was set.
uint64_t traceBssrdfChunk(const Medium& m, const EstimateSettings& s, size_t angleIndex,
                          uint64_t first, uint64_t count, ChunkTally& t,
                          const std::atomic<bool>* cancel);

} // namespace pathtrace::detail
