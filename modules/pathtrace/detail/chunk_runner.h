// pathtrace/detail/chunk_runner: the chunked multi-threaded run shared by runSlab (run_slab.cpp)
// and runImageChunks (camera_runner.cpp), with results independent of the thread count.
//   Paths are cut into chunks of `chunkPaths`; worker threads (std::thread) take chunks in
//   increasing order from an atomic counter and trace each into a ring slot (2 slots per worker
//   bound the memory; a worker waits for its slot to be merged); the calling thread merges the
//   slots in chunk order, so every sum is formed in the same order for any thread count. The
//   calling thread polls every 50 ms: it merges, reports progress and watches `cancel`; on
//   cancel the workers stop and the result keeps the completed prefix of chunks.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace pathtrace::detail {

struct ChunkCallbacks {
    // Called once, before any worker starts, with the number of ring slots to provide.
    std::function<void(size_t slots)> allocate;
    // Traces paths [first, first + count) into ring slot `slot`; returns how many were traced
    // (fewer than `count` only when `abort` was set). Called on worker threads; an exception
    // counts as 0 paths traced.
    std::function<uint64_t(size_t slot, uint64_t first, uint64_t count,
                           const std::atomic<bool>* abort)>
        trace;
    // Merges the `count` paths of ring slot `slot` (on the calling thread, in chunk order).
    std::function<void(size_t slot, uint64_t count)> merge;
};

// Runs `paths` paths (> 0) in chunks of `chunkPaths` on `threads` workers (≤ 0: the hardware
// concurrency; never more than the chunks). `progress` (may be empty) gets the paths traced so
// far; `cancel` may be null.
void runChunks(uint64_t paths, uint64_t chunkPaths, int threads, const ChunkCallbacks& callbacks,
               const std::function<void(uint64_t done)>& progress, const std::atomic<bool>* cancel);

} // namespace pathtrace::detail
