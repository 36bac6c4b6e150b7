// integrate/radial_source: where a model's radial sampling distributions come from (King et
// al. 2013's pdf_disk per colour channel). The model's own profile R(r) = Bssrdf(0, n,
// (r, 0, 0), n) is always tabulated on the GPU (render::buildProfileTable without a cap: the
// table runs until R has decayed by kProfileDecay), each channel a sampling::TabulatedRadial cut
// at R_m keeping all but `energyLoss` of its energy; a profile that cannot be sampled (NaN,
// negative, no energy, energy that does not converge within the table) is a core::Error naming
// `name`, the channel and the radius. Then, the first that applies:
//   1. the model's `::begin sample` section (analytic_sampler.cpp): SampleRadius, PdfRadius and
//      MaxRadius evaluated on the GPU on dense grids, checked (normalised, the inverse, no NaN,
//      no negative pdf, no radius beyond MaxRadius, agreeing with the table) and used as
//      sampling::InverseCdfRadial, kind "analytic sampler";
//   2. the lobe interface QdLobeCount / QdLobe (lobe_sampler.cpp): per channel a
//      sampling::GaussianLobes of the lobes, checked against the table, kind "Gaussian lobes";
//   3. the table itself, kind "profile table".
// A failed check of 1 or 2 is a core::Error naming the model file (Model::path) and the line of
// the section or of the QdLobe definition.
#pragma once

#include "bssrdf/program.h"
#include "sampling/radial.h"

#include <array>
#include <memory>
#include <string>

namespace integrate {

struct RadialSource {
    std::array<std::unique_ptr<sampling::RadialDistribution>, 3> channel;
    // how they were made, for messages and the Timings panel: "analytic sampler", "Gaussian
    // lobes" or "profile table"
    std::string kind;
    std::array<const sampling::RadialDistribution*, 3> pointers() const {
        return {channel[0].get(), channel[1].get(), channel[2].get()};
    }
};

// `pencilProgram` from bssrdf::buildModelProgram(m, "pencil_profile.comp").
RadialSource radialSource(GLuint pencilProgram, const bssrdf::Model& m,
                          const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                          double energyLoss, const std::string& name);

} // namespace integrate
