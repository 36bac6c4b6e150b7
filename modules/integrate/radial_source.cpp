// A model's radial sampling distributions (radial_source.h).
#include "integrate/radial_source.h"

#include "integrate/detail/model_samplers.h"
#include "render/profile_table.h"
#include "sampling/tabulated_radial.h"

namespace integrate {

RadialSource radialSource(GLuint pencilProgram, const bssrdf::Model& m,
                          const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                          double energyLoss, const std::string& name) {
    const render::ProfileTable t = render::buildProfileTable(pencilProgram, m, values, b, 0.0);
    const std::vector<double> radii = sampling::profileGridRadii(t.rMax, int(t.values.size()));
    std::vector<glm::dvec3> v(t.values.begin(), t.values.end());
    std::array<sampling::TabulatedRadial, 3> table =
        sampling::tabulateChannels(radii, v, energyLoss, name);
    RadialSource s;
    if (m.sample) {
        s.kind = "analytic sampler";
        s.channel = detail::analyticDistributions(pencilProgram, m, values, b, table, energyLoss);
    } else if (m.lobesLine > 0) {
        s.kind = "Gaussian lobes";
        s.channel = detail::lobeDistributions(pencilProgram, m, values, b, table, energyLoss);
    } else {
        s.kind = "profile table";
        for (int c = 0; c < 3; ++c)
            s.channel[size_t(c)] =
                std::make_unique<sampling::TabulatedRadial>(std::move(table[size_t(c)]));
    }
    return s;
}

} // namespace integrate
