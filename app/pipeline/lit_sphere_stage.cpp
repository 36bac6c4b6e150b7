// Lit-sphere stage: progressive path-traced sphere in a background thread (see header).
#include "pipeline/lit_sphere_stage.h"

#include "core/core.h"
#include "pathtrace/sphere_tracer.h"
#include "pipeline/image_display.h"
#include "pipeline/reference_stage.h"

#include "core/fields.h"
#include <algorithm>

namespace app {

void PathTracedSphere::cancel() {
    m_cancel = true;
    if (m_thread.joinable()) m_thread.join();
    m_cancel = false;
}

void PathTracedSphere::wait() {
    if (m_thread.joinable()) m_thread.join();
}

void PathTracedSphere::start(const std::array<pathtrace::Medium, 3>& media,
                             const pathtrace::LitSphereSetup& s, int targetSpp, bool gpu,
                             const std::filesystem::path& mesh) {
    cancel();
    ++m_runs;
    {
        std::lock_guard lock(m_mutex);
        m_image = pathtrace::Image{};
        m_problem.clear();
        m_energy.clear();
    }
    m_sppDone = 0;
    m_rate = 0;
    m_target = targetSpp;
    m_useGpu = gpu && mesh.empty(); // the GL tracer knows the sphere only
    if (!mesh.empty() && (mesh != m_meshPath || !m_mesh)) {
        try {
            m_mesh = std::make_shared<const pathtrace::LitMesh>(pathtrace::loadLitMesh(mesh));
            m_meshPath = mesh;
        } catch (const core::Error& e) {
            m_mesh.reset();
            m_meshPath.clear();
            std::lock_guard lock(m_mutex);
            m_problem = e.what();
            return;
        }
    }
    std::shared_ptr<const pathtrace::LitMesh> meshToTrace = mesh.empty() ? nullptr : m_mesh;
    if (m_useGpu) {
        try {
            if (!m_gpu) m_gpu = std::make_unique<pathtrace::GpuSphereTracer>(m_gpuShader);
            pathtrace::LitSphereSetup p = s;
            p.samplesPerPixel = uint64_t(targetSpp);
            m_gpu->reset(media, p);
            m_pathsPerSpp = std::max<uint64_t>(1, m_gpu->targetPaths() / uint64_t(targetSpp));
        } catch (const core::Error& e) {
            m_problem = e.what();
        }
        return;
    }
    m_thread = std::thread([this, media, s, targetSpp, meshToTrace] {
        // passes of a few samples per pixel, each with its own seed: independent estimates
        // merged by sample count, so the picture sharpens while the user watches
        const int perPass = 2;
        core::Stopwatch clock;
        uint64_t paths = 0;
        for (int done = 0, pass = 0; done < targetSpp && !m_cancel; ++pass) {
            pathtrace::LitSphereSetup p = s;
            p.samplesPerPixel = uint64_t(std::min(perPass, targetSpp - done));
            p.seed = s.seed * 1000003ull + uint64_t(pass);
            p.threads =
                std::max(1u, std::thread::hardware_concurrency() - 1); // keep a core for the UI
            pathtrace::Image img;
            pathtrace::ImageStats st;
            try {
                img = meshToTrace
                          ? pathtrace::traceLitMesh(*meshToTrace, media, p, {}, &m_cancel, {}, &st)
                          : pathtrace::traceLitSphere(media, p, {}, &m_cancel, {}, &st);
            } catch (const core::Error& e) {
                std::lock_guard lock(m_mutex);
                m_problem = e.what();
                return;
            }
            if (m_cancel) break; // a cut pass is dropped: the image stays a merge of whole passes
            done += int(p.samplesPerPixel);
            paths += 3 * (meshToTrace ? meshToTrace->pathCount(p) : pathtrace::litSpherePaths(p));
            {
                std::lock_guard lock(m_mutex);
                m_image = combine(m_image, img);
                // every pass is checked on its own (a pass is an independent estimate)
                for (int c = 0; c < 3 && m_energy.empty(); ++c) {
                    const std::string e = pathtrace::energyProblem(st.channel[size_t(c)]);
                    if (!e.empty()) m_energy = std::string("channel ") + "RGB"[c] + ": " + e;
                }
            }
            m_sppDone = done;
            m_rate = double(paths) / std::max(1e-9, clock.ms() * 1e-3);
        }
    });
}

bool PathTracedSphere::stepGpu(double budgetMs) {
    if (!m_useGpu || !m_gpu || !m_problem.empty() || m_gpu->finished()) return false;
    core::Stopwatch clock;
    const double before = m_gpu->seconds();
    try {
        do {
            m_gpu->step(4096);
        } while (!m_gpu->finished() && clock.ms() < budgetMs);
    } catch (const core::Error& e) {
        std::lock_guard lock(m_mutex);
        m_problem = e.what();
    }
    m_sppDone = int(std::min<uint64_t>(m_gpu->pathsDone() / m_pathsPerSpp, uint64_t(m_target)));
    const double sec = m_gpu->seconds();
    m_rate = sec > 0 ? 3.0 * double(m_gpu->pathsDone()) / sec : 0.0;
    (void)before;
    return true;
}

void PathTracedSphere::reloadGpu() {
    if (!m_gpu) return;
    try {
        m_gpu->reload(); // success starts the image over
        m_shaderProblem.clear();
        m_sppDone = 0;
    } catch (const core::Error& e) {
        m_shaderProblem = e.what();
        core::logError("path tracer shader: " + m_shaderProblem + " (previous program kept)");
    }
}

bool PathTracedSphere::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    if (!m_gpu || !m_gpu->shaderRecord().dependencies.containsAny(changed)) return false;
    reloadGpu();
    return true;
}

