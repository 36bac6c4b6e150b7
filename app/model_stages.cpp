// The material and pencil stages (model_stages.h).
#include "model_stages.h"

#include "core/core.h"
#include "gl/gl.h"

#include "core/fields.h"

namespace app {
namespace {
// The preset's name is no input of the material (the values it set are).
std::string keyOf(MaterialSettings s, long long generation) {
    s.preset.clear();
    return core::keyOf(generation, s);
}

void computeMaterial(bssrdf::ModelEntry& e, ModelView& v, const MaterialSettings& shared) {
    const MaterialSettings& s = v.override ? v.own : shared;
    std::string key = keyOf(s, e.generation);
    if (key == v.materialKey) return;
    v.materialKey = key;
    try {
        v.effective = effectiveParams(e, s);
        v.materialProblem.clear();
    } catch (const core::Error& err) {
        v.effective.reset();
        v.materialProblem = err.what();
    }
}

void computeProfile(bssrdf::ModelEntry& e, ModelView& v, double rMax, int samples) {
    if (!v.effective || !e.usable()) return;
    const std::string key = core::keyOf(v.materialKey, rMax, samples, e.values);
    if (key == v.profileKey) return;
    v.profileKey = key;
    gl::ScopedStageTimer timer("pencil plot");
    v.profile =
        bssrdf::evaluateProfile(e.programs.at("pencil_profile.comp").id(), *e.model, e.values,
                                builtinsOf(*v.effective), bssrdf::radiusGrid(rMax, samples));
}

} // namespace

bssrdf::Builtins builtinsOf(const material::MaterialParams& p) {
    bssrdf::Builtins b;
    b.sigmaA = glm::vec3(p.sigmaA);
    b.sigmaS = glm::vec3(p.sigmaS);
    b.g = static_cast<float>(p.g);
    b.ior = static_cast<float>(p.eta);
    b.scale = static_cast<float>(p.scale);
    return b;
}

material::MaterialParams effectiveParams(const bssrdf::ModelEntry& e, const MaterialSettings& s) {
    material::MaterialParams p = s.params;
    if (s.mode == ParamMode::Sigma) {
        material::validate(p, "parameters");
        return p;
    }
    if (!e.hasInversion())
        throw core::Error(e.displayPath, 0,
                          "R_dr / l_d parametrisation unavailable: the model has no "
                          "diffuseReflectance section");
    // g, η and scale are validated on their own; σ comes from the inversion.
    material::MaterialParams probe = p;
    probe.sigmaA = glm::dvec3(0.01);
    probe.sigmaS = glm::dvec3(1.0);
    material::validate(probe, "parameters");
    gl::ScopedStageTimer timer("inversion");
    const GLuint program = e.programs.at("invert_rdr.comp").id();
    auto batch = [&](const std::vector<glm::dvec3>& alpha) {
        return bssrdf::evaluateDiffuseReflectance(program, *e.model, e.values, builtinsOf(p),
                                                  alpha);
    };
    glm::dvec3 alphaPrime = material::solveAlphaPrime(s.rdr, batch);
    auto sig = material::sigmaFromAlphaPrime(alphaPrime, s.ld, p.g);
    p.sigmaA = sig.sigmaA;
    p.sigmaS = sig.sigmaS;
    material::validate(p, "inverted parameters");
    return p;
}

bool MaterialStage::update(const ModelStageInputs& in) {
    m_views = in.views;
    bool changed = false;
    for (auto& e : in.library->entries()) {
        if (!e.usable()) continue;
        ModelView& v = (*in.views)[e.displayPath];
        const std::string before = v.materialKey;
        computeMaterial(e, v, *in.shared);
        changed |= v.materialKey != before;
    }
    return changed;
}

StageStatus MaterialStage::status() const {
    StageStatus st;
    if (!m_views) return st;
    for (const auto& [path, v] : *m_views)
        if (!v.materialProblem.empty()) st.problems.push_back(path + ": " + v.materialProblem);
    return st;
}

bool PencilStage::update(const PencilInputs& in) {
    bool changed = false;
    for (auto& e : in.library->entries()) {
        if (!e.usable()) continue;
        ModelView& v = (*in.views)[e.displayPath];
        const std::string before = v.profileKey;
        computeProfile(e, v, in.rMaxMm, in.samples);
        changed |= before != v.profileKey;
    }
    return changed;
}

} // namespace app
