// pathtrace/camera_runner: multi-threaded image runs independent of the thread count (the
// scheme of run_slab.cpp, run by detail/chunk_runner). Paths are cut into chunks of
// kImageChunkPaths; worker threads take chunks in increasing order from an atomic counter and
// trace each into a ring slot of per-path records (2 slots per worker bound the memory; a
// worker waits for its slot to be merged); the calling thread adds the records into the tally
// path by path in chunk order, so every sum is formed in the same order for any thread count.
// The calling thread polls every 50 ms: it merges, reports progress and watches `cancel`; on
// cancel the workers stop and the tally keeps the completed prefix of chunks.
#include "pathtrace/camera.h"
#include "pathtrace/detail/chunk_runner.h"

#include <algorithm>
#include <vector>

namespace pathtrace {

ImageTally runImageChunks(uint64_t paths, int threads, size_t pixels, const ChunkTracer& trace,
                          const std::function<void(uint64_t done)>& progress,
                          const std::atomic<bool>* cancel) {
    ImageTally t(pixels);
    if (paths == 0) return t;
    // per ring slot: the records of one chunk, channel-major: records[c·count + i]
    std::vector<std::vector<ExitRecord>> ring;
    const detail::ChunkCallbacks callbacks{
        .allocate =
            [&](size_t slots) {
                ring.assign(slots, std::vector<ExitRecord>(static_cast<size_t>(
                                       kChannels * std::min<uint64_t>(kImageChunkPaths, paths))));
            },
        .trace =
            [&](size_t slot, uint64_t first, uint64_t count, const std::atomic<bool>* abort) {
                return trace(first, count, ring[slot].data(), abort);
            },
        .merge =
            [&](size_t slot, uint64_t count) {
                for (uint64_t i = 0; i < count; ++i)
                    t.add(ring[slot].data(), count, i);
            },
    };
    detail::runChunks(paths, kImageChunkPaths, threads, callbacks, progress, cancel);
    if (progress) progress(t.paths);
    return t;
}

} // namespace pathtrace
