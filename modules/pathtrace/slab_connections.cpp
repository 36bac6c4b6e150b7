// pathtrace/slab_connections: the CPU slab reference (tracePath, traceSlab, runSlab) for every
// estimator, run through the oblique-incidence walk of bssrdf_walk.cpp at θi = 0 with one θs bin
// and one direction cell — thesis Algorithm 1 with the MCML entry convention, R_d(r) on the
// slab's uniform radial bins; connections add the seed-001 estimator (derivation in
// bssrdf_walk.cpp). One walk serves every CPU slab figure, so they cannot drift apart. The result
// is returned as a SlabTally so every consumer of the slab reference (CLI, GUI, tests) reads it
// unchanged, and a sharded `slab` run writes the same table `estimate` does. Paths are grouped in
// the aligned chunks [k·kChunkPaths, (k+1)·kChunkPaths), summed per chunk and added exactly
// (detail/exact_sum.h), so runSlab and traceSlab(0, paths) agree bitwise for any thread count, as
// for the other estimators.
#include "pathtrace/detail/slab_connections.h"

#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/detail/bssrdf_chunk.h"
#include "pathtrace/fresnel.h"

#include <algorithm>

namespace pathtrace::detail {

EstimateSettings estimateSettingsOf(const SlabSettings& s) {
    EstimateSettings e;
    e.thetaIDeg = {0.0};
    e.bins.rBins = s.bins;
    e.bins.rMaxMm = s.rMaxMm;
    e.bins.spacing = RadialSpacing::Uniform;
    e.bins.thetaSBins = 1;
    e.bins.dirCosBins = 1;
    e.bins.dirPhiBins = 1;
    e.paths = s.paths;
    e.seed = s.seed;
    e.threads = s.threads;
    e.termination = s.termination;
    e.splitting = s.splitting;
    e.exits = s.exits;
    e.estimator = s.estimator == Estimator::Analog     ? BssrdfEstimator::Analog
                  : s.estimator == Estimator::Implicit ? BssrdfEstimator::Implicit
                                                       : BssrdfEstimator::Connections;
    return e;
}

SlabTally slabTallyOf(const BssrdfTally& b, const Medium& m) {
    SlabTally t;
    t.paths = b.paths;
    for (size_t i = 0; i < b.binSum.size(); ++i) {
        t.binSum.push_back(b.binSum[i].value());
        t.binSumSq.push_back(b.binSumSq[i].value());
    }
    for (const detail::ExactSum& x : b.batchSum)
        t.batchSum.push_back(x.value());
    t.batchPaths = b.batchPaths;
    t.rdSum = b.exitSum.value();
    t.rdSumSq = b.exitSumSq.value();
    t.absSum = b.absSum.value();
    t.absSumSq = b.absSumSq.value();
    t.specular = fresnelDielectric(1.0, m.eta);
    t.rouletteSum = b.rouletteSum.value();
    t.rouletteSumSq = b.rouletteSumSq.value();
    t.truncSum = b.truncSum.value();
    t.truncSumSq = b.truncSumSq.value();
    t.truncatedPaths = b.truncatedPaths;
    t.events = uint64_t(b.events.value());
    t.gapSum = b.energySum.value();
    t.gapSumSq = b.energySumSq.value();
    return t;
}

PathRecord tracePathViaEstimate(const Medium& m, const SlabSettings& s, uint64_t pathIndex) {
    return traceBssrdfPath(m, estimateSettingsOf(s), 0, pathIndex);
}

SlabTally traceSlabViaEstimate(const Medium& m, const SlabSettings& s, uint64_t first,
                               uint64_t count, const std::atomic<bool>* cancel) {
    const EstimateSettings e = estimateSettingsOf(s);
    BssrdfTally total = makeTally(e.bins);
    ChunkTally chunk;
    for (uint64_t p = first, end = first + count; p < end;) {
        const uint64_t next = std::min(end, (p / kChunkPaths + 1) * kChunkPaths);
        const uint64_t got = traceBssrdfChunk(m, e, 0, p, next - p, chunk, cancel);
        if (got < next - p) break; // cancelled: keep the completed pieces
        chunk.addTo(total);
        p = next;
    }
    return slabTallyOf(total, m);
}

} // namespace pathtrace::detail

namespace pathtrace {

PathRecord tracePath(const Medium& m, const SlabSettings& s, uint64_t pathIndex) {
    validate(m);
    validate(s);
    return detail::tracePathViaEstimate(m, s, pathIndex);
}

SlabTally traceSlab(const Medium& m, const SlabSettings& s, uint64_t first, uint64_t count,
                    const std::atomic<bool>* cancel) {
    validate(m);
    validate(s);
    return detail::traceSlabViaEstimate(m, s, first, count, cancel);
}

} // namespace pathtrace