shader::Records PathTracedSphere::shaderRecords() const {
    if (!m_gpu) return {};
    return {{m_gpuShader.filename().string(), m_gpu->shaderRecord()}};
}

pathtrace::Image PathTracedSphere::image() const {
    if (m_useGpu) return m_gpu && m_gpu->pathsDone() > 0 ? m_gpu->image() : pathtrace::Image{};
    std::lock_guard lock(m_mutex);
    return m_image;
}

std::string PathTracedSphere::problem() const {
    std::lock_guard lock(m_mutex);
    if (!m_problem.empty()) return m_problem;
    if (!m_shaderProblem.empty()) return m_shaderProblem;
    if (m_useGpu && m_gpu && m_gpu->pathsDone() > 1) {
        // the GL tracer tallies exits and truncations only: truncation against the error bar
        std::array<double, 3> exitedErr{};
        m_gpu->exitedPower(&exitedErr);
        const std::array<double, 3> truncated = m_gpu->truncatedPower();
        for (int c = 0; c < 3; ++c)
            if (truncated[size_t(c)] > exitedErr[size_t(c)])
                return std::string("channel ") + "RGB"[c] + ": paths truncated at the event " +
                       "limit: the image may miss up to " + std::to_string(truncated[size_t(c)]) +
                       " W, more than the standard error of the exited power";
    }
    return m_energy;
}

bool LitSphereStage::update(const LitSphereInputs& in) {
    const LitSphereSettings& ls = in.settings;
    if (!ls.enabled) {
        if (!m_key.empty()) m_pathTraced.cancel();
        restart();
        return false;
    }
    const bssrdf::ModelEntry* e = in.entry;
    if (!e || !in.params) return false;
    pathtrace::LitSphereSetup setup;
    setup.radiusMm = ls.radiusMm;
    for (int i = 0; i < 3; ++i)
        setup.lightDir[i] = ls.lightDir[i];
    setup.width = setup.height = ls.size;
    setup.seed = ls.seed;
    // integratedSpp is a target the integration runs to, not an input of its image
    LitSphereSettings keyed = ls;
    keyed.integratedSpp = 0;
    const std::string key =
        core::keyOf(e->displayPath, e->generation, in.materialKey, keyed, e->values);
    // the path tracer sees the medium and the scene only: a change of the model, its values or
    // the integration's sampling leaves its image running
    const std::string pathKey = core::keyOf(in.materialKey, ls.radiusMm, ls.lightDir, ls.size,
                                            ls.seed, ls.pathSpp, ls.gpu, ls.mesh);
    bool changed = false;
    if (key != m_key) {
        m_key = key;
        m_model = e->displayPath;
        m_problem.clear();
        try {
            std::filesystem::path mesh;
            if (!ls.mesh.empty()) {
                mesh = ls.mesh;
                if (mesh.is_relative()) mesh = in.root / mesh;
            }
            // Disk sampling, or any sampling of a mesh: the CPU + GPU integrator, made aside so
            // that a failure (a mesh that cannot be read, a profile or a model's own sampler
            // that cannot be sampled) keeps the last good integration and its image.
            std::unique_ptr<integrate::ImageIntegrator> probe;
            if (ls.sampling != integrate::Sampling::Uniform || !mesh.empty()) {
                probe = mesh.empty() ? std::make_unique<integrate::ImageIntegrator>(setup)
                                     : std::make_unique<integrate::ImageIntegrator>(
                                           setup, mesh::loadObj(mesh), mesh.string());
                integrate::Settings is;
                is.sampling = ls.sampling;
                is.axes = ls.axes;
                is.seed = ls.seed;
                // (re)builds the model's radial distributions for disk sampling (Timings): its
                // profile table, its analytic sampler or its lobes, checked
                probe->setModel(e->programs.at("pencil_profile.comp").id(), *e->model, e->values,
                                in.builtins, is, e->displayPath);
            } else {
                m_integrator.reset(setup);
            }
            m_probe = std::move(probe);
            if (pathKey != m_pathKey) {
                m_pathKey = pathKey;
                m_ptSppSeen = 0;
                m_pathTraced.start(mediaOf(*in.params), setup, ls.pathSpp, ls.gpu, mesh);
            }
        } catch (const core::Error& err) {
            m_problem = err.what();
            m_pathTraced.cancel();
            m_pathKey.clear();
        }
        changed = true;
    }
    if (!m_problem.empty()) return changed;
    try {
        changed |= stepIntegration(in);
    } catch (const core::Error& err) { // a model loop past its budget: the integration stops
        m_problem = err.what();        // here, with what it had (a new key starts it again)
        changed = true;
    }
    if (ls.gpu) m_pathTraced.stepGpu(in.budgetMs < 0 ? 1e9 : 0.5 * in.budgetMs);
    if (m_pathTraced.sppDone() != m_ptSppSeen) {
        m_ptSppSeen = m_pathTraced.sppDone();
        changed = true;
    }
    return changed;
}

