// octree internals shared by build.cpp and attributes.cpp: the bottom-up node attributes of
// thesis 3.3.3 (Σ E·A, Σ A, irradiance-weighted mean, bounding box), accumulated in double.
#pragma once

#include "octree/octree.h"

#include <string>

namespace octree::detail {

// Recomputes every NodeRecord from t.points (irradiance, area, position) and t.descriptors,
// deepest level first (children have larger indices than their parent: breadth-first order).
void computeNodeAttributes(Octree& t);

[[noreturn]] void fail(const std::string& message); // throws core::Error("octree", 0, message)

} // namespace octree::detail
