// The mesh rendering pipeline as a stage graph (scene_stage.h).
#include "pipeline/scene_stage.h"

#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"
#include "render/frame_analysis.h"

#include <chrono>

namespace app {
namespace fs = std::filesystem;

namespace {

double nowSeconds() {
    return core::secondsSinceStart();
}

} // namespace

SceneStage::SceneStage(fs::path root) : m_root(std::move(root)) {}

SceneStage::~SceneStage() {
    if (m_pending.valid()) m_pending.wait();
}

fs::path SceneStage::resolve(const std::string& file) const {
    fs::path p(file);
    return p.is_absolute() ? p : m_root / p;
}

// A problem is reported once, by whoever shows the stage's problems (the Errors panel, or the
// command that fails on it); the log keeps it at info level.
void SceneStage::setProblem(const std::string& stage, const std::string& text) {
    m_problems[stage] = text;
    core::logInfo(stage + ": " + text);
}
void SceneStage::clearProblem(const std::string& stage) {
    m_problems.erase(stage);
}

std::vector<std::string> SceneStage::problems() const {
    std::map<std::string, std::string> all = m_problems;
    if (!m_comparison.problem().empty()) all["brute force"] = m_comparison.problem();
    std::vector<std::string> out;
    for (const auto& [stage, text] : all)
        out.push_back(stage + ": " + text);
    return out;
}

void SceneStage::ensureGl() {
    if (!m_irradiance_stage)
        m_irradiance_stage = std::make_unique<irradiance::Stage>(m_root / "shaders");
    if (!m_renderer) m_renderer = std::make_unique<render::Renderer>(shader::Sources{m_root});
}

void SceneStage::setGivenGbuffer(std::optional<render::Gbuffer> g) {
    ensureGl();
    m_renderer->setGivenGbuffer(std::move(g));
    m_renderKey.clear();
}

void SceneStage::setGivenIrradiance(std::optional<std::vector<glm::vec3>> e) {
    m_givenIrradiance = std::move(e);
    ++m_givenIrradianceVersion; // computed and adopted again at the next update or finish
}

std::string SceneStage::meshHash() const {
    if (!m_mesh) return "";
    std::string bytes;
    bytes.append(reinterpret_cast<const char*>(m_mesh->vertices.data()),
                 m_mesh->vertices.size() * sizeof(m_mesh->vertices[0]));
    bytes.append(reinterpret_cast<const char*>(m_mesh->triangles.data()),
                 m_mesh->triangles.size() * sizeof(m_mesh->triangles[0]));
    return core::hashHex(bytes);
}

bool SceneStage::updateMesh() {
    const std::string key = m_settings.meshFile;
    if (key == m_meshKey) return false;
    m_meshKey = key;
    core::Stopwatch clock;
    try {
        const fs::path file = resolve(key);
        mesh::Mesh m = mesh::loadObj(file);
        const mesh::RenderablePrep prep = mesh::prepareRenderable(m, key);
        if (prep.droppedDegenerate)
            core::logWarn(key + ": dropped " + std::to_string(prep.droppedDegenerate) +
                          " degenerate (zero-area) triangles");
        ensureGl();
        const bool same = m_mesh && m_mesh->vertices == m.vertices &&
                          m_mesh->triangles == m.triangles && m_mesh->normals == m.normals;
        if (same) { // reloaded with the same content: nothing downstream changes
            clearProblem("mesh");
            return false;
        }
        // The renderer gets the mesh together with its point cloud (applyCloud), so the frame
        // never mixes the new surface with the old cloud while the new one is generated.
        m_mesh = std::move(m);
        ++m_meshVersion;
        if (!m_cameraFitted) {
            m_settings.render.camera.fit(*m_mesh);
            m_cameraFitted = true;
        }
        clearProblem("mesh");
    } catch (const std::exception& e) {
        setProblem("mesh", e.what());
        return false;
    }
    StageStat& st = m_stats["scene.mesh"];
    st.ms = clock.ms();
    ++st.runs;
    gl::recordTiming("scene.mesh", st.ms);
    return true;
}

double SceneStage::generatingSeconds() const {
    return m_pending.valid() ? nowSeconds() - m_pendingStart : 0.0;
}

void SceneStage::reloadFiles() {
    m_meshKey.clear();
    m_envTried = "\n(reload)";
    m_texTried = "\n(reload)";
    if (!m_settings.pointCloudFile.empty()) m_cloudKey.clear();
}

void SceneStage::cancelPointCloud() {
    // The generation itself cannot be interrupted; its result is dropped (the key is cleared so
    // the next update does not adopt it).
    if (m_pending.valid()) {
        std::thread([f = std::move(m_pending)]() mutable { f.wait(); }).detach();
        m_cloudKey = "(cancelled)";
        core::logInfo("point cloud generation cancelled");
    }
}

void SceneStage::applyCloud(pointcloud::PointCloud cloud, bool fromCache, double ms) {
    std::vector<glm::vec3> pos(cloud.points.size()), nor(cloud.points.size());
    std::vector<float> area(cloud.points.size());
    for (size_t i = 0; i < cloud.points.size(); ++i) {
        const auto& p = cloud.points[i];
        pos[i] = {p.p[0], p.p[1], p.p[2]};
        nor[i] = {p.n[0], p.n[1], p.n[2]};
        area[i] = p.area;
    }
    octree::Octree tree;
    {
        gl::ScopedStageTimer t("scene.octree");
        tree = octree::build(pos, nor, area); // throws: the previous cloud and tree stay
    }
    ensureGl();
    m_irradiance_stage->setScene(*m_mesh, pos, nor);
    m_renderer->setMesh(*m_mesh);
    m_renderer->setOctree(tree);
    StageStat& ot = m_stats["scene.octree"];
    ot.ms = tree.stats.buildMs;
    ++ot.runs;
    m_tree = std::move(tree);
    m_cloud = std::move(cloud);
    m_cloudFromCache = fromCache;
    m_uniformity = pointcloud::measureUniformity(m_cloud);
    StageStat& pc = m_stats["scene.pointcloud"];
    pc.ms = ms;
    ++pc.runs;
    gl::recordTiming("scene.pointcloud", ms);
    ++m_cloudVersion;
    m_irradiance.clear();
}

bool SceneStage::updatePointCloud(bool wait) {
    if (!m_mesh) return false;
    const pointcloud::GenerateOptions& o = m_settings.points;
    const std::string key = core::keyOf(m_meshVersion, m_settings.pointCloudFile, o);
    bool changed = false;
    if (key != m_cloudKey) {
        m_cloudKey = key;
        if (m_pending.valid()) {
            cancelPointCloud();
            m_cloudKey = key;
        }
        try {
            if (!m_settings.pointCloudFile.empty()) {
                core::Stopwatch clock;
                pointcloud::PointCloud c = pointcloud::readPly(resolve(m_settings.pointCloudFile));
                if (c.points.empty())
                    throw core::Error(m_settings.pointCloudFile, 0, "the point cloud is empty");
                if (c.points.size() > octree::kMaxIndex + 1u)
                    throw core::Error(m_settings.pointCloudFile, 0,
                                      "more than 2^24 points (the octree's 24-bit index)");
                applyCloud(std::move(c), false, clock.ms());
                clearProblem("point cloud");
                return true;
            }
            pointcloud::checkOptions(o);
            const fs::path cache = m_settings.useCache ? pointcloud::defaultCacheDir() : fs::path();
            m_pendingStart = nowSeconds();
            m_cloudProgress->store(0);
            m_pending =
                std::async(std::launch::async, [m = *m_mesh, o, cache, p = m_cloudProgress] {
                    return pointcloud::generate(m, o, cache, [p](int done, int total) {
                        p->store(double(done) / double(total));
                    });
                });
        } catch (const std::exception& e) {
            setProblem("point cloud", e.what());
            return false;
        }
    }
    if (!m_pending.valid()) return false;
    if (!wait && m_pending.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
        return false;
    if (wait && m_finishProgress)
        while (m_pending.wait_for(std::chrono::milliseconds(200)) != std::future_status::ready)
            m_finishProgress("point cloud", m_cloudProgress->load());
    try {
        pointcloud::Generated g = m_pending.get();
        applyCloud(std::move(g.cloud), g.fromCache, g.milliseconds);
        clearProblem("point cloud");
        changed = true;
    } catch (const std::exception& e) {
        setProblem("point cloud", e.what());
    }
    return changed;
}

bool SceneStage::updateIrradiance(float ior, bool finishOccluded) {
    if (!m_tree || !m_irradiance_stage) return false;
    irradiance::Stage& st = *m_irradiance_stage;
    // the user's light with the rendered material's η: E_t carries Ft(η) (an input, never
    // written back into the user's settings)
    irradiance::Settings s = m_settings.light;
    s.ior = ior;
    const bool ibl =
        s.mode == irradiance::LightMode::Ibl || s.mode == irradiance::LightMode::OccludedIbl;
    // Environment / projected texture files (loaded when named and changed).
    // m_envTried / m_texTried: the file last attempted (not retried every frame);
    // m_envLoads / m_texLoads: successful loads (what the irradiance depends on).
    if (ibl && m_settings.environmentFile != m_envTried) {
        m_envTried = m_settings.environmentFile;
        try {
            st.loadEnvironment(resolve(m_envTried));
            ++m_envLoads;
            clearProblem("environment");
        } catch (const std::exception& e) {
            setProblem("environment", e.what());
        }
    }
    if (s.mode == irradiance::LightMode::Filtered &&
        m_settings.projectedTextureFile != m_texTried) {
        m_texTried = m_settings.projectedTextureFile;
        try {
            if (m_texTried.empty())
                st.useCheckerTexture();
            else
                st.loadProjectedTexture(resolve(m_texTried));
            ++m_texLoads;
            clearProblem("projected texture");
        } catch (const std::exception& e) {
            setProblem("projected texture", e.what());
        }
    }
    const std::string key = core::keyOf(m_cloudVersion, s, ibl ? m_envLoads : 0,
                                        s.mode == irradiance::LightMode::Filtered ? m_texLoads : 0,
                                        m_irradianceBuilds, m_givenIrradianceVersion);
    bool changed = false;
    auto adopt = [&](std::vector<glm::vec3> e, double ms) {
        const bool given = m_givenIrradiance && m_givenIrradiance->size() == e.size();
        if (m_givenIrradiance && !given)
            setProblem("given irradiance", std::to_string(m_givenIrradiance->size()) +
                                               " values for " + std::to_string(e.size()) +
                                               " points");
        else
            clearProblem("given irradiance");
        octree::setIrradiance(*m_tree, given ? *m_givenIrradiance : e);
        m_renderer->updateAttributes(*m_tree);
        m_irradiance = std::move(e);
        ++m_irrVersion;
        StageStat& stat = m_stats["scene.irradiance"];
        stat.ms = ms;
        ++stat.runs;
        changed = true;
    };
    if (key != m_irrKey) {
        m_irrKey = key;
        if (st.occludedRunning()) st.cancelOccluded();
        m_occludedActive = false;
        m_occludedRelError = glm::vec3(0.0f);
        m_occludedDone = m_occludedTotal = 0;
        try {
            core::Stopwatch clock;
            if (ibl && !st.hasEnvironment())
                throw core::Error(m_settings.environmentFile, 0, "no environment map loaded");
            if (s.mode == irradiance::LightMode::OccludedIbl) {
                st.beginOccluded(s);
                m_occludedActive = true;
            } else {
                std::vector<glm::vec3> e;
                {
                    gl::ScopedStageTimer t("scene.irradiance");
                    e = st.compute(s);
                    glFinish();
                }
                adopt(std::move(e), clock.ms());
            }
            clearProblem("irradiance");
        } catch (const std::exception& e) {
            setProblem("irradiance", e.what());
        }
    }
    if (m_occludedActive) {
        try {
            core::Stopwatch clock;
            bool done = false;
            do {
                gl::ScopedStageTimer t("scene.irradiance");
                done = st.stepOccluded();
                glFinish();
            } while (finishOccluded && !done);
            if (done) m_occludedActive = false;
            std::vector<glm::vec3> e = st.occludedResult();
            if (!e.empty()) {
                glm::dvec3 error(0.0), sum(0.0);
                const std::vector<glm::vec3> se = st.occludedStdError();
                for (size_t i = 0; i < e.size() && i < se.size(); ++i) {
                    error += glm::dvec3(se[i]);
                    sum += glm::dvec3(e[i]);
                }
                for (int c = 0; c < 3; ++c)
                    m_occludedRelError[c] = sum[c] > 0 ? float(error[c] / sum[c]) : 0.0f;
                m_occludedDone = st.occludedSamplesDone();
                m_occludedTotal = st.occludedSamplesTotal();
                adopt(std::move(e), clock.ms());
            }
        } catch (const std::exception& e) {
            m_occludedActive = false;
            setProblem("irradiance", e.what());
        }
    }
    return changed;
}

float SceneStage::occludedProgress() const {
    return m_occludedTotal > 0 ? float(m_occludedDone) / float(m_occludedTotal) : 0.0f;
}
bool SceneStage::occludedRunning() const {
    return m_occludedActive;
}
void SceneStage::cancelOccluded() {
    if (m_irradiance_stage && m_occludedActive) m_irradiance_stage->cancelOccluded();
    m_occludedActive = false;
}

bool SceneStage::updateRender(const SceneModelInput& model, bool interacting, bool finishNow) {
    if (!m_tree || !m_renderer || !model.entry || !model.entry->model || m_irradiance.empty())
        return false;
    const bssrdf::ModelEntry& e = *model.entry;
    // Model programs: built again when the model changes (a changed shader file rebuilds them
    // through reloadShaders); a failure keeps the old.
    const std::string modelKey = core::keyOf(e.displayPath, e.modelGeneration);
    if (modelKey != m_modelKey) {
        // A changed model reaches the renderer one update later than the rest (not when
        // finishing): its first dispatch makes the driver generate the traversal program's code
        // (about 1 s on llvmpipe), and the frame in between shows the pencil plot's new pixels.
        // While the check's server generates that code (and the driver's shader cache then
        // hands it over), the model waits for it.
        if (!finishNow && (m_deferredModelKey != modelKey || model.codePending)) {
            m_deferredModelKey = modelKey;
            return false;
        }
        m_modelKey = modelKey;
        try {
            m_renderer->setModel(*e.model);
            clearProblem("render");
        } catch (const std::exception& ex) {
            setProblem("render", ex.what());
        }
    }
    if (!m_renderer->ready()) return false;
    const bool half = interacting && m_settings.halfResolutionWhileChanging;
    render::Settings rs = m_settings.render;
    if (half) {
        rs.width = std::max(1, rs.width / 2);
        rs.height = std::max(1, rs.height / 2);
    }
    const std::string key = core::keyOf(m_irrVersion, m_modelKey, m_renderBuilds, model.materialKey,
                                        rs, e.values, model.builtins);
    try {
        if (key != m_renderKey) {
            m_renderKey = key;
            m_renderer->setMaterial(e.values, model.builtins);
            m_comparison.setFrameModel(*e.model, e.values, model.builtins);
            // Interactive frames are sliced into short dispatches so the UI keeps running.
            if (!finishNow) rs.iterationsPerDispatch = kInteractiveIterations;
            m_renderer->begin(rs);
            m_comparison.setFrameSettings(rs);
            m_renderClock.reset();
            clearProblem("render settings");
        }
        if (!m_renderer->inProgress()) return false;
        if (!m_renderer->advance(finishNow ? 1e30 : kFrameBudgetMs)) return false;
        adoptFrame();
    } catch (const std::exception& ex) {
        setProblem("render settings", ex.what());
        return false;
    }
    return true;
}

bool SceneStage::update(const SceneModelInput& model, bool interacting) {
    if (!m_settings.enabled) return false;
    bool changed = updateMesh();
    changed |= updatePointCloud(false);
    changed |= updateIrradiance(lightIor(model), false);
    changed |= updateRender(model, interacting, false);
    changed |= m_comparison.advance(kFrameBudgetMs);
    return changed;
}

void SceneStage::finish(const SceneModelInput& model, const FinishProgress& progress) {
    m_finishProgress = progress;
    auto step = [&](const char* name) {
        if (progress) progress(name, -1.0);
    };
    // a step without its input (no mesh ever loaded, no cloud) has nothing to run: not announced
    step("mesh");
    updateMesh();
    if (m_mesh) {
        step("point cloud");
        updatePointCloud(true);
    }
    if (!m_cloud.points.empty()) {
        step("irradiance");
        updateIrradiance(lightIor(model), true);
        step("render");
        updateRender(model, false, true);
    }
    m_finishProgress = {};
}

bool SceneStage::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    std::string problem;
    auto note = [&](const shader::Reloaded& r) {
        if (problem.empty()) problem = r.problem;
        return r.rebuilt > 0 || !r.problem.empty();
    };
    bool attempted = false;
    if (m_irradiance_stage) {
        const shader::Reloaded r = m_irradiance_stage->reloadShaders(changed);
        attempted |= note(r);
        m_irradianceBuilds += r.rebuilt;
    }
    if (m_renderer) {
        const shader::Reloaded r = m_renderer->reloadShaders(changed);
        attempted |= note(r);
        m_renderBuilds += r.rebuilt;
    }
    attempted |= note(m_comparison.reloadShaders(changed));
    if (!attempted) return false;
    if (problem.empty())
        clearProblem("shaders");
    else
        setProblem("shaders", problem);
    return true;
}

shader::Records SceneStage::shaderRecords() const {
    shader::Records out;
    auto add = [&](const std::string& owner, const shader::Records& records) {
        for (const auto& [name, record] : records)
            out[owner + ":" + name] = record;
    };
    if (m_renderer) add("render", m_renderer->shaderRecords());
    if (m_irradiance_stage) add("irradiance", m_irradiance_stage->shaderRecords());
    add("brute force", m_comparison.shaderRecords());
    return out;
}

pathtrace::Image hdrImage(const render::Readback& rb) {
    pathtrace::Image img;
    img.width = rb.width;
    img.height = rb.height;
    const size_t pixels = size_t(rb.width) * size_t(rb.height);
    img.mean.resize(3 * pixels);
    img.variance.assign(3 * pixels, 0.0f);
    img.samples = 1;
    for (size_t p = 0; p < pixels; ++p)
        for (int c = 0; c < 3; ++c)
            img.mean[3 * p + size_t(c)] = rb.hdr[p][c];
    return img;
}

render::Readback SceneStage::readback() const {
    if (!m_renderer || !hasFrame()) return {};
    return m_renderer->readback();
}

PixelDebug SceneStage::debugPixel(int x, int y) {
    if (!hasFrame() || !m_tree || !m_renderer)
        throw core::Error("debugger", 0, "no rendered frame to debug yet");
    if (m_renderer->inProgress())
        throw core::Error("debugger", 0, "a frame is still rendering; click again when it is done");
    render::Readback rb = m_renderer->readback();
    if (x < 0 || y < 0 || x >= rb.width || y >= rb.height)
        throw core::Error("debugger", 0,
                          "pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                              ") is outside the " + std::to_string(rb.width) + "x" +
                              std::to_string(rb.height) + " frame");
    PixelDebug d;
    d.x = x;
    d.y = y;
    const size_t p = rb.index(x, y);
    d.hit = rb.position[p].w > 0.5f;
    if (!d.hit) return d;
    const glm::vec3 xo(rb.position[p]), no(rb.normal[p]);
    d.gpuExitance = glm::vec3(rb.exitance[p]);
    d.gpuStats = rb.stats[p];
    const float scale = m_renderer->builtins().scale;
    render::Settings rs = m_settings.render;
    d.trace = octree::traverse(*m_tree, xo, no, rs.criterion());
    std::vector<glm::vec3> values = m_renderer->evaluatePairs(render::tracePairs(d.trace, scale));
    octree::accumulate(d.trace, values, scale);
    // Brute force at this pixel: every point in slot order, the shader's formula.
    d.bruteExitance = render::bruteForceExitance(
        *m_tree, m_renderer->evaluatePairs(render::allPointPairs(*m_tree, xo, no, scale)), scale);
    return d;
}

