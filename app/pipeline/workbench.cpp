// The workbench (workbench.h): models, the file watcher, the stages in data-flow order, the
// Errors list and the save → pixels clock of hot reload.
#include "pipeline/workbench.h"
#include "pathtrace/mco.h"

#include "probe/model_probe_process.h"

#include "core/color.h"
#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>

#include <sys/stat.h>

namespace app {
namespace fs = std::filesystem;

namespace {
double epochSeconds() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}
} // namespace

Workbench::Workbench(fs::path root, bool watch, const std::vector<fs::path>& models)
    : m_root(fs::absolute(root).lexically_normal()) {
    try {
        m_presets = material::loadPresets(m_root / "materials" / "presets.json");
    } catch (const core::Error& e) {
        m_actionErrors.push_back(e.what());
    }
    if (const auto* p = material::findPreset(m_presets, m_shared.preset))
        m_shared.params = material::applyPreset(*p, m_shared.params);
    m_reference = std::make_unique<ReferenceStage>(m_root / "shaders" / "pathtrace_slab.comp");
    m_slice = std::make_unique<SliceStage>(m_root / "shaders" / "bssrdf_walk.comp",
                                           m_root / "shaders" / "pathtrace_slab.comp");
    m_scoreboard = std::make_unique<ScoreboardStage>();
    m_fit = std::make_unique<FitStage>();
    m_geometry = std::make_unique<GeometryStage>();
    m_monteCarlo = std::make_unique<MonteCarloStage>();
    m_textureSpace = std::make_unique<TextureSpaceStage>(m_root);
    m_litSpheres = std::make_unique<LitSphereStage>(m_root / "shaders" / "pathtrace_sphere.comp");
    m_scene = std::make_unique<SceneStage>(m_root);
    m_scene->settings().enabled = false;
    m_library = std::make_unique<bssrdf::ModelLibrary>(
        m_root,
        std::vector<std::string>{"pencil_profile.comp", "invert_rdr.comp", "sphere_bssrdf.comp"});
    // A new or changed model is first evaluated in a child process with a time limit, so a
    // Bssrdf() that does not end never reaches this process's GL (model_probe_process.h).
    if (!modelProbeExecutable().empty())
        m_library->setProbe(
            makeProbeStarter(m_root, [this](const fs::path& file) { return probeInputs(file); }));
    if (models.empty()) m_library->scanAll();
    for (const auto& m : models) {
        if (!fs::exists(m)) throw core::Error(m.string(), 0, "no such model file");
        m_library->reload(m);
    }
    m_library->waitForProbes(); // all at once: as long as the slowest, within the limit
    core::logInfo("resources: " + m_root.string());
    if (watch)
        m_watcher = std::make_unique<core::FileWatcher>(
            std::vector<fs::path>{m_root / "materials", m_root / "shaders"});
    // The stages in data-flow order; each gathers its inputs from the ones before it.
    m_pipeline = {
        {&m_material,
         [this] {
             return m_material.update({m_library.get(), &m_views, &m_shared});
         },
         [this](CaptureEntries& out) {
             m_material.capture({m_library.get(), &m_views, &m_shared}, out);
         }},
        {&m_pencil,
         [this] {
             double rMax = m_plot.fixedRange ? m_plot.rMaxMm : autoRMax();
             if (!(rMax > 0) || !std::isfinite(rMax)) rMax = 20.0;
             const bool changed = rMax != m_rMax;
             m_rMax = rMax;
             return m_pencil.update({m_library.get(), &m_views, m_rMax, m_plot.samples}) || changed;
         },
         [this](CaptureEntries& out) {
             m_pencil.capture({m_library.get(), &m_views, m_rMax, m_plot.samples}, out);
         }},
        {m_reference.get(), [this] { return m_reference->update(referenceInputs()); },
         [this](CaptureEntries& out) { m_reference->capture(referenceInputs(), out); }},
        {m_slice.get(), [this] { return m_slice->update(sliceInputs()); },
         [this](CaptureEntries& out) { m_slice->capture(sliceInputs(), out); }},
        {m_scoreboard.get(),
         [this] {
             const ReferenceSnapshot snap = m_reference->snapshot();
             const ReferenceInputs ri = referenceInputs();
             // the pencil legend shows the same scores, so they follow the reference too
             ScoreboardInputs in;
             in.enabled = m_scoreboardEnabled || m_refSettings.enabled;
             in.library = m_library.get();
             in.views = &m_views;
             in.reference = &snap;
             in.referenceModel = ri.model;
             in.params = ri.params;
             if (m_mcml) {
                 in.mcml = &m_mcml->profile;
                 in.mcmlMedium = m_mcml->medium;
                 in.mcmlName = m_mcml->name;
             }
             return m_scoreboard->update(in);
         }},
        {m_fit.get(),
         [this] {
             const ReferenceSnapshot snap = m_reference->snapshot();
             return m_fit->update(
                 {m_library.get(), &snap, referenceInputs().params, m_rMax, m_plot.samples});
         },
         [this](CaptureEntries& out) {
             const ReferenceSnapshot snap = m_reference->snapshot(); // finished by its capture
             m_fit->capture(
                 {m_library.get(), &snap, referenceInputs().params, m_rMax, m_plot.samples},
                 m_fitRequest, out);
         }},
        {m_geometry.get(),
         [this] {
             return m_geometry->update({&m_geometryTab, m_library.get(), &m_presets});
         }},
        {m_litSpheres.get(), [this] { return m_litSpheres->update(litSphereInputs(8.0)); },
         [this](CaptureEntries& out) { m_litSpheres->capture(litSphereInputs(-1), out); }},
        {m_scene.get(), [this] { return m_scene->update(sceneModelInput(), m_interacting); },
         [this](CaptureEntries& out) { m_scene->capture(sceneModelInput(), out); }},
        {m_monteCarlo.get(),
         [this] {
             return m_monteCarlo->update({m_mc, m_scene.get(), sceneModelInput(), 20.0});
         }},
        {m_textureSpace.get(),
         [this] {
             return m_textureSpace->update({m_ts, m_scene.get(), sceneModelInput(), 20.0});
         },
         [this](CaptureEntries& out) {
             m_textureSpace->capture({m_ts, m_scene.get(), sceneModelInput(), -1}, out);
         }},
    };
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
    core::logInfo("opened " + fs::absolute(file).lexically_normal().string());
    // A model from anywhere is hot-reloaded like those in materials/.
    if (m_watcher) m_watcher->watch(fs::absolute(file).lexically_normal().parent_path());
    update();
}

