// pathtrace/detail/slab_chunk: the one compiled copy of the slab path loop (thesis Algorithm 1
// with the estimator options of pathtrace.h) behind tracePath, the per-path record that the
// accounting tests read. Runs (traceSlab, runSlab) go through the oblique walk at θi = 0
// (bssrdf_walk.cpp), which draws the same random numbers and so traces the same paths.
#pragma once

#include "pathtrace/pathtrace.h"

#include <atomic>
#include <cstdint>

namespace pathtrace::detail {

// Traces paths [first, first + count) into out[0, count). Returns how many were traced: fewer
// than `count` only when `cancel` (checked every 256 paths; may be null) was set. No
// validation, no allocation, no exceptions.
uint64_t traceChunk(const Medium& m, const SlabSettings& s, uint64_t first, uint64_t count,
                    PathRecord* out, const std::atomic<bool>* cancel);

} // namespace pathtrace::detail
