// Workbench state and stage graph: reload → material (inversion) → pencil profile.
#include "workbench.h"

#include "reference_plot.h"

#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <sys/stat.h>

namespace app {
namespace fs = std::filesystem;

namespace {
double epochSeconds() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}
// The preset's name is no input of the material (the values it set are).
std::string keyOf(MaterialSettings s, long long generation) {
    s.preset.clear();
    return core::keyOf(generation, s);
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

Workbench::Workbench(fs::path root, bool watch, const std::vector<fs::path>& models)
    : m_root(fs::absolute(root).lexically_normal()) {
    try {
        m_presets = material::loadPresets(m_root / "materials" / "presets.json");
    } catch (const core::Error& e) {
        m_actionErrors.push_back(e.what());
    }
    if (const auto* p = material::findPreset(m_presets, m_shared.preset))
        m_shared.params = material::applyPreset(*p, m_shared.params);
    m_gpuRef = std::make_unique<GpuReference>(m_root / "shaders" / "pathtrace_slab.comp");
    m_ptSphere = std::make_unique<PathTracedSphere>(m_root / "shaders" / "pathtrace_sphere.comp");
    m_scene = std::make_unique<SceneStage>(m_root);
    m_scene->settings().enabled = false;
    m_library = std::make_unique<bssrdf::ModelLibrary>(
        m_root,
        std::vector<std::string>{"pencil_profile.comp", "invert_rdr.comp", "sphere_bssrdf.comp"});
    if (models.empty()) m_library->scanAll();
    for (const auto& m : models) {
        if (!fs::exists(m)) throw core::Error(m.string(), 0, "no such model file");
        m_library->reload(m);
    }
    if (watch)
        m_watcher = std::make_unique<core::FileWatcher>(
            std::vector<fs::path>{m_root / "materials", m_root / "shaders"});
    update();
}

void Workbench::reloadAll() {
    std::vector<fs::path> files;
    for (const auto& e : m_library->entries())
        files.push_back(e.file);
    std::error_code ec;
    for (auto& d : fs::directory_iterator(m_root / "materials", ec))
        if (d.path().extension() == ".bssrdf") {
            fs::path f = fs::absolute(d.path()).lexically_normal();
            if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
        }
    for (const auto& f : files)
        m_library->reload(f);
    for (auto& [k, v] : m_views)
        v.materialKey.clear(), v.profileKey.clear();
    update();
}

void Workbench::openModel(const fs::path& file) {
    if (!fs::exists(file)) throw core::Error(file.string(), 0, "no such file");
    if (file.extension() != ".bssrdf")
        throw core::Error(file.string(), 0, "not a .bssrdf model file");
    m_library->open(file);
    update();
}

void Workbench::applyPreset(MaterialSettings& s, const std::string& name) {
    const auto* p = material::findPreset(m_presets, name);
    if (!p) throw core::Error("preset", 0, "unknown preset '" + name + "'");
    s.params = material::applyPreset(*p, s.params);
    s.preset = name;
    s.mode = ParamMode::Sigma;
}

MaterialSettings& Workbench::settingsFor(const std::string& displayPath) {
    auto& v = m_views[displayPath];
    return v.override ? v.own : m_shared;
}

void Workbench::computeMaterial(bssrdf::ModelEntry& e, ModelView& v) {
    const MaterialSettings& s = v.override ? v.own : m_shared;
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

double Workbench::autoRMax() const {
    double ld = 0;
    for (const auto& e : m_library->entries()) {
        auto it = m_views.find(e.displayPath);
        if (it == m_views.end() || !it->second.effective || !it->second.visible) continue;
        glm::dvec3 l = material::diffuseMeanFreePath(*it->second.effective);
        for (int c = 0; c < 3; ++c)
            if (std::isfinite(l[c])) ld = std::max(ld, l[c]);
    }
    return ld > 0 ? m_plot.rangeLd * ld : 20.0;
}

void Workbench::computeProfile(bssrdf::ModelEntry& e, ModelView& v) {
    if (!v.effective || !e.usable()) return;
    const std::string key = core::keyOf(v.materialKey, m_rMax, m_plot.samples, e.values);
    if (key == v.profileKey) return;
    v.profileKey = key;
    gl::ScopedStageTimer timer("pencil plot");
    v.profile = bssrdf::evaluateProfile(e.programs.at("pencil_profile.comp").id(), *e.model,
                                        e.values, builtinsOf(*v.effective),
                                        bssrdf::radiusGrid(m_rMax, m_plot.samples));
}

bool Workbench::update() {
    bool changed = false;
    if (m_watcher) {
        auto paths = m_watcher->poll();
        if (!paths.empty()) {
            for (const auto& p : paths) {
                struct stat st {};
                if (::stat(p.c_str(), &st) == 0) {
                    double s = double(st.st_mtim.tv_sec) + 1e-9 * double(st.st_mtim.tv_nsec);
                    if (!m_pendingSaveTime || s < *m_pendingSaveTime) m_pendingSaveTime = s;
                }
            }
            changed |= m_library->onFilesChanged(paths);
            for (const auto& p : paths) {
                const std::string name = p.filename().string();
                if (name.rfind("octree_", 0) == 0 || name.rfind("render_", 0) == 0 ||
                    name.rfind("irradiance_", 0) == 0 || name == "bssrdf_prelude.glsl") {
                    ++m_shaderGeneration; // the scene's render and irradiance programs
                    changed = true;
                    break;
                }
            }
            for (const auto& p : paths)
                if (p.filename().string().rfind("pathtrace", 0) == 0) {
                    m_gpuRef->reload(); // the GPU tracers' shaders or their includes
                    m_ptSphere->reloadGpu();
                    changed = true;
                    break;
                }
        }
    }
    // drop views of models that disappeared
    for (auto it = m_views.begin(); it != m_views.end();) {
        bool alive = false;
        for (auto& e : m_library->entries())
            alive |= e.displayPath == it->first;
        it = alive ? std::next(it) : m_views.erase(it);
    }
    for (auto& e : m_library->entries())
        if (e.usable()) computeMaterial(e, m_views[e.displayPath]);
    double rMax = m_plot.fixedRange ? m_plot.rMaxMm : autoRMax();
    if (!(rMax > 0) || !std::isfinite(rMax)) rMax = 20.0;
    if (rMax != m_rMax) changed = true;
    m_rMax = rMax;
    for (auto& e : m_library->entries()) {
        if (!e.usable()) continue;
        auto& v = m_views[e.displayPath];
        std::string before = v.profileKey;
        computeProfile(e, v);
        changed |= before != v.profileKey;
    }
    updateReference();
    changed |= updateLitSpheres(8.0);
    changed |= m_scene->update(sceneModelInput(), m_interacting, m_shaderGeneration);
    if (m_ref->version() + m_gpuSteps != m_refVersion) {
        m_refVersion = m_ref->version() + m_gpuSteps;
        changed = true;
    }
    return changed;
}

SceneModelInput Workbench::sceneModelInput() const {
    SceneModelInput in;
    const ModelView* view = nullptr;
    in.entry = sourceModel(&view);
    if (in.entry) {
        in.builtins = builtinsOf(*view->effective);
        in.materialKey = view->materialKey;
    }
    return in;
}

const bssrdf::ModelEntry* Workbench::sourceModel(const ModelView** view) const {
    for (const auto& e : m_library->entries()) {
        auto it = m_views.find(e.displayPath);
        if (it == m_views.end() || !it->second.effective || !e.usable()) continue;
        if (!m_plot.solo.empty() ? m_plot.solo == e.displayPath : it->second.visible) {
            if (view) *view = &it->second;
            return &e;
        }
    }
    return nullptr;
}

bool Workbench::updateLitSpheres(double budgetMs) {
    if (!m_sphere.enabled) {
        if (!m_sphereKey.empty()) m_ptSphere->cancel();
        m_sphereKey.clear();
        return false;
    }
    const ModelView* view = nullptr;
    const bssrdf::ModelEntry* e = sourceModel(&view);
    if (!e) return false;
    const auto& p = *view->effective;
    pathtrace::LitSphereSetup setup;
    setup.radiusMm = m_sphere.radiusMm;
    for (int i = 0; i < 3; ++i)
        setup.lightDir[i] = m_sphere.lightDir[i];
    setup.width = setup.height = m_sphere.size;
    setup.seed = m_sphere.seed;
    // integratedSpp is a target the integration runs to, not an input of its image
    LitSphereSettings keyed = m_sphere;
    keyed.integratedSpp = 0;
    const std::string key =
        core::keyOf(e->displayPath, e->generation, view->materialKey, keyed, e->values);
    bool changed = false;
    if (key != m_sphereKey) {
        m_sphereKey = key;
        m_sphereModel = e->displayPath;
        m_sphereProblem.clear();
        m_ptSppSeen = 0;
        std::array<pathtrace::Medium, 3> media;
        for (int c = 0; c < 3; ++c)
            media[c] = {p.sigmaA[c], p.sigmaS[c], p.g, p.eta};
        try {
            m_integrator.reset(setup);
            std::filesystem::path mesh;
            if (!m_sphere.mesh.empty()) {
                mesh = m_sphere.mesh;
                if (mesh.is_relative()) mesh = m_root / mesh;
            }
            m_ptSphere->start(media, setup, m_sphere.pathSpp, m_sphere.gpu, mesh);
        } catch (const core::Error& err) {
            m_sphereProblem = err.what();
            m_ptSphere->cancel();
        }
        changed = true;
    }
    if (!m_sphereProblem.empty()) return changed;
    // the GPU integration takes a slice per frame, sized to stay near the budget
    const uint64_t done = m_integrator.samplesPerPixelDone();
    if (done < uint64_t(m_sphere.integratedSpp) && e->programs.count("sphere_bssrdf.comp")) {
        const int n = int(std::min<uint64_t>(uint64_t(m_integratedSlice),
                                             uint64_t(m_sphere.integratedSpp) - done));
        core::Stopwatch sw;
        m_integrator.step(e->programs.at("sphere_bssrdf.comp").id(), *e->model, e->values,
                          builtinsOf(p), n); // timed inside as "sphere BSSRDF integration"
        const double ms = sw.ms();
        if (budgetMs < 0)
            m_integratedSlice = kFixedSlice; // fixed slices (finishLitSpheres)
        else if (ms < 0.5 * budgetMs)
            m_integratedSlice = std::min(m_integratedSlice * 2, 4096);
        else if (ms > budgetMs)
            m_integratedSlice = std::max(m_integratedSlice / 2, 1);
        changed = true;
    }
    if (m_sphere.gpu) m_ptSphere->stepGpu(budgetMs < 0 ? 1e9 : 0.5 * budgetMs);
    if (m_ptSphere->sppDone() != m_ptSppSeen) {
        m_ptSppSeen = m_ptSphere->sppDone();
        changed = true;
    }
    return changed;
}

void Workbench::finishLitSpheres() {
    // restart and take fixed slices: the GPU sums then do not depend on frame timings, so the
    // same build and seed give bitwise the same images (captures rely on it)
    m_sphereKey.clear();
    m_integratedSlice = kFixedSlice;
    updateLitSpheres(-1);
    while (m_sphere.enabled && m_sphereProblem.empty() &&
           m_integrator.samplesPerPixelDone() < uint64_t(m_sphere.integratedSpp))
        if (!updateLitSpheres(-1)) break;
    m_ptSphere->wait();
}

ReferenceSnapshot Workbench::finishReference() {
    updateReference();
    if (m_refSettings.gpu) {
        while (m_gpuRef->step(1000.0)) {
        }
    } else {
        m_ref->wait();
    }
    return referenceSnapshot();
}

void Workbench::updateReference() {
    if (!m_refSettings.enabled) {
        if (!m_refKey.empty()) cancelReference();
        m_refKey.clear();
        return;
    }
    // GPU work is sliced per frame on this (the GL) thread
    if (m_refSettings.gpu && m_gpuRef->step(8.0)) ++m_gpuSteps;
    // σ of the soloed model, else of the first visible model with a usable material
    const ModelView* source = nullptr;
    std::string name;
    for (const auto& e : m_library->entries()) {
        auto it = m_views.find(e.displayPath);
        if (it == m_views.end() || !it->second.effective) continue;
        if (!m_plot.solo.empty() ? m_plot.solo == e.displayPath : it->second.visible) {
            source = &it->second;
            name = e.displayPath;
            break;
        }
    }
    if (!source) return;
    const auto& p = *source->effective;
    std::array<pathtrace::Medium, 3> media;
    for (int c = 0; c < 3; ++c)
        media[c] = {p.sigmaA[c], p.sigmaS[c], p.g, p.eta};
    pathtrace::SlabSettings s;
    s.rMaxMm = m_rMax;
    s.bins = m_refSettings.bins;
    s.seed = m_refSettings.seed;
    material::MaterialParams keyed = p;
    keyed.scale = 0; // lengths of the slab are in mm: the mesh scale is no input
    const std::string key = core::keyOf(keyed, m_rMax, m_refSettings);
    if (key == m_refKey) return;
    m_refKey = key;
    m_refModel = name;
    cancelReference();
    if (m_refSettings.gpu)
        m_gpuRef->start(media, s, m_refSettings.paths);
    else
        m_ref->start(media, s, m_refSettings.paths);
}

void Workbench::framePresented() {
    if (!m_pendingSaveTime) return;
    glFinish();
    double latencyMs = (epochSeconds() - *m_pendingSaveTime) * 1000.0;
    m_pendingSaveTime.reset();
    if (latencyMs >= 0 && latencyMs < 60000) {
        gl::recordTiming("hot reload: save -> new pixels", latencyMs);
        core::logInfo("hot reload: save to new pixels " + std::to_string(latencyMs) + " ms");
    }
}

std::vector<ErrorItem> Workbench::errors() const {
    std::vector<ErrorItem> out;
    for (const auto& e : m_library->entries()) {
        if (e.problem) {
            bool shader = e.problem->file.rfind("shaders/", 0) == 0;
            out.push_back({shader ? "shader" : "model", e.problem->text()});
        }
        auto it = m_views.find(e.displayPath);
        if (it != m_views.end() && !it->second.materialProblem.empty())
            out.push_back({"material", e.displayPath + ": " + it->second.materialProblem});
    }
    for (const auto& p : m_library->problems())
        out.push_back({"shader", p.text()});
    if (m_refSettings.enabled) {
        const ReferenceSnapshot snap = referenceSnapshot();
        if (!snap.problem.empty()) out.push_back({"reference", snap.problem});
        if (!snap.energy.empty()) out.push_back({"reference", snap.energy});
    }
    if (m_sphere.enabled) {
        if (!m_sphereProblem.empty()) out.push_back({"lit sphere", m_sphereProblem});
        std::string pt = m_ptSphere->problem();
        if (!pt.empty()) out.push_back({"lit sphere", pt});
    }
    for (const auto& p : m_scene->problems())
        out.push_back({"scene", p});
    for (const auto& a : m_actionErrors)
        out.push_back({"action", a});
    return out;
}

void Workbench::reportActionError(const std::string& text) {
    core::logError(text);
    m_actionErrors.push_back(text);
}

std::string Workbench::normalisationNote() {
    return "Bssrdf(Xi=0, Wi=n, Xo=(r,0,0), Wo=n): R_d per unit power entering the medium [1/mm^2]";
}

std::vector<plot::Series> Workbench::plotSeries() const {
    std::vector<plot::Series> out;
    size_t index = 0;
    auto valueOf = [&](const glm::dvec3& v, int channel) {
        return channel < 3 ? v[channel] : material::luminance(v);
    };
    for (const auto& e : m_library->entries()) {
        auto it = m_views.find(e.displayPath);
        size_t colorIndex = index++;
        if (it == m_views.end() || it->second.profile.r.empty()) continue;
        const ModelView& v = it->second;
        if (!m_plot.solo.empty() && m_plot.solo != e.displayPath) continue;
        if (m_plot.solo.empty() && !v.visible) continue;
        const std::string name = e.model ? e.model->name : e.displayPath;
        auto make = [&](int channel, const std::string& label, uint32_t color) {
            plot::Series s;
            s.label = label;
            s.color = color;
            s.x = v.profile.r;
            s.y.resize(s.x.size());
            for (size_t i = 0; i < s.x.size(); ++i) {
                double y = valueOf(v.profile.value[i], channel);
                s.y[i] = m_plot.rTimesR ? y * s.x[i] : y;
            }
            out.push_back(std::move(s));
        };
        if (!m_plot.solo.empty()) {
            make(0, name + " R", 0xff4040ffu);
            make(1, name + " G", 0xff40ff40u);
            make(2, name + " B", 0xffff6040u);
        } else {
            make(m_plot.channel, name, plot::defaultColor(colorIndex));
        }
    }
    if (!m_refSettings.enabled) return out;
    ReferenceSnapshot snap = referenceSnapshot();
    if (snap.pathsDone == 0) return out;
    if (!m_plot.solo.empty()) {
        for (int c = 0; c < 3; ++c) {
            plot::Series ref = referenceSeries(snap, c, m_plot.rTimesR);
            ref.label = std::string("path traced ") + "RGB"[c];
            out.push_back(std::move(ref));
        }
        return out;
    }
    plot::Series ref = referenceSeries(snap, m_plot.channel, m_plot.rTimesR);
    // error figures of each model that uses the reference's σ, at the plotted channel's l_d
    const ModelView* src = nullptr;
    if (auto it = m_views.find(m_refModel); it != m_views.end()) src = &it->second;
    for (auto& s : out) {
        for (const auto& e : m_library->entries()) {
            auto it = m_views.find(e.displayPath);
            if (!e.model || s.label != e.model->name || it == m_views.end()) continue;
            const auto& mine = it->second.effective;
            const bool sameMedium =
                src && mine && src->effective && mine->sigmaA == src->effective->sigmaA &&
                mine->sigmaS == src->effective->sigmaS && mine->g == src->effective->g &&
                mine->eta == src->effective->eta;
            if (!sameMedium) {
                s.label += "  (other sigma: no error figures)";
                continue;
            }
            glm::dvec3 ld = material::diffuseMeanFreePath(*it->second.effective);
            if (snap.energyFails(m_plot.channel)) {
                s.label += "  (reference failed its energy check: no error figures)";
                continue;
            }
            ModelError err = modelError(s, ref, ld[m_plot.channel < 3 ? m_plot.channel : 1]);
            if (!err.valid) continue;
            char buf[160];
            std::snprintf(buf, sizeof buf, "  rel.L2 %.1f%%  ratio@1ld %.3f  @4ld %.3f",
                          100 * err.relL2, err.ratioAt1, err.ratioAt4);
            s.label += buf;
        }
    }
    out.push_back(std::move(ref));
    return out;
}

} // namespace app
