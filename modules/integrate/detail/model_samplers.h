// integrate/detail: the radial distributions a model file may define itself, checked against
// its tabulated profile (radial_source.h). Each throws core::Error(model path, line of the
// definition, "channel R|G|B: …") when a check fails; tolerances are stated in the .cpp files.
#pragma once

#include "bssrdf/program.h"
#include "sampling/radial.h"
#include "sampling/tabulated_radial.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace integrate::detail {

using Distributions = std::array<std::unique_ptr<sampling::RadialDistribution>, 3>;

// The `::begin sample` section (analytic_sampler.cpp).
Distributions analyticDistributions(GLuint pencilProgram, const bssrdf::Model& m,
                                    const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                                    const std::array<sampling::TabulatedRadial, 3>& table,
                                    double energyLoss);

// The lobe interface QdLobeCount / QdLobe (lobe_sampler.cpp).
Distributions lobeDistributions(GLuint pencilProgram, const bssrdf::Model& m,
                                const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                                const std::array<sampling::TabulatedRadial, 3>& table,
                                double energyLoss);

// Whether a candidate density pdf_area (values `pdfArea` at radii `r`, cut at `radiusMax`)
// describes the tabulated profile `table` (profile_agreement.cpp): "" or what differs.
std::string agreementProblem(const sampling::TabulatedRadial& table, double radiusMax,
                             const std::vector<double>& r, const std::vector<double>& pdfArea,
                             double energyLoss);

// "channel R: " … for messages.
inline std::string channelLabel(int c) {
    return std::string("channel ") + "RGB"[c] + ": ";
}

} // namespace integrate::detail
