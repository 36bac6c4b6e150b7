// core/limits: the values a described numeric setting accepts (core/fields.h). A settings
// description names them beside the member, v("count", s.count, "points", Limits{1, 1e7}),
// and every reader of the setting checks them: the JSON reader (captures, settings files), the
// CLI flags generated from the description, and the GUI widgets that ask core::limitsOf. This
// header holds only the type, so descriptions need not pull in the JSON machinery.
#pragma once

#include <limits>

namespace core {

// The closed range [lo, hi] a numeric member accepts (per component for a vector); ±infinity
// for no bound. Every floating-point member must also be finite, with or without limits.
struct Limits {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
};

} // namespace core
