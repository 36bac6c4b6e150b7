// pathtrace/detail/slab_connections: the CPU slab reference, every estimator, run through the
// oblique-incidence estimate (bssrdf_estimate.h) at θi = 0 (slab_connections.cpp).
#pragma once

#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/pathtrace.h"

#include <atomic>

namespace pathtrace::detail {
// The estimate settings equivalent to slab settings s (θi 0, one θs bin, one cell).
EstimateSettings estimateSettingsOf(const SlabSettings& s);
// A BssrdfTally of those settings as a slab tally (values rounded to doubles).
SlabTally slabTallyOf(const BssrdfTally& b, const Medium& m);
// tracePath (no validation).
PathRecord tracePathViaEstimate(const Medium& m, const SlabSettings& s, uint64_t pathIndex);
// traceSlab (no validation).
SlabTally traceSlabViaEstimate(const Medium& m, const SlabSettings& s, uint64_t first,
                               uint64_t count, const std::atomic<bool>* cancel);
} // namespace pathtrace::detail
