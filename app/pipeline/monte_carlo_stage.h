// The Monte Carlo render of the Render panel (a renderer beside hierarchical and brute force):
// the shown frame's view of the mesh, every pixel's radiance integrated by probe-ray importance
// sampling (King et al. 2013) or uniform area sampling of entry points with direct light and
// shadow rays through Embree (integrate/integrate.h, ViewPoints: the point-cloud renderer's
// conventions, Fresnel terms and light), progressive within the frame budget, with a standard
// error per pixel. It starts over when the shown full-resolution frame, the model, its material
// or the light change, and waits while a new frame is being rendered. The directional light
// only: the IBL modes have no Monte Carlo counterpart here (a problem says so).
#pragma once

#include "core/limits.h"
#include "integrate/integrate.h"
#include "pipeline/scene_stage.h"
#include "pipeline/stage.h"

#include <memory>
#include <string>
#include <vector>

namespace app {

struct MonteCarloSettings {
    bool enabled = false; // the GUI sets it while the Render panel shows this renderer
    integrate::Sampling sampling = integrate::Sampling::Disk;
    sampling::AxisScheme axes = integrate::Settings{}.axes;
    int spp = 256; // target samples per pixel
    uint64_t seed = 1;
};
template <class V> void fields(V& v, MonteCarloSettings& s) {
    v("enabled", s.enabled, "Monte Carlo render of the Render panel's view");
    v("sampling", s.sampling, "entry points by disk probe rays or uniform area sampling");
    v("axes", s.axes, integrate::kAxesHelp);
    v("spp", s.spp, "target samples per pixel", core::Limits{1, 1e7});
    v("seed", s.seed, "random seed");
}

// The shading points, camera and directional light of a finished frame of `scene` (its
// read-back G-buffer), in the renderer's conventions. Throws core::Error when the light is not
// directional.
integrate::ViewPoints viewPointsOf(SceneStage& scene);

struct MonteCarloInputs {
    MonteCarloSettings settings;
    SceneStage* scene = nullptr;
    SceneModelInput model;
    double budgetMs = 20.0; // < 0: run to the target (finish)
};

class MonteCarloStage : public StageOf<MonteCarloInputs> {
  public:
    const char* name() const override { return "monte carlo"; }
    bool update(const MonteCarloInputs& in) override;
    StageStatus status() const override;
    // Runs to the target on the current frame (CLI, tests, bench).
    void finish(MonteCarloInputs in);
    bool active() const { return m_integrator != nullptr; }
    litsphere::Image image() const; // L_o per pixel with the variance of the mean
    uint64_t sppDone() const { return m_integrator ? m_integrator->samplesPerPixelDone() : 0; }
    double seconds() const { return m_integrator ? m_integrator->seconds() : 0; }
    const std::string& problem() const { return m_problem; }

  private:
    std::unique_ptr<integrate::ImageIntegrator> m_integrator;
    std::string m_key, m_problem;
    int m_slice = 1;
};

} // namespace app