void Workbench::openMcmlReference(const std::filesystem::path& file,
                                  const std::filesystem::path& second) {
    const pathtrace::McoFile a = pathtrace::readMco(file);
    McmlReference r;
    r.path = file.string();
    r.name = file.filename().string();
    r.medium = pathtrace::mediumOfMco(a, r.path);
    if (second.empty()) {
        r.profile = pathtrace::slabFromMco(a);
    } else {
        const pathtrace::McoFile b = pathtrace::readMco(second);
        const pathtrace::Medium mb = pathtrace::mediumOfMco(b, second.string());
        if (mb.sigmaA != r.medium.sigmaA || mb.sigmaS != r.medium.sigmaS || mb.g != r.medium.g ||
            mb.eta != r.medium.eta || a.dr != b.dr || a.nr != b.nr)
            throw core::Error(second.string(), 0,
                              "not a run of the same input as " + r.path +
                                  " (medium or grid differ)");
        r.profile = pathtrace::slabFromMco(a, &b);
    }
    m_mcml = std::move(r);
}

void Workbench::applyPreset(MaterialSettings& s, const std::string& name) {
    const auto* p = material::findPreset(m_presets, name);
    if (!p) throw core::Error("preset", 0, material::unknownPresetMessage(m_presets, name));
    s.params = material::applyPreset(*p, s.params);
    s.preset = name;
    s.mode = ParamMode::Sigma;
}