void SceneStage::adoptFrame() {
    m_frame = m_renderer->currentFrame();
    if (m_displayW != m_frame.width || m_displayH != m_frame.height || !m_displayLdr.id()) {
        GLuint id = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &id);
        glTextureStorage2D(id, 1, GL_RGBA8, m_frame.width, m_frame.height);
        glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        m_displayLdr = gl::Texture(id);
        m_displayW = m_frame.width;
        m_displayH = m_frame.height;
    }
    glCopyImageSubData(m_frame.ldr, GL_TEXTURE_2D, 0, 0, 0, 0, m_displayLdr.id(), GL_TEXTURE_2D, 0,
                       0, 0, 0, m_frame.width, m_frame.height, 1);
    m_frame.ldr = m_displayLdr.id();
    // NaN, Inf or negative radiance is counted, named after the model, never passed off as black
    const std::string bad = render::invalidPixelsProblem(m_frame.invalid);
    const bssrdf::Model* model = m_comparison.frameModel();
    const std::string text = (model ? model->path + ": " : std::string()) + bad;
    if (bad.empty())
        clearProblem("render values");
    else if (auto it = m_problems.find("render values");
             it == m_problems.end() || it->second != text)
        setProblem("render values", text);
    StageStat& st = m_stats["scene.render"];
    st.ms = m_renderClock.ms();
    ++st.runs;
    m_comparison.frameShown(m_frame.width, m_frame.height);
}

