// pathtrace/detail/slab_connections: the slab reference's Estimator::Connections, run through
// the oblique-incidence estimate (bssrdf_estimate.h) at θi = 0 (slab_connections.cpp).
#pragma once

#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/pathtrace.h"

#include <atomic>

namespace pathtrace::detail {
// The estimate settings equivalent to slab settings s (θi 0, one θs bin, one cell).
EstimateSettings connectionSettings(const SlabSettings& s);
// A BssrdfTally of those settings as a slab tally (values rounded to doubles).
SlabTally slabTallyOf(const BssrdfTally& b, const Medium& m);
// traceSlab for Estimator::Connections (no validation).
SlabTally traceSlabConnections(const Medium& m, const SlabSettings& s, uint64_t first,
                               uint64_t count, const std::atomic<bool>* cancel);
} // namespace pathtrace::detail
