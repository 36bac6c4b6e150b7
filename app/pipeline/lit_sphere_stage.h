// Lit-sphere stage (thesis 3.5, 3.6.2): the same sphere, light and camera (pathtrace/
// lit_sphere.h) rendered two ways, progressively:
//   - path traced: the volumetric tracer in a background thread, in passes of a few samples
//     per pixel merged as independent estimates (the UI never waits);
//   - BSSRDF integrated: the selected model's Bssrdf() integrated over the sphere by uniform
//     area sampling on the GPU (shaders/sphere_bssrdf.comp), a slice per frame on the GL
//     thread.
#pragma once

#include "core/limits.h"
#include "pipeline/stage.h"

#include "bssrdf/program_library.h"
#include "bssrdf/sphere_integrator.h"
#include "integrate/integrate.h"
#include "material/material.h"
#include "pathtrace/gpu_sphere.h"
#include "pathtrace/lit_sphere.h"
#include "pathtrace/mesh_tracer.h"
#include "pathtrace/pathtrace.h"

#include <glm/vec3.hpp>

#include <array>
#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

namespace app {

struct LitSphereSettings {
    bool enabled = false;
    double radiusMm = 10.0;
    glm::vec3 lightDir{0.5f, 0.5f, 0.7071f}; // towards the light
    int size = 128;                          // square image
    int pathSpp = 64;                        // path tracer target, samples per pixel
    int integratedSpp = 4096;                // BSSRDF integration target, samples per pixel
    uint64_t seed = 1;
    bool gpu = false; // path trace on the GL compute tracer (sliced per frame) instead of the CPU
    std::string mesh; // OBJ path: path trace this mesh (CPU, Embree) instead of the sphere
    // BSSRDF integration: uniform area sampling (on the sphere: the GPU pass) or disk probe rays
    // (integrate/integrate.h); the defaults are the estimator's own
    integrate::Sampling sampling = integrate::Settings{}.sampling;
    sampling::AxisScheme axes = integrate::Settings{}.axes;
};
// The description of LitSphereSettings' members (core/fields.h).
template <class V> void fields(V& v, LitSphereSettings& s) {
    v("enabled", s.enabled, "render the lit spheres");
    v("radius_mm", s.radiusMm, "sphere radius, mm", core::Limits{1e-3, 1e4});
    v("light", s.lightDir, "direction towards the light");
    v("size", s.size, "image side in pixels", core::Limits{8, 4096});
    v("path_spp", s.pathSpp, "path tracer samples per pixel", core::Limits{1, 1e7});
    v("integrated_spp", s.integratedSpp, "BSSRDF integration samples per pixel",
      core::Limits{1, 1e8});
    v("seed", s.seed, "random seed");
    v("gpu", s.gpu, "GL compute path tracer instead of the CPU");
    v("mesh", s.mesh, "OBJ to path trace and integrate instead of the sphere (empty: sphere)");
    v("sampling", s.sampling, "BSSRDF integration: uniform area sampling or disk probe rays");
    v("axes", s.axes, integrate::kAxesHelp);
}

// The path-traced sphere: CPU passes in a background thread, or the GL compute tracer
// (shaders/pathtrace_sphere.comp) stepped from the GL thread with stepGpu().
class PathTracedSphere {
  public:
    explicit PathTracedSphere(std::filesystem::path gpuShader)
        : m_gpuShader(std::move(gpuShader)) {}
    ~PathTracedSphere() { cancel(); }
    void start(const std::array<pathtrace::Medium, 3>& media, const pathtrace::LitSphereSetup& s,
               int targetSpp, bool gpu = false, const std::filesystem::path& mesh = {});
    // GPU mode: traces for about `budgetMs` (GL thread); returns true when paths were added.
    bool stepGpu(double budgetMs);
    // A path tracer shader changed: recompile; on error the old program keeps running.
    void reloadGpu();
    // Hot reload: reloadGpu() when one of `changed` is a file the GPU program was built from.
    bool reloadShaders(const std::vector<std::filesystem::path>& changed);
    shader::Records shaderRecords() const; // the GPU tracer's program, once created
    void cancel();
    void wait();
    pathtrace::Image image() const;
    int sppDone() const { return m_sppDone.load(); }
    int sppTarget() const { return m_target; }
    double pathsPerSecond() const { return m_rate.load(); }
    std::string problem() const;
    // How many runs start() began (a run restarts the image from no paths).
    long long runs() const { return m_runs; }

