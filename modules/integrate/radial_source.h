// integrate/radial_source: where a model's radial sampling distributions come from (King et
// al. 2013's pdf_disk per colour channel). Today: the model's own profile R(r) = Bssrdf(0, n,
// (r, 0, 0), n), tabulated on the GPU (render::buildProfileTable without a cap: the table runs
// until R has decayed by kProfileDecay), each channel a sampling::TabulatedRadial cut at R_m
// keeping all but `energyLoss` of its energy. A profile that cannot be sampled (NaN, negative,
// no energy, energy that does not converge within the table) is a core::Error naming `name`,
// the channel and the radius.
#pragma once

#include "bssrdf/program.h"
#include "sampling/radial.h"

#include <array>
#include <memory>
#include <string>

namespace integrate {

struct RadialSource {
    std::array<std::unique_ptr<sampling::RadialDistribution>, 3> channel;
    std::string kind; // how they were made, for messages and the Timings panel ("profile table")
    std::array<const sampling::RadialDistribution*, 3> pointers() const {
        return {channel[0].get(), channel[1].get(), channel[2].get()};
    }
};

// `pencilProgram` from bssrdf::buildModelProgram(m, "pencil_profile.comp").
RadialSource radialSource(GLuint pencilProgram, const bssrdf::Model& m,
                          const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                          double energyLoss, const std::string& name);

} // namespace integrate
