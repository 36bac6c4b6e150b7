// Shared by the lit-sphere tracer tests: a medium from its coefficients and the three media
// (one per channel) that the sphere and mesh tracer tests render.
#pragma once

#include "pathtrace/pathtrace.h"

#include <array>

namespace pathtrace_test {

inline pathtrace::Medium med(double sa, double ss, double g, double eta) {
    pathtrace::Medium m;
    m.sigmaA = sa;
    m.sigmaS = ss;
    m.g = g;
    m.eta = eta;
    return m;
}

inline const std::array<pathtrace::Medium, 3> kMedia = {
    med(0.05, 1.0, 0.0, 1.3), med(0.2, 2.0, 0.5, 1.3), med(0.5, 0.5, 0.0, 1.5)};

} // namespace pathtrace_test
