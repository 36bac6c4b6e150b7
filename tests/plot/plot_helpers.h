// Shared helpers for the plot tests: an axis and a series from their values.
#pragma once

#include "plot/plot.h"

#include <string>
#include <utility>
#include <vector>

namespace plot_test {

inline plot::Axis axis(double lo, double hi, plot::Scale s, std::string label = "") {
    plot::Axis a;
    a.lo = lo;
    a.hi = hi;
    a.scale = s;
    a.label = std::move(label);
    return a;
}

inline plot::Series series(std::vector<double> x, std::vector<double> y) {
    plot::Series s;
    s.x = std::move(x);
    s.y = std::move(y);
    return s;
}

} // namespace plot_test
