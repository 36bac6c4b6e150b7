// pathtrace/run_slab: multi-threaded slab runs with results independent of the thread count.
//   The run is the oblique-incidence estimate at θi = 0 (detail/slab_connections.h): chunks of
//   kChunkPaths paths traced by the worker pool of detail/chunk_runner, each summed path by
//   path and added exactly (detail/exact_sum.h), so the result is bitwise that of
//   traceSlab(m, s, 0, paths) — and of a sharded run merged — for any thread count. The calling
//   thread polls every 50 ms: it merges, reports progress and watches `cancel`; on cancel the
//   result keeps the completed prefix of chunks.
#include "core/core.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/detail/slab_connections.h"
#include "pathtrace/pathtrace.h"

namespace pathtrace {

SlabResult runSlab(const Medium& m, const SlabSettings& s,
                   const std::function<void(uint64_t done)>& progress,
                   const std::atomic<bool>* cancel) {
    validate(m);
    validate(s);
    core::Stopwatch clock;
    const EstimateSettings e = detail::estimateSettingsOf(s);
    SlabResult r = finalize(
        detail::slabTallyOf(estimateChunks(m, e, 0, 0, chunkCount(e), progress, cancel), m), s);
    if (progress) progress(r.paths);
    r.seconds = clock.ms() / 1000.0;
    return r;
}

} // namespace pathtrace