  private:
    long long m_runs = 0;
    std::thread m_thread;
    std::atomic<bool> m_cancel{false};
    std::atomic<int> m_sppDone{0};
    std::atomic<double> m_rate{0};
    int m_target = 0;
    mutable std::mutex m_mutex;
    pathtrace::Image m_image;
    std::string m_problem;
    std::string m_energy; // the first failed energy check of a CPU pass (pathtrace::energyProblem)
    std::filesystem::path m_gpuShader;
    std::unique_ptr<pathtrace::GpuSphereTracer> m_gpu;
    bool m_useGpu = false;
    uint64_t m_pathsPerSpp = 1;
    std::string m_shaderProblem;
    std::shared_ptr<const pathtrace::LitMesh> m_mesh; // loaded mesh (kept while the path stays)
    std::filesystem::path m_meshPath;
};

// Both lit spheres as one stage of the workbench. Inputs: the source model (the same one the
// reference and the scene use) with its material, the settings, the project root (relative
// mesh paths) and the time budget of this update's GPU slices (< 0: fixed slices, so the GPU
// sums do not depend on frame timings — captures rely on it).
struct LitSphereInputs {
    const bssrdf::ModelEntry* entry = nullptr; // none: no usable model, nothing runs
    std::optional<material::MaterialParams> params;
    bssrdf::Builtins builtins;
    std::string materialKey;
    LitSphereSettings settings;
    std::filesystem::path root;
    double budgetMs = 8.0;
};

class LitSphereStage : public StageOf<LitSphereInputs> {
  public:
    explicit LitSphereStage(std::filesystem::path gpuShaderFile)
        : m_pathTraced(std::move(gpuShaderFile)) {}
    const char* name() const override { return "lit sphere"; }
    bool update(const LitSphereInputs& in) override;
    StageStatus status() const override;
    void cancel() override { m_pathTraced.cancel(); }
    // Restarts and runs both renderings to their targets (tests, captures).
    void finish(LitSphereInputs in);
    // Captures (when enabled): the mesh as an input when one is traced, then both renderings
    // run to their targets, lit_sphere.* (or lit_mesh.*) .path_traced and .integrated, EXR with
    // a variance per pixel (per-pixel z-tests on replay). core::Error with the stage's problem
    // (a refused mesh, a bad setup), never a consequence such as an empty image.
    void capture(const LitSphereInputs& in, CaptureEntries& out);
    // Both renderings start again at the next update.
    void restart() {
        m_key.clear();
        m_pathKey.clear();
    }
    // The GPU path tracer's program ("lit sphere:PROGRAM").
    bool reloadShaders(const std::vector<std::filesystem::path>& changed) override {
        return m_pathTraced.reloadShaders(changed);
    }
    shader::Records shaderRecords() const override;

    const PathTracedSphere& pathTracer() const { return m_pathTraced; }
    PathTracedSphere& pathTracer() { return m_pathTraced; }
    pathtrace::Image integratedImage() const {
        return m_probe ? m_probe->image() : m_integrator.image();
    }
    uint64_t integratedSppDone() const {
        return m_probe ? m_probe->samplesPerPixelDone() : m_integrator.samplesPerPixelDone();
    }
    const std::string& model() const { return m_model; }
    // The first problem: a bad setup, else the path tracer's own (e.g. a mesh it refused).
    std::string problem() const { return !m_problem.empty() ? m_problem : m_pathTraced.problem(); }

  private:
    PathTracedSphere m_pathTraced;
    bssrdf::SphereIntegrator m_integrator;               // uniform sampling of the sphere (GPU)
    std::unique_ptr<integrate::ImageIntegrator> m_probe; // otherwise: disk, or a mesh
    // One integration step within the budget; true when samples were added.
    bool stepIntegration(const LitSphereInputs& in);
    std::string m_key, m_model, m_problem;
    std::string m_pathKey; // the path tracer's inputs: the medium and the scene
    int m_ptSppSeen = 0;
    int m_integratedSlice = 16;
    static constexpr int kFixedSlice = 256;
};

} // namespace app
