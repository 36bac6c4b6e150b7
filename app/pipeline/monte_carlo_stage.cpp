// The Render panel's Monte Carlo renderer (monte_carlo_stage.h).
#include "pipeline/monte_carlo_stage.h"

#include "core/fields.h"
#include "gl/gl.h"
#include "pipeline/param_json.h"

#include <algorithm>

namespace app {

integrate::ViewPoints viewPointsOf(SceneStage& scene) {
    const irradiance::Settings& light = scene.settings().light;
    if (light.mode != irradiance::LightMode::Directional)
        throw core::Error("monte carlo", 0,
                          std::string("the Monte Carlo render has the directional light only; "
                                      "the scene's light is ") +
                              irradiance::lightModeName(light.mode));
    const render::Readback rb = scene.readback();
    integrate::ViewPoints view;
    view.width = rb.width;
    view.height = rb.height;
    view.position = rb.position;
    view.normal = rb.normal;
    view.camera = glm::dvec3(scene.settings().render.camera.position());
    view.lightDir = glm::dvec3(light.direction);
    view.irradiance = glm::dvec3(light.irradiance);
    return view;
}

bool MonteCarloStage::update(const MonteCarloInputs& in) {
    const MonteCarloSettings& s = in.settings;
    if (!s.enabled || !in.scene) return false;
    SceneStage& scene = *in.scene;
    const bssrdf::ModelEntry* e = in.model.entry;
    if (!e || !e->usable() || !scene.hasFrame() || !scene.hasMesh()) return false;
    const render::Settings& r = scene.settings().render;
    // the shown frame at full resolution, finished: its G-buffer gives the pixels
    if (scene.rendering() || scene.frame().width != r.width || scene.frame().height != r.height)
        return false;
    const irradiance::Settings& light = scene.settings().light;
    MonteCarloSettings keyed = s; // spp is a target the render runs to, not an input
    keyed.spp = 0;
    const std::string key = core::keyOf(r.camera, r.width, r.height, light, keyed) +
                            scene.meshHash() + std::to_string(e->generation) +
                            toJson(e->values).dump() + in.model.materialKey;
    bool changed = false;
    if (key != m_key) {
        m_key = key;
        m_integrator.reset();
        m_problem.clear();
        changed = true;
        try {
            const integrate::ViewPoints view = viewPointsOf(scene);
            m_integrator = std::make_unique<integrate::ImageIntegrator>(
                scene.mesh(), double(in.model.builtins.scale), scene.settings().meshFile, view);
            integrate::Settings is;
            is.sampling = s.sampling;
            is.axes = s.axes;
            is.seed = s.seed;
            m_integrator->setModel(e->programs.at("pencil_profile.comp").id(), *e->model, e->values,
                                   in.model.builtins, is, e->displayPath);
            m_slice = 1;
        } catch (const std::exception& err) {
            m_integrator.reset();
            m_problem = err.what();
        }
    }
    if (!m_integrator || m_integrator->samplesPerPixelDone() >= uint64_t(s.spp)) return changed;
    const int n = int(std::min<uint64_t>(uint64_t(m_slice),
                                         uint64_t(s.spp) - m_integrator->samplesPerPixelDone()));
    core::Stopwatch clock;
    m_integrator->step(n);
    const double ms = clock.ms();
    gl::recordTiming("monte carlo render", ms);
    if (in.budgetMs < 0)
        m_slice = 16;
    else if (ms < 0.5 * in.budgetMs)
        m_slice = std::min(m_slice * 2, 64);
    else if (ms > in.budgetMs)
        m_slice = std::max(m_slice / 2, 1);
    return true;
}

void MonteCarloStage::finish(MonteCarloInputs in) {
    in.budgetMs = -1;
    in.settings.enabled = true;
    update(in);
    while (m_integrator && m_integrator->samplesPerPixelDone() < uint64_t(in.settings.spp))
        if (!update(in)) break;
}

litsphere::Image MonteCarloStage::image() const {
    return m_integrator ? m_integrator->image() : litsphere::Image{};
}

StageStatus MonteCarloStage::status() const {
    StageStatus st;
    if (!m_problem.empty()) st.problems.push_back(m_problem);
    st.stats.emplace_back("spp", std::to_string(sppDone()));
    return st;
}

} // namespace app
