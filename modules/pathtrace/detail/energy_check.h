// pathtrace/detail/energy_check: the one energy check behind energyProblem() of the slab
// result (pathtrace.h) and of an image channel (camera.h): the accounting identity, the mean
// roulette change against 0 (|z| ≤ kEnergyZ) and the truncated weight against the error bar
// of what the tracer reports.
#pragma once

#include "pathtrace/pathtrace.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

namespace pathtrace::detail {

struct EnergyTerms {
    const char* identity; // the terms summed, e.g. "specular + R_d + absorbed + ..."
    double sum, expected; // their sum and what it must equal
    double roulette, rouletteStderr;
    double truncated, errorBar; // truncated weight; standard error of the reported figure
    uint64_t truncatedPaths;
    const char* figure; // what the truncation lowers, e.g. "R_d"
    const char* unit;   // "" or " W"
};

inline std::string energyProblem(const EnergyTerms& t) {
    char b[360];
    if (!(std::fabs(t.sum - t.expected) <= 1e-6 * std::max(1.0, std::fabs(t.expected)))) {
        std::snprintf(b, sizeof b, "energy check failed: %s = %.9g%s, expected %.9g%s", t.identity,
                      t.sum, t.unit, t.expected, t.unit);
        return b;
    }
    if (t.rouletteStderr > 0 && std::fabs(t.roulette) > kEnergyZ * t.rouletteStderr) {
        std::snprintf(b, sizeof b,
                      "energy check failed: mean roulette change %.3g +- %.2g%s is not 0 (z = "
                      "%.1f): a roulette is biased, %s cannot be trusted",
                      t.roulette, t.rouletteStderr, t.unit, t.roulette / t.rouletteStderr,
                      t.figure);
        return b;
    }
    if (t.truncated > t.errorBar) {
        std::snprintf(b, sizeof b,
                      "%llu paths truncated at the event limit: %s may be low by up to %.3g%s "
                      "(their weight), more than its standard error %.2g%s; raise the event "
                      "limit",
                      static_cast<unsigned long long>(t.truncatedPaths), t.figure, t.truncated,
                      t.unit, t.errorBar, t.unit);
        return b;
    }
    return {};
}

} // namespace pathtrace::detail
