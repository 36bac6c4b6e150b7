// The material and pencil stages (model_stages.h).
#include "pipeline/model_stages.h"

#include "bssrdf/conditioning.h"
#include "core/core.h"
#include "core/fields.h"
#include "core/text.h"
#include "gl/gl.h"

namespace app {
namespace {
// The preset's name is no input of the material (the values it set are).
std::string keyOf(MaterialSettings s, long long generation) {
    s.preset.clear();
    return core::keyOf(generation, s);
}

// A table model path-traced for one medium per channel describes that medium only: a material
// that differs is named (the curve is still drawn, so nothing the user sees disappears).
std::string tableMediumProblem(const bssrdf::Model& m, const material::MaterialParams& p) {
    if (m.tableMedia.size() != 3) return {};
    static const char* kChannel[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) {
        const auto& t = m.tableMedia[size_t(c)];
        auto near = [](double a, double b) { return std::fabs(a - b) <= 1e-6 * std::fabs(b); };
        if (!near(p.sigmaA[c], t.sigmaA) || !near(p.sigmaS[c], t.sigmaS) || !near(p.g, t.g) ||
            !near(p.eta, t.eta))
            return std::string("its table was computed for ") + kChannel[c] + " sigma_a " +
                   core::formatNumber(t.sigmaA) + ", sigma_s " + core::formatNumber(t.sigmaS) +
                   ", g " + core::formatNumber(t.g) + ", eta " + core::formatNumber(t.eta) +
                   "; the material has sigma_a " + core::formatNumber(p.sigmaA[c]) + ", sigma_s " +
                   core::formatNumber(p.sigmaS[c]) + ", g " + core::formatNumber(p.g) + ", eta " +
                   core::formatNumber(p.eta) + " (its curve describes another medium)";
    }
    return {};
}

void computeMaterial(bssrdf::ModelEntry& e, ModelView& v, const MaterialSettings& shared) {
    const MaterialSettings& s = v.override ? v.own : shared;
    e.inversionInUse = s.mode != ParamMode::Sigma;
    std::string key = keyOf(s, e.generation);
    if (key == v.materialKey) return;
    v.materialKey = key;
    try {
        v.effective = effectiveParams(e, s);
        v.materialProblem = tableMediumProblem(*e.model, *v.effective);
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
    try {
        v.profile =
            bssrdf::evaluateProfile(e.programs.at("pencil_profile.comp").id(), *e.model, e.values,
                                    builtinsOf(*v.effective), bssrdf::radiusGrid(rMax, samples));
    } catch (const core::Error& err) { // a loop past its budget: the last good profile stays
        v.profileProblem = err.what();
        return;
    }
    v.profileProblem = bssrdf::profileProblem(v.profile);
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
    // g, η and scale are validated on their own; σ comes from the inversion.
    material::MaterialParams probe = p;
    probe.sigmaA = glm::dvec3(0.01);
    probe.sigmaS = glm::dvec3(1.0);
    material::validate(probe, "parameters");
    gl::ScopedStageTimer timer("inversion");
    glm::dvec3 alphaPrime;
    if (e.hasInversion()) {
        const GLuint program = e.programs.at("invert_rdr.comp").id();
        auto batch = [&](const std::vector<glm::dvec3>& alpha) {
            return bssrdf::evaluateDiffuseReflectance(program, *e.model, e.values, builtinsOf(p),
                                                      alpha);
        };
        alphaPrime = material::solveAlphaPrime(s.rdr, batch);
    } else {
        // no closed form: R_dr by integrating the model's own profile (one GPU profile per
        // α′, so a coarse grid per round and more rounds: 16^8 brackets α′ to ~2^-32)
        const GLuint program = e.programs.at("pencil_profile.comp").id();
        auto batch = [&](const std::vector<glm::dvec3>& alpha) {
            return bssrdf::integrateDiffuseReflectance(program, *e.model, e.values, builtinsOf(p),
                                                       alpha);
        };
        try {
            alphaPrime = material::solveAlphaPrime(s.rdr, batch, 16, 8);
        } catch (const core::Error& err) {
            throw core::Error(e.displayPath, 0,
                              std::string("R_dr / l_d by the numerically integrated profile "
                                          "(no diffuseReflectance section): ") +
                                  err.what());
        }
    }
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

StageStatus PencilStage::status() const {
    StageStatus st;
    if (!m_views) return st;
    for (const auto& [path, v] : *m_views)
        if (!v.profileProblem.empty())
            st.problems.push_back(v.profileProblem.rfind(path + ":", 0) == 0
                                      ? v.profileProblem // names the file and line itself
                                      : path + ": " + v.profileProblem);
    return st;
}

bool PencilStage::update(const PencilInputs& in) {
    m_views = in.views;
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

namespace {

// σ from R_dr/l_d: the bisection brackets α′ to 2^-27; float32 DiffuseReflectance moves the
// root by ~1 ulp of α′ ≈ 6e-8, amplified by 1/(1−α′) in σa (≤ ~1e3 for the presets).
constexpr double kInvertedRelTol = 1e-4;

// The model's view when it has an effective σ, else null.
const ModelView* capturedView(const bssrdf::ModelEntry& e,
                              const std::map<std::string, ModelView>& views) {
    auto it = views.find(e.displayPath);
    return e.usable() && it != views.end() && it->second.effective ? &it->second : nullptr;
}

std::string captureName(const bssrdf::ModelEntry& e) {
    return e.model ? e.model->name : e.file.stem().string();
}

// The pencil plot's per-value allowance for another driver: twice the spread of each value under
// the errors GLSL allows the model's transcendental functions (bssrdf/conditioning.h). Without it
// (the perturbed program does not build) the replay keeps the relative floor alone, and says why.
void addConditioning(const bssrdf::ModelLibrary& library, const bssrdf::ModelEntry& e,
                     const ModelView& v, CaptureEntry& p) {
    try {
        const std::vector<glm::dvec3> spread = bssrdf::profileSpread(
            *e.model, library.sources(), e.values, builtinsOf(*v.effective), v.profile.r);
        p.conditioning.columns = p.table.columns;
        for (size_t i = 0; i < spread.size(); ++i)
            p.conditioning.rows.push_back(
                {0.0, 2.0 * spread[i].x, 2.0 * spread[i].y, 2.0 * spread[i].z});
        p.conditioningNote = "2x the spread of each value under the errors GLSL 4.50 allows the "
                             "model's exp, log, pow and sqrt (" +
                             std::to_string(bssrdf::kConditioningPatterns) + " sign patterns)";
    } catch (const core::Error& err) {
        p.conditioningNote.clear();
        core::logInfo(e.displayPath + ": no per-value tolerance for another driver (" + err.what() +
                      "); the replay allows the relative floor alone");
    }
}

} // namespace

void MaterialStage::capture(const ModelStageInputs& in, CaptureEntries& out) const {
    for (const auto& e : in.library->entries()) {
        const std::string name = captureName(e);
        const ModelView* v = capturedView(e, *in.views);
        if (!v) {
            auto it = in.views->find(e.displayPath);
            const std::string why = it == in.views->end() || it->second.materialProblem.empty()
                                        ? "not computed"
                                        : it->second.materialProblem;
            out.missing.push_back(name + ": " + (e.problem ? e.problem->text() : why));
            continue;
        }
        const MaterialSettings& s = v->override ? v->own : *in.shared;
        CaptureEntry m = captureEntry(CaptureEntry::Kind::Csv, "material." + name, "channel");
        m.table.comments = {"model " + e.displayPath, "effective sigma in 1/mm"};
        m.table.columns = {"channel", "sigma_a", "sigma_s"};
        for (int c = 0; c < 3; ++c)
            m.table.rows.push_back({double(c), v->effective->sigmaA[c], v->effective->sigmaS[c]});
        if (s.mode == ParamMode::RdrLd) {
            m.relTol = kInvertedRelTol;
            m.note = "inverted from R_dr/l_d with float32 GPU DiffuseReflectance";
        } else {
            m.note = "copied from the inputs (exact)";
        }
        out.entries.push_back(std::move(m));
    }
}

void PencilStage::capture(const PencilInputs& in, CaptureEntries& out) const {
    for (const auto& e : in.library->entries()) {
        const ModelView* v = capturedView(e, *in.views);
        if (!v) continue; // listed as missing by the material stage
        const std::string name = captureName(e);
        CaptureEntry p = captureEntry(CaptureEntry::Kind::Csv, "pencil_plot." + name, "r_mm");
        p.relTol = kProfileRelTol;
        p.note = "float32 GPU evaluation of Bssrdf(); GLSL exp <= (3+2|x|) ulp";
        p.table.comments = {"model " + e.displayPath,
                            "Bssrdf(Xi=0, Wi=n, Xo=(r,0,0), Wo=n) in 1/mm^2"};
        p.table.columns = {"r_mm", "R", "G", "B"};
        for (size_t i = 0; i < v->profile.r.size(); ++i)
            p.table.rows.push_back({v->profile.r[i], v->profile.value[i].x, v->profile.value[i].y,
                                    v->profile.value[i].z});
        if (out.forReplay) addConditioning(*in.library, e, *v, p);
        out.entries.push_back(std::move(p));
    }
}

} // namespace app
