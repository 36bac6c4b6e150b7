// Shared by the model tests (normalized diffusion, photon beam diffusion, multipole,
// quantized diffusion, directional dipole): the media they evaluate at and the double-precision
// pieces of their independent references that are the same for every model (Fresnel
// reflectance from inside and its moments by Simpson's rule, not the models' own rules).
#pragma once

#include "../support/gl_fixture.h"
#include "bssrdf/program.h"
#include "bssrdf/program_library.h"
#include "material/material.h"

#include <glm/glm.hpp>

#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace model_ref {

struct Medium {
    std::string name;
    double sa, ss, g, eta;
};

// Unpolarised Fresnel reflectance for light inside (relative index eta) at cos θ = mu.
inline double fresnelInside(double mu, double eta) {
    const double s2 = eta * eta * (1 - mu * mu);
    if (s2 >= 1) return 1;
    const double ct = std::sqrt(1 - s2);
    const double rs = (eta * mu - ct) / (eta * mu + ct), rp = (mu - eta * ct) / (mu + eta * ct);
    return 0.5 * (rs * rs + rp * rp);
}

// Composite Simpson's rule on n (even) intervals.
inline double simpson(const std::function<double(double)>& f, double a, double b, int n) {
    const double h = (b - a) / n;
    double s = f(a) + f(b);
    for (int i = 1; i < n; ++i)
        s += (i % 2 ? 4 : 2) * f(a + i * h);
    return s * h / 3;
}

// ∫0^1 F(mu) mu^k dmu by Simpson's rule on 20000 intervals (not the models' rule).
inline double moment(int k, double eta) {
    return simpson([&](double mu) { return fresnelInside(mu, eta) * std::pow(mu, k); }, 0, 1,
                   20000);
}

// Every preset medium of every table (each channel on its own, except one that does not scatter;
// the presets list σ′s, so with g = 0 σs = σ′s),
// an anisotropic one at η = 1.5 and an index-matched one.
inline std::vector<Medium> media() {
    std::vector<Medium> out;
    for (const auto& p :
         material::loadPresets(testsupport::sourceRoot() / "materials/presets.json")) {
        for (int c = 0; c < 3; ++c)
            if (p.sigmaSPrime[c] > 0) // a table may list a channel that does not scatter
                out.push_back({p.name + "[" + std::to_string(c) + "]", p.sigmaA[c],
                               p.sigmaSPrime[c], 0.0, p.eta});
    }
    out.push_back({"anisotropic eta 1.5", 0.05, 5.0, 0.8, 1.5});
    out.push_back({"matched boundary", 0.2, 1.0, 0.0, 1.0});
    return out;
}

// The model's built-in uniforms for one medium (the same in every channel).
inline bssrdf::Builtins builtins(const Medium& m) {
    bssrdf::Builtins b;
    b.sigmaA = glm::vec3(float(m.sa));
    b.sigmaS = glm::vec3(float(m.ss));
    b.g = float(m.g);
    b.ior = float(m.eta);
    return b;
}

// A fixture holding one shipped model (materials/FILE) built for the pencil profile and the
// R_dr inversion, with a headless GL context; fails the test when it does not load.
class ModelTest : public ::testing::Test {
  protected:
    explicit ModelTest(std::string file) : m_file(std::move(file)) {}
    void SetUp() override {
        testsupport::context();
        m_lib = std::make_unique<bssrdf::ModelLibrary>(
            testsupport::sourceRoot(),
            std::vector<std::string>{"pencil_profile.comp", "invert_rdr.comp"});
        m_lib->reload(testsupport::sourceRoot() / "materials" / m_file);
        m_e = m_lib->find("materials/" + m_file);
        ASSERT_NE(m_e, nullptr);
        ASSERT_FALSE(m_e->problem) << m_e->problem->text();
    }
    std::string m_file;
    std::unique_ptr<bssrdf::ModelLibrary> m_lib;
    bssrdf::ModelEntry* m_e = nullptr;
};

} // namespace model_ref
