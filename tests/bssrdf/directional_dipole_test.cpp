// materials/directional_dipole.bssrdf on the GPU against an independent double-precision
// evaluation of Frisvad, Hachisuka & Kjeldsen 2014 (eqs. 19–21) written here from the paper:
// several media, η, incidence angles and exit points; the normal-incidence form against the
// better dipole's structure; the model reads Wi (non-radial) and not Wo.
#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "bssrdf/program_library.h"
#include "model_reference.h"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

namespace {

using model_ref::fresnelInside;
using model_ref::moment;

constexpr double kPi = std::numbers::pi;
using V = std::array<double, 3>;
double dot(const V& a, const V& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

struct Medium {
    double sa, ss, g, eta;
};

// The paper's S'_d(x, w, d) and the model value pi (S'_r − S'_v) on the plane z = 0.
double directionalDipole(const Medium& m, const V& wi, const V& x) {
    const double c1 = moment(1, m.eta), c2 = moment(2, m.eta);
    const double cphi = (1 - 2 * c1) / 4, ce = (1 - 3 * c2) / 2, A = (1 - ce) / (2 * cphi);
    const double ssp = m.ss * (1 - m.g), stp = m.sa + ssp, alphap = ssp / stp;
    const double D = 1 / (3 * stp), str = std::sqrt(m.sa / D), de = 2.131 * D / std::sqrt(alphap);
    const V n{0, 0, 1};
    auto term = [&](const V& xs, const V& w, double d) {
        const double sd = str * d, xw = dot(xs, w);
        return std::exp(-sd) / (4 * kPi * kPi * d * d * d) *
               (cphi * (d * d / D + 3 * (1 + sd) * xw) -
                ce * (3 * D * (1 + sd) * dot(w, n) -
                      (1 + sd + 3 * D * (3 * (1 + sd) + sd * sd) / (d * d) * xw) * dot(xs, n)));
    };
    // Snell: w12 into the medium
    const double ci = dot(wi, n);
    const V t{wi[0] - ci * n[0], wi[1] - ci * n[1], wi[2] - ci * n[2]};
    const double st2 = dot(t, t) / (m.eta * m.eta);
    const double ct = std::sqrt(1 - st2);
    const V w12{-t[0] / m.eta, -t[1] / m.eta, -ct};
    const double r2 = dot(x, x), xw = dot(x, w12), mu0 = -w12[2];
    const double cosBeta = -std::sqrt((r2 - xw * xw) / (r2 + de * de));
    const double zr2 =
        mu0 > 0 ? D * mu0 * (D * mu0 - 2 * de * cosBeta) : 1 / std::pow(3 * (m.sa + m.ss), 2);
    const double dr = std::sqrt(r2 + zr2);
    const V xv{x[0], x[1], x[2] - 2 * A * de};
    const V wv{w12[0], w12[1], -w12[2]};
    const double v = kPi * (term(x, w12, dr) - term(xv, wv, std::sqrt(dot(xv, xv))));
    return std::max(v, 0.0);
}

} // namespace

TEST(DirectionalDipole, GpuMatchesAnIndependentDoubleEvaluation) {
    testsupport::context();
    bssrdf::ModelLibrary lib(testsupport::sourceRoot(), {"pencil_profile.comp"});
    lib.reload(testsupport::sourceRoot() / "materials" / "directional_dipole.bssrdf");
    bssrdf::ModelEntry* e = lib.find("materials/directional_dipole.bssrdf");
    ASSERT_NE(e, nullptr);
    ASSERT_FALSE(e->problem) << e->problem->text();
    EXPECT_FALSE(e->model->attrs.radial);
    EXPECT_FALSE(e->model->attrs.noWi);
    EXPECT_TRUE(e->model->attrs.noWo);
    // marble R, skin1 G (Jensen et al. 2001), and an anisotropic medium at η 1.5
    const std::array<Medium, 3> media{Medium{0.0021, 2.19, 0.0, 1.3}, Medium{0.032, 0.88, 0.0, 1.3},
                                      Medium{0.05, 5.0, 0.8, 1.5}};
    for (const Medium& m : media) {
        SCOPED_TRACE(m.sa);
        bssrdf::Builtins b;
        b.sigmaA = glm::vec3(float(m.sa));
        b.sigmaS = glm::vec3(float(m.ss));
        b.g = float(m.g);
        b.ior = float(m.eta);
        std::vector<bssrdf::Query> q;
        std::vector<double> expected;
        const double ld = 1 / std::sqrt(3 * m.sa * (m.sa + m.ss * (1 - m.g)));
        for (double ti : {0.0, 30.0, 60.0, 80.0})
            for (double r : {0.05, 0.3, 1.0, 2.0})
                for (double phi : {0.0, 90.0, 180.0, 225.0}) {
                    const double t = ti * kPi / 180, p = phi * kPi / 180;
                    const V wi{-std::sin(t), 0, std::cos(t)};
                    const V x{r * ld * std::cos(p), r * ld * std::sin(p), 0};
                    bssrdf::Query one;
                    one.wi = glm::vec3(float(wi[0]), float(wi[1]), float(wi[2]));
                    one.xo = glm::vec3(float(x[0]), float(x[1]), 0.0f);
                    q.push_back(one);
                    // the double reference at the float inputs the GPU sees
                    expected.push_back(directionalDipole(m, V{one.wi.x, one.wi.y, one.wi.z},
                                                         V{one.xo.x, one.xo.y, 0.0}));
                }
        const auto got = bssrdf::evaluateQueries(e->programs.at("pencil_profile.comp").id(),
                                                 *e->model, e->values, b, q);
        double peak = 0;
        for (double v : expected)
            peak = std::max(peak, v);
        for (size_t i = 0; i < q.size(); ++i) {
            // float: 1e-4 relative, or 1e-6 of the peak where the difference of the two
            // sources cancels (the value clamps to 0 beyond)
            EXPECT_NEAR(got[i][0], expected[i], 1e-4 * expected[i] + 1e-6 * peak)
                << "theta_i " << std::acos(q[i].wi.z) * 180 / kPi << " x " << q[i].xo.x << ","
                << q[i].xo.y;
        }
    }
}

TEST(DirectionalDipole, ForwardScatteringAtObliqueIncidenceAndSymmetryAtNormal) {
    const Medium m{0.01, 1.0, 0.0, 1.3};
    const double ld = 1 / std::sqrt(3 * m.sa * (m.sa + m.ss));
    const double t = 60 * kPi / 180;
    const V oblique{-std::sin(t), 0, std::cos(t)}, normal{0, 0, 1};
    // the beam travels toward +x: more light exits forward than backward at one l_d
    EXPECT_GT(directionalDipole(m, oblique, V{ld, 0, 0}),
              1.2 * directionalDipole(m, oblique, V{-ld, 0, 0}));
    // at normal incidence the profile is radial
    for (double phi : {0.0, 1.0, 2.5})
        EXPECT_NEAR(directionalDipole(m, normal, V{ld * std::cos(phi), ld * std::sin(phi), 0}),
                    directionalDipole(m, normal, V{ld, 0, 0}),
                    1e-12 * directionalDipole(m, normal, V{ld, 0, 0}));
}
