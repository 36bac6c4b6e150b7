// pathtrace/run_slab: multi-threaded slab runs with results independent of the thread count
//   (worker pool, ring and in-order merge: detail/chunk_runner).
//   Paths are cut into chunks of kChunkPaths (independent of the thread count). Worker
//   threads (std::thread) take chunks in increasing order from an atomic counter and trace each
//   into a ring slot of per-path records; the calling thread adds the records into the tally
//   path by path, in chunk order, so every sum is formed in exactly the order of a
//   single-threaded traceSlab(m, s, 0, paths): bitwise identical for any thread count. The ring
//   (2 slots per worker) bounds memory; a worker waits for its slot to be merged. The calling
//   thread polls every 50 ms: it merges, reports progress and watches `cancel`; on cancel the
//   workers stop (checked every 256 paths) and the result keeps the completed prefix of chunks.
#include "core/core.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/detail/chunk_runner.h"
#include "pathtrace/detail/slab_chunk.h"
#include "pathtrace/detail/slab_connections.h"
#include "pathtrace/pathtrace.h"

#include <algorithm>
#include <vector>

namespace pathtrace {

SlabResult runSlab(const Medium& m, const SlabSettings& s,
                   const std::function<void(uint64_t done)>& progress,
                   const std::atomic<bool>* cancel) {
    validate(m);
    validate(s);
    core::Stopwatch clock;
    if (s.estimator == Estimator::Connections) {
        const EstimateSettings e = detail::connectionSettings(s);
        SlabResult r = finalize(
            detail::slabTallyOf(estimateChunks(m, e, 0, 0, chunkCount(e), progress, cancel), m), s);
        r.seconds = clock.ms() / 1000.0;
        return r;
    }
    SlabTally t = makeTally(s);
    std::vector<std::vector<PathRecord>> ring; // per ring slot: the records of one chunk
    const detail::ChunkCallbacks callbacks{
        .allocate =
            [&](size_t slots) {
                ring.assign(slots, std::vector<PathRecord>(static_cast<size_t>(
                                       std::min<uint64_t>(kChunkPaths, s.paths))));
            },
        .trace =
            [&](size_t slot, uint64_t first, uint64_t count, const std::atomic<bool>* abort) {
                return detail::traceChunk(m, s, first, count, ring[slot].data(), abort);
            },
        .merge =
            [&](size_t slot, uint64_t count) {
                for (uint64_t i = 0; i < count; ++i)
                    accumulate(t, ring[slot][i], s);
            },
    };
    detail::runChunks(s.paths, kChunkPaths, s.threads, callbacks, progress, cancel);
    if (progress) progress(t.paths);
    SlabResult r = finalize(t, s);
    r.seconds = clock.ms() / 1000.0;
    return r;
}

} // namespace pathtrace