glm::vec3 SceneStage::exitanceAt(const glm::vec3& xo, const glm::vec3& no) {
    if (!m_tree || !m_renderer || !m_renderer->ready() || m_irradiance.empty())
        throw core::Error("point cloud", 0, "no rendered scene yet");
    const float scale = m_renderer->builtins().scale;
    octree::Trace t = octree::traverse(*m_tree, xo, no, m_settings.render.criterion());
    octree::accumulate(t, m_renderer->evaluatePairs(render::tracePairs(t, scale)), scale);
    return t.radiantExitance;
}

std::vector<glm::vec4> SceneStage::bruteForceExitance() {
    if (m_renderer && m_renderer->inProgress()) {
        m_renderer->advance(1e30);
        adoptFrame();
    }
    m_comparison.requestBruteForce();
    m_comparison.advance(1e30);
    if (const auto* r = m_comparison.bruteForceResult()) return *r;
    throw core::Error("render", 0, "the brute-force pass failed (see Errors)");
}

StageStatus SceneStage::status() const {
    StageStatus st;
    st.problems = problems();
    st.running = generating() || rendering();
    if (generating()) st.progress = generatingProgress();
    for (const auto& [name, stat] : m_stats)
        st.stats.push_back(
            {name, std::to_string(stat.runs) + " runs, last " + std::to_string(stat.ms) + " ms"});
    return st;
}

} // namespace app