MaterialSettings& Workbench::settingsFor(const std::string& displayPath) {
    auto& v = m_views[displayPath];
    return v.override ? v.own : m_shared;
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

ProbeInputs Workbench::probeInputs(const fs::path& file) const {
    ProbeInputs in;
    const std::string path = core::relativeTo(file, m_root);
    const auto it = m_views.find(path);
    material::MaterialParams p =
        (it != m_views.end() && it->second.override ? it->second.own : m_shared).params;
    if (it != m_views.end() && it->second.effective) p = *it->second.effective;
    in.builtins = builtinsOf(p);
    in.rMaxMm = m_rMax;
    in.samples = m_plot.samples;
    // the scene shows this model: the check's server generates its traversal code too
    if (const SceneSettings& ss = m_scene->settings(); ss.enabled)
        if (const SceneModelInput scene = sceneModelInput();
            scene.entry && scene.entry->file == file) {
            in.renderWidth = ss.render.width;
            in.renderHeight = ss.render.height;
        }
    return in;
}

bool Workbench::update() {
    bool changed = m_library->pollProbes();
    gl::expireDebugProblems(kGlProblemSeconds);
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
            // the first part of a save's latency (bench reload prints each part)
            if (m_pendingSaveTime)
                gl::recordTiming("hot reload: file event",
                                 (epochSeconds() - *m_pendingSaveTime) * 1000.0);
            // Each owner rebuilds exactly its programs whose recorded files include a changed
            // path (templates, #include'd files, shaders/common/*); model files reload models.
            changed |= m_library->onFilesChanged(paths);
            for (const PipelineStep& step : m_pipeline)
                changed |= step.stage->reloadShaders(paths);
        }
    }
    // drop views of models that disappeared
    for (auto it = m_views.begin(); it != m_views.end();) {
        bool alive = false;
        for (auto& e : m_library->entries())
            alive |= e.displayPath == it->first;
        it = alive ? std::next(it) : m_views.erase(it);
    }
    assignPlotSlots();
    for (PipelineStep& step : m_pipeline) {
        // a stage's error is an Errors entry, never the end of the frame loop
        try {
            const bool ran = step.run();
            if (ran) step.failed.clear();
            changed |= ran;
        } catch (const core::Error& e) {
            if (step.failed != e.what())
                core::logError(std::string(step.stage->name()) + ": " + e.what());
            changed |= step.failed != e.what();
            step.failed = e.what();
        }
    }
    return changed;
}

void Workbench::assignPlotSlots() {
    std::set<size_t> held;
    for (auto it = m_plotSlots.begin(); it != m_plotSlots.end();) {
        const bool present = m_library->find(it->first) != nullptr;
        if (present) held.insert(it->second);
        it = present ? std::next(it) : m_plotSlots.erase(it);
    }
    for (const auto& e : m_library->entries()) {
        if (m_plotSlots.count(e.displayPath)) continue;
        size_t slot = 0;
        while (held.count(slot))
            ++slot;
        m_plotSlots[e.displayPath] = slot;
        held.insert(slot);
    }
}

size_t Workbench::plotSlot(const std::string& displayPath) const {
    auto it = m_plotSlots.find(displayPath);
    return it == m_plotSlots.end() ? 0 : it->second;
}

shader::Records Workbench::shaderPrograms() const {
    shader::Records out;
    for (const auto& e : m_library->entries())
        for (const auto& [consumer, record] : e.shaders)
            out["model:" + e.displayPath + ":" + consumer] = record;
    for (const PipelineStep& step : m_pipeline)
        for (const auto& [name, record] : step.stage->shaderRecords())
            out[name] = record;
    return out;
}

SceneModelInput Workbench::sceneModelInput() const {
    SceneModelInput in;
    const ModelView* view = nullptr;
    // The Render panel's choice when it names a usable model, else the first visible one.
    if (const std::string& chosen = m_scene->settings().model; !chosen.empty())
        if (const bssrdf::ModelEntry* e = m_library->find(chosen); e && e->usable())
            if (auto it = m_views.find(e->displayPath);
                it != m_views.end() && it->second.effective) {
                in.entry = e;
                view = &it->second;
            }
    if (!in.entry) in.entry = sourceModel(&view);
    if (in.entry) {
        in.builtins = builtinsOf(*view->effective);
        in.materialKey = view->materialKey;
        in.codePending = rendererCodePending(in.entry->displayPath);
    }
    return in;
}

