// A model's radial sampling distributions (radial_source.h).
#include "integrate/radial_source.h"

#include "render/profile_table.h"
#include "sampling/tabulated_radial.h"

namespace integrate {

RadialSource radialSource(GLuint pencilProgram, const bssrdf::Model& m,
                          const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                          double energyLoss, const std::string& name) {
    const render::ProfileTable t = render::buildProfileTable(pencilProgram, m, values, b, 0.0);
    const std::vector<double> radii = sampling::profileGridRadii(t.rMax, int(t.values.size()));
    RadialSource s;
    s.kind = "profile table";
    for (int c = 0; c < 3; ++c) {
        std::vector<double> v(t.values.size());
        for (size_t k = 0; k < v.size(); ++k)
            v[k] = t.values[k][c];
        s.channel[size_t(c)] =
            std::make_unique<sampling::TabulatedRadial>(radii, std::move(v), energyLoss, c, name);
    }
    return s;
}

} // namespace integrate