bool LitSphereStage::stepIntegration(const LitSphereInputs& in) {
    const bssrdf::ModelEntry* e = in.entry;
    const LitSphereSettings& ls = in.settings;
    // a slice per frame, sized to stay near the budget (fixed slices in finish())
    const uint64_t done = integratedSppDone();
    if (done >= uint64_t(ls.integratedSpp)) return false;
    if (!m_probe && !e->programs.count("sphere_bssrdf.comp")) return false;
    const int n =
        int(std::min<uint64_t>(uint64_t(m_integratedSlice), uint64_t(ls.integratedSpp) - done));
    core::Stopwatch sw;
    if (m_probe) {
        m_probe->step(n);
        gl::recordTiming("sphere BSSRDF integration (probe rays)", sw.ms());
    } else {
        m_integrator.step(e->programs.at("sphere_bssrdf.comp").id(), *e->model, e->values,
                          in.builtins, n); // timed inside as "sphere BSSRDF integration"
    }
    const double ms = sw.ms();
    const int maxSlice = m_probe ? 256 : 4096;
    if (in.budgetMs < 0)
        m_integratedSlice = m_probe ? 64 : kFixedSlice; // fixed slices (finish)
    else if (ms < 0.5 * in.budgetMs)
        m_integratedSlice = std::min(m_integratedSlice * 2, maxSlice);
    else if (ms > in.budgetMs)
        m_integratedSlice = std::max(m_integratedSlice / 2, 1);
    return true;
}

void LitSphereStage::finish(LitSphereInputs in) {
    // restart and take fixed slices: the GPU sums then do not depend on frame timings, so the
    // same build and seed give bitwise the same images (captures rely on it)
    in.budgetMs = -1;
    restart();
    m_integratedSlice = kFixedSlice;
    update(in);
    while (in.settings.enabled && m_problem.empty() &&
           integratedSppDone() < uint64_t(in.settings.integratedSpp))
        if (!update(in)) break;
    m_pathTraced.wait();
}

StageStatus LitSphereStage::status() const {
    StageStatus st;
    if (m_key.empty()) return st;
    if (!m_problem.empty()) st.problems.push_back(m_problem);
    if (std::string pt = m_pathTraced.problem(); !pt.empty()) st.problems.push_back(pt);
    st.running = m_pathTraced.sppDone() < m_pathTraced.sppTarget();
    st.progress = m_pathTraced.sppTarget() > 0
                      ? double(m_pathTraced.sppDone()) / double(m_pathTraced.sppTarget())
                      : 1.0;
    st.stats.push_back({"path traced spp", std::to_string(m_pathTraced.sppDone())});
    st.stats.push_back({"integrated spp", std::to_string(integratedSppDone())});
    return st;
}

shader::Records LitSphereStage::shaderRecords() const {
    shader::Records out;
    for (const auto& [name, record] : m_pathTraced.shaderRecords())
        out["lit sphere:" + name] = record;
    return out;
}

void LitSphereStage::capture(const LitSphereInputs& in, CaptureEntries& out) {
    if (!in.settings.enabled) return;
    if (const std::string& mesh = in.settings.mesh; !mesh.empty()) {
        // the mesh is an input like the models: path (relative to the root) and content hash
        const std::string text = core::readFile(in.root / mesh);
        out.inputs.push_back({mesh, core::hashHex(text),
                              text.size() < (1u << 20)
                                  ? text
                                  : "(mesh, " + std::to_string(text.size()) + " bytes)"});
    }
    finish(in);
    if (const std::string p = problem(); !p.empty()) throw core::Error("lit spheres", 0, p);
    const std::string what = in.settings.mesh.empty() ? "lit_sphere" : "lit_mesh";
    for (const bool traced : {true, false}) {
        CaptureEntry e = captureEntry(CaptureEntry::Kind::ExrStat,
                                      what + (traced ? ".path_traced" : ".integrated"));
        e.image = traced ? m_pathTraced.image() : integratedImage();
        e.alpha = kMonteCarloAlpha;
        e.note = "Monte Carlo image: per-pixel z-test, Bonferroni over all pixels and channels";
        out.entries.push_back(std::move(e));
    }
}

} // namespace app