void Workbench::requestSceneComparison(const std::string& model) {
    if (model.empty()) return m_scene->comparison().requestBruteForce();
    const bssrdf::ModelEntry* e = m_library->find(model);
    auto it = e ? m_views.find(e->displayPath) : m_views.end();
    if (!e || !e->usable() || it == m_views.end() || !it->second.effective)
        throw core::Error(model, 0, "not a usable model to compare with");
    m_scene->comparison().request(
        {&*e->model, e->values, builtinsOf(*it->second.effective), e->model->name});
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

ReferenceInputs Workbench::referenceInputs() const {
    ReferenceInputs in;
    in.settings = m_refSettings;
    in.rMaxMm = m_rMax;
    const ModelView* view = nullptr;
    if (const bssrdf::ModelEntry* e = sourceModel(&view)) {
        in.params = view->effective;
        in.model = e->displayPath;
    }
    return in;
}

SliceInputs Workbench::sliceInputs() {
    SliceInputs in;
    in.library = m_library.get();
    in.views = &m_views;
    in.settings = m_sliceSettings;
    const ModelView* view = nullptr;
    if (const bssrdf::ModelEntry* e = sourceModel(&view)) {
        in.params = view->effective;
        in.model = e->displayPath;
    }
    return in;
}

LitSphereInputs Workbench::litSphereInputs(double budgetMs) const {
    LitSphereInputs in;
    in.settings = m_sphere;
    in.root = m_root;
    in.budgetMs = budgetMs;
    const ModelView* view = nullptr;
    if ((in.entry = sourceModel(&view))) {
        in.params = view->effective;
        in.builtins = builtinsOf(*view->effective);
        in.materialKey = view->materialKey;
    }
    return in;
}

void Workbench::finishLitSpheres() {
    m_litSpheres->finish(litSphereInputs(-1));
}

void Workbench::capture(CaptureEntries& out,
                        const std::function<void(const std::string&)>& onStage) {
    update();
    for (const PipelineStep& step : m_pipeline) {
        if (!step.capture) continue;
        if (onStage) onStage(step.stage->name());
        step.capture(out);
    }
}

void Workbench::startFit(const std::string& model, const std::vector<std::string>& params,
                         const FitSettings& s) {
    const ReferenceSnapshot snap = m_reference->snapshot();
    m_fit->start({m_library.get(), &snap, referenceInputs().params, m_rMax, m_plot.samples}, model,
                 params, s);
    m_fitRequest.model = model;
    m_fitRequest.params.clear();
    for (const std::string& p : params)
        m_fitRequest.params += (m_fitRequest.params.empty() ? "" : ",") + p;
    m_fitRequest.maxEvaluations = s.maxEvaluations;
    m_fitRequest.xtolRel = s.xtolRel;
}

void Workbench::finishFit() {
    const ReferenceSnapshot snap = m_reference->snapshot();
    m_fit->finish({m_library.get(), &snap, referenceInputs().params, m_rMax, m_plot.samples});
}

ReferenceSnapshot Workbench::finishReference() {
    return m_reference->finish(referenceInputs());
}

bool Workbench::working() const {
    if (m_library->checking() || m_scene->occludedRunning()) return true;
    return std::any_of(m_pipeline.begin(), m_pipeline.end(),
                       [](const PipelineStep& step) { return step.stage->status().running; });
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
    // One entry per problem: a shader file every model includes fails for each model with the
    // same message; that is one entry naming the models it affects.
    std::vector<std::vector<std::string>> affected;
    for (const auto& e : m_library->entries()) {
        if (!e.problem) continue;
        const bool shader = e.problem->file.rfind("shaders/", 0) == 0;
        const ErrorItem item{shader ? "shader" : "model", e.problem->text()};
        auto same = std::find_if(out.begin(), out.end(), [&](const ErrorItem& o) {
            return o.source == item.source && o.text == item.text;
        });
        if (same == out.end()) {
            out.push_back(item);
            affected.emplace_back();
            same = out.end() - 1;
        }
        if (shader)
            affected[size_t(same - out.begin())].push_back(e.model ? e.model->name
                                                                   : e.file.stem().string());
    }
    for (size_t i = 0; i < out.size(); ++i)
        if (!affected[i].empty()) {
            std::string names;
            for (const std::string& n : affected[i])
                names += (names.empty() ? "" : ", ") + n;
            out[i].text += " (affects " + names + ")";
        }
    for (const auto& p : m_library->problems())
        out.push_back({"shader", p.text()});
    for (const PipelineStep& step : m_pipeline) {
        for (const std::string& p : step.stage->status().problems)
            out.push_back({step.stage->name(), p});
        if (!step.failed.empty()) out.push_back({step.stage->name(), step.failed});
    }
    for (const auto& a : m_actionErrors)
        out.push_back({"action", a});
    for (const gl::DebugProblem& p : gl::debugProblems())
        out.push_back({"GL", p.first + (p.count > 1 ? " (" + std::to_string(p.count) + " times)"
                                                    : std::string())});
    return out;
}

void Workbench::clearActionErrors() {
    m_actionErrors.clear();
    gl::clearDebugProblems();
}

void Workbench::reportActionError(const std::string& text) {
    core::logError(text);
    m_actionErrors.push_back(text);
}

} // namespace app
