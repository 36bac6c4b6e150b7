// The three stages of texture-space importance sampling (pipeline.h).
#include "texspace/pipeline.h"

#include "core/color.h"
#include "core/core.h"
#include "octree/octree.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

namespace texspace {

void validateSettings(const Settings& s, int maxTextureSize) {
    auto fail = [](const std::string& m) { throw core::Error("texture space", 0, m); };
    const int k = s.textureSize;
    if (k < 16 || k > 2048 || (k & (k - 1)) != 0)
        fail("texture_size must be a power of two in [16, 2048] (got " + std::to_string(k) + ")");
    if (maxTextureSize > 0 && k > maxTextureSize)
        fail("texture_size " + std::to_string(k) + " is above this GL's limit of " +
             std::to_string(maxTextureSize) + " texels per side");
    if (s.samples < 1 || s.samples > (1 << 20))
        fail("samples N must lie in [1, 1048576] (got " + std::to_string(s.samples) + ")");
    if (s.sampleSets < 1) fail("sample_sets must be at least 1");
    if (s.hybrid) validateHybrid(s.local);
}

Pipeline::Pipeline(const std::filesystem::path& root)
    : m_src(root), m_irradiance(std::make_unique<irradiance::Stage>(root / "shaders")),
      m_sampler(std::make_unique<GpuSampler>(shader::Sources{root})),
      m_renderer(std::make_unique<render::Renderer>(shader::Sources{root})) {}

Pipeline::~Pipeline() = default;

void Pipeline::setMesh(const mesh::Mesh& m, int textureSize) {
    Settings probe;
    probe.textureSize = textureSize;
    GLint maxTex = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTex);
    validateSettings(probe, maxTex);
    // The atlas is laid out for the smallest power-of-two texture (>= K) whose cells hold its
    // gutters; sampled at a smaller K the texel centres only thin it out (texels are looked up
    // at their centres, never filtered, so the gutters need not be a texel of K wide).
    Parameterization param;
    int layout = textureSize;
    for (;; layout *= 2) {
        try {
            param = parameterize(m, layout);
            break;
        } catch (const core::Error&) {
            if (layout >= 8192) throw;
        }
    }
    Texels texels = rasterize(m, param, textureSize);
    if (texels.covered == 0)
        throw core::Error("texture space", 0,
                          "no texel centre of the " + std::to_string(textureSize) +
                              "² texture "
                              "lies inside a triangle: use a larger texture_size");
    std::vector<uint32_t> covered;
    std::vector<glm::vec3> pos, nrm;
    covered.reserve(texels.covered);
    for (size_t t = 0; t < texels.triangle.size(); ++t)
        if (texels.triangle[t] >= 0) {
            covered.push_back(uint32_t(t));
            pos.emplace_back(texels.position[t]);
            nrm.emplace_back(texels.normal[t]);
        }
    m_irradiance->setScene(m, pos, nrm);
    m_renderer->setMesh(m);
    m_meshCopy = m;
    m_localMesh = false;
    m_param = std::move(param);
    m_layoutSize = layout;
    m_texels = std::move(texels);
    m_covered = std::move(covered);
    m_lightReady = false;
    m_running = false;
    m_et.clear();
    m_ownEt.clear();
}

double Pipeline::representedArea() const {
    const double texelArea = 1.0 / (double(m_texels.size) * double(m_texels.size));
    double a = 0;
    for (uint32_t t : m_covered)
        a += m_texels.areaRatio[t] * texelArea;
    return a;
}

void Pipeline::beginLight(const irradiance::Settings& light) {
    if (!hasMesh()) throw core::Error("texture space", 0, "no mesh");
    m_lightReady = false;
    m_light = light;
    m_lightOccluded = light.mode == irradiance::LightMode::OccludedIbl;
    if (m_lightOccluded)
        m_irradiance->beginOccluded(light);
    else
        finishLight(m_irradiance->compute(light));
}

bool Pipeline::advanceLight() {
    if (m_lightReady) return true;
    if (!m_lightOccluded || !m_irradiance->occludedRunning()) return false;
    if (!m_irradiance->stepOccluded()) return false;
    finishLight(m_irradiance->occludedResult());
    return true;
}

float Pipeline::lightProgress() const {
    if (m_lightReady) return 1.0f;
    return m_lightOccluded ? m_irradiance->occludedProgress() : 0.0f;
}

void Pipeline::finishLight(std::vector<glm::vec3> et) {
    const size_t n = m_texels.triangle.size();
    const double texelArea = 1.0 / double(n);
    if (m_givenEt && m_givenEt->size() != n)
        throw core::Error("texture space", 0,
                          "the given irradiance has " + std::to_string(m_givenEt->size()) +
                              " texels, the texture " + std::to_string(n));
    m_ownEt.assign(n, glm::vec3(0.0f));
    m_et.assign(n, glm::vec3(0.0f));
    m_weights.assign(n, 0.0);
    for (size_t k = 0; k < m_covered.size(); ++k) {
        const uint32_t t = m_covered[k];
        m_ownEt[t] = et[k];
        const glm::vec3 e = m_givenEt ? (*m_givenEt)[t] : et[k];
        if (!(e.x >= 0 && e.y >= 0 && e.z >= 0) || !std::isfinite(e.x + e.y + e.z))
            throw core::Error("texture space", 0,
                              std::string(m_givenEt ? "the given " : "") + "irradiance of texel " +
                                  std::to_string(t) + " is negative or not finite");
        m_et[t] = e;
        m_weights[t] = double(core::luminance(e)) * m_texels.areaRatio[t] * texelArea;
    }
    m_total = 0;
    for (double w : m_weights)
        m_total += w;
    if (m_total > 0) {
        m_cdf = buildMipCdf(m_weights, m_texels.size);
        m_total = m_cdf.total();
        m_sampler->setCdf(m_cdf);
    } else {
        m_cdf = MipCdf{};
    }
    m_lightReady = true;
}

std::vector<glm::vec3> Pipeline::eprime() const {
    std::vector<glm::vec3> e(m_ownEt.size(), glm::vec3(0.0f));
    for (uint32_t t : m_covered)
        e[t] = m_ownEt[t] * float(m_texels.areaRatio[t]);
    return e;
}

std::vector<glm::vec3> Pipeline::eprimeOccludedRasterSpread(const std::vector<size_t>& texels) {
    if (!m_lightReady) throw core::Error("texture space", 0, "the light is not computed yet");
    if (m_light.mode != irradiance::LightMode::OccludedIbl)
        throw core::Error("texture space", 0, "the light is not occluded image based lighting");
    const std::vector<glm::vec3> spread = m_irradiance->occludedRasterSpread(m_light);
    std::vector<size_t> point(m_texels.triangle.size(), SIZE_MAX); // texel → irradiance point
    for (size_t k = 0; k < m_covered.size(); ++k)
        point[m_covered[k]] = k;
    std::vector<glm::vec3> out;
    out.reserve(texels.size());
    for (size_t t : texels) {
        if (t >= point.size() || point[t] == SIZE_MAX)
            throw core::Error("texture space", 0,
                              "texel " + std::to_string(t) + " is not covered by the chart");
        out.push_back(spread[point[t]] * float(m_texels.areaRatio[t]));
    }
    return out;
}

std::vector<glm::vec3> Pipeline::eprimeUnshadowedOccluded(const std::vector<size_t>& texels) const {
    if (!m_lightReady) throw core::Error("texture space", 0, "the light is not computed yet");
    if (m_light.mode != irradiance::LightMode::OccludedIbl)
        throw core::Error("texture space", 0, "the light is not occluded image based lighting");
    std::vector<glm::vec3> normals;
    normals.reserve(texels.size());
    for (size_t t : texels)
        normals.emplace_back(m_texels.normal[t]); // as setMesh gave them to the stage
    std::vector<glm::vec3> u = m_irradiance->occludedUnshadowed(m_light, normals);
    for (size_t k = 0; k < texels.size(); ++k)
        u[k] *= float(m_texels.areaRatio[texels[k]]);
    return u;
}

std::vector<float> Pipeline::visibilitySpread(const std::vector<size_t>& texels) {
    if (!m_lightReady) throw core::Error("texture space", 0, "the light is not computed yet");
    const std::vector<float> all = m_irradiance->visibilitySpread(m_light); // per covered texel
    std::vector<float> out;
    out.reserve(texels.size());
    for (size_t t : texels) { // m_covered is ascending
        const auto it = std::lower_bound(m_covered.begin(), m_covered.end(), uint32_t(t));
        if (it == m_covered.end() || *it != t)
            throw core::Error("texture space", 0, "texel " + std::to_string(t) + " is not covered");
        out.push_back(all[size_t(it - m_covered.begin())]);
    }
    return out;
}

Pipeline::EprimeFactors Pipeline::eprimeFactors() {
    if (!m_lightReady) throw core::Error("texture space", 0, "the light is not computed yet");
    const irradiance::Stage::Factors f = m_irradiance->factors(m_light);
    EprimeFactors out;
    out.unshadowed.assign(m_et.size(), glm::vec3(0.0f));
    out.visibility.assign(m_et.size(), 0.0f);
    for (size_t k = 0; k < m_covered.size(); ++k) {
        const uint32_t t = m_covered[k];
        out.unshadowed[t] = f.unshadowed[k] * float(m_texels.areaRatio[t]);
        out.visibility[t] = f.visibility[k];
    }
    return out;
}

SampleSet Pipeline::drawSet(int samples, uint64_t seed, uint64_t index) const {
    if (!m_lightReady) throw core::Error("texture space", 0, "the light is not computed yet");
    if (samples < 1) throw core::Error("texture space", 0, "samples N must be at least 1");
    SampleSet s;
    if (!(m_total > 0)) return s;
    const std::vector<GpuSample> d =
        m_sampler->draw(uint64_t(samples), seed, index * uint64_t(samples));
    s.draws.reserve(d.size());
    std::unordered_map<uint32_t, size_t> slot;
    for (const GpuSample& g : d) {
        s.draws.push_back(g.texel);
        auto [it, added] = slot.try_emplace(g.texel, s.texel.size());
        if (added) {
            s.texel.push_back(g.texel);
            s.count.push_back(0);
        }
        ++s.count[it->second];
    }
    for (size_t i = 0; i < s.texel.size(); ++i) {
        const uint32_t t = s.texel[i];
        const double y = core::luminance(glm::dvec3(m_et[t]));
        if (!(y > 0) || m_texels.triangle[t] < 0)
            throw core::Error("texture space", 0,
                              "texel " + std::to_string(t) + " was drawn without weight");
        s.position.emplace_back(m_texels.position[t]);
        s.normal.emplace_back(m_texels.normal[t]);
        s.irradiance.push_back(m_et[t]);
        s.area.push_back(float(double(s.count[i]) * m_total / (double(samples) * y)));
    }
    return s;
}

SampleSet Pipeline::allTexels() const {
    if (!m_lightReady) throw core::Error("texture space", 0, "the light is not computed yet");
    SampleSet s;
    const double texelArea = 1.0 / double(m_texels.triangle.size());
    for (uint32_t t : m_covered) {
        if (!(m_weights[t] > 0)) continue;
        s.texel.push_back(t);
        s.count.push_back(1);
        s.position.emplace_back(m_texels.position[t]);
        s.normal.emplace_back(m_texels.normal[t]);
        s.irradiance.push_back(m_et[t]);
        s.area.push_back(float(m_texels.areaRatio[t] * texelArea));
    }
    return s;
}

void Pipeline::setModel(const bssrdf::Model& m) {
    m_renderer->setModel(m);
    m_radial = m.attrs.radial;
    m_running = false;
}

void Pipeline::setMaterial(const bssrdf::ParamValues& values, const bssrdf::Builtins& b) {
    m_renderer->setMaterial(values, b);
    m_running = false;
}

namespace {

// The set as an octree of points (render.h's input); a set without points (W = 0) is one point
// of zero area, so the frame still has its G-buffer and every pixel is 0.
octree::Octree setTree(const SampleSet& s, const glm::vec3& anywhere) {
    if (s.position.empty()) {
        octree::Octree t = octree::build({anywhere}, {glm::vec3(0, 0, 1)}, {0.0f});
        octree::setIrradiance(t, {glm::vec3(0.0f)});
        return t;
    }
    octree::Octree t = octree::build(s.position, s.normal, s.area);
    octree::setIrradiance(t, s.irradiance);
    return t;
}

} // namespace

void Pipeline::begin(const Settings& s, const render::Settings& view) {
    validateSettings(s);
    if (!m_lightReady) throw core::Error("texture space", 0, "the light is not computed yet");
    m_run = s;
    m_view = view;
    m_view.bruteForce = true;
    m_setsDone = 0;
    m_width = m_height = 0;
    m_sumL.clear(), m_sumL2.clear(), m_sumM.clear(), m_sumM2.clear();
    m_localM.clear(), m_localL.clear(), m_ownLocalL.clear();
    m_localStarted = false;
    m_taps.clear();
    m_rp = glm::vec3(0.0f);
    if (s.hybrid) beginHybrid();
    m_running = true;
    m_setRendering = false;
}

void Pipeline::beginHybrid() {
    validateHybrid(m_run.local);
    if (!m_radial)
        throw core::Error("hybrid", 0,
                          "the hybrid needs a radial model (its profile table gives R_p and the "
                          "local filter)");
    if (m_light.mode != irradiance::LightMode::Directional)
        throw core::Error("hybrid", 0,
                          std::string("the hybrid's local term needs the directional light (the "
                                      "light-view map); the light is ") +
                              irradiance::lightModeName(m_light.mode));
    // R_p and the filter from the profile table (the renderer builds it for the current model,
    // material and mesh; its range comes from the mesh's bounds, so an octree of one point on
    // the mesh will do)
    m_renderer->setOctree(setTree(SampleSet{}, glm::vec3(m_texels.position[m_covered[0]])));
    const render::ProfileTable& table = m_renderer->prepareProfileTable();
    m_rp = findRp(table, double(m_run.local.lowerBound));
    m_taps = ringFilter(table, m_rp, double(m_run.local.k), m_run.local.rings, m_run.local.perRing);
    if (!m_local) m_local = std::make_unique<LocalTerm>(m_src);
    if (!m_localMesh) {
        m_local->setMesh(m_meshCopy);
        m_localMesh = true;
        m_lightMapSize = 0;
    }
    // the light-view map depends on the mesh and the light only, not on the view
    if (m_lightMapSize != m_run.local.lightMapSize || m_lightMapDirection != m_light.direction ||
        m_lightMapShift != m_mapShift) {
        m_local->setVertexSnap(m_localSnap);
        m_local->renderLightMap(m_light.direction, m_run.local.lightMapSize, m_mapShift);
        m_lightMapSize = m_run.local.lightMapSize;
        m_lightMapDirection = m_light.direction;
        m_lightMapShift = m_mapShift;
    }
    m_local->setLookupShift(m_lookupShift);
    m_view.weight = {true, m_rp, m_run.local.k};
}

void Pipeline::beginLocal() {
    const render::Frame& f = m_renderer->currentFrame();
    render::Camera cam = m_view.camera;
    cam.aspect = float(f.width) / float(f.height);
    m_local->begin(f.position, f.normal, f.width, f.height, cam.position(),
                   m_renderer->profileTable(), m_taps, m_rp, m_run.local.k, m_light.irradiance,
                   m_light.ior, m_renderer->builtins().scale);
}

void Pipeline::startSet() {
    core::Stopwatch clock;
    m_lastSet = drawSet(m_run.samples, m_run.seed, uint64_t(m_setsDone));
    m_sampleMs = clock.ms();
    gl::recordTiming("texture space: draw set", m_sampleMs);
    m_renderer->setOctree(setTree(m_lastSet, glm::vec3(m_texels.position[m_covered[0]])));
    m_renderer->begin(m_view);
    m_setRendering = true;
}

bool Pipeline::advance(double budgetMs) {
    if (!m_running) return false;
    core::Stopwatch clock;
    while (!done()) {
        if (localPending() && m_setsDone > 0) {
            // the local term on the first set's G-buffer (the view's), in bands of rows so a
            // frame budget holds; the next set starts only when it is done
            if (!m_localStarted) {
                beginLocal();
                m_localStarted = true;
                m_localMs = 0;
            }
            bool finished = false;
            while (!finished) {
                core::Stopwatch band;
                finished = m_local->step(8);
                m_localMs += band.ms();
                if (!finished && clock.ms() >= budgetMs) return false;
            }
            const LocalTerm::Result r = m_local->result();
            m_localM = r.exitance;
            m_ownLocalL = r.radiance;
            m_localL = r.radiance;
            if (m_givenLocalL) {
                if (m_givenLocalL->size() != m_localL.size())
                    throw core::Error("hybrid", 0,
                                      "the given local term has " +
                                          std::to_string(m_givenLocalL->size()) +
                                          " pixels, the frame " + std::to_string(m_localL.size()));
                for (size_t p = 0; p < m_localL.size(); ++p)
                    m_localL[p] = glm::vec4((*m_givenLocalL)[p], m_localL[p].w);
            }
            gl::recordTiming("texture space: hybrid local term", m_localMs);
            if (clock.ms() >= budgetMs) break;
            continue;
        }
        if (!m_setRendering) startSet();
        const double left = std::max(1.0, budgetMs - clock.ms());
        if (!m_renderer->advance(left)) return false;
        m_setRendering = false;
        const render::Frame& f = m_renderer->currentFrame();
        m_renderMs = f.gbufferMs + f.profileMs + f.traverseMs + f.tonemapMs;
        accumulate(m_renderer->readback());
        if (clock.ms() >= budgetMs) break;
    }
    return done();
}

render::Readback Pipeline::renderSet(const SampleSet& set, const render::Settings& view) {
    m_running = false;
    m_setRendering = false;
    render::Settings v = view;
    v.bruteForce = true;
    m_renderer->setOctree(setTree(set, glm::vec3(m_texels.position[m_covered[0]])));
    m_renderer->render(v);
    return m_renderer->readback();
}

void Pipeline::accumulate(const render::Readback& rb) {
    const size_t n = rb.hdr.size();
    m_lastL = rb.hdr;
    if (m_localL.size() == n)
        for (size_t p = 0; p < n; ++p)
            m_lastL[p] += glm::vec4(glm::vec3(m_localL[p]), 0.0f);
    if (m_setsDone == 0) {
        m_width = rb.width, m_height = rb.height;
        m_sumL.assign(3 * n, 0.0), m_sumL2.assign(3 * n, 0.0);
        m_sumM.assign(3 * n, 0.0), m_sumM2.assign(3 * n, 0.0);
    }
    for (size_t p = 0; p < n; ++p)
        for (int c = 0; c < 3; ++c) {
            const double l = rb.hdr[p][c], m = rb.exitance[p][c];
            m_sumL[3 * p + size_t(c)] += l, m_sumL2[3 * p + size_t(c)] += l * l;
            m_sumM[3 * p + size_t(c)] += m, m_sumM2[3 * p + size_t(c)] += m * m;
        }
    ++m_setsDone;
}

namespace {

litsphere::Image meanImage(int w, int h, int k, const std::vector<double>& s1,
                           const std::vector<double>& s2) {
    litsphere::Image im;
    im.width = w, im.height = h;
    im.samples = uint64_t(k);
    im.mean.assign(s1.size(), 0.0f);
    im.variance.assign(s1.size(), 0.0f);
    if (k == 0) return im;
    for (size_t i = 0; i < s1.size(); ++i) {
        const double m = s1[i] / k;
        im.mean[i] = float(m);
        // sample variance of the sets / k; 0 for a single set
        im.variance[i] = k > 1 ? float(std::max(0.0, (s2[i] - k * m * m) / (k - 1)) / k) : 0.0f;
    }
    return im;
}

} // namespace

shader::Reloaded Pipeline::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    shader::Reloaded out;
    for (const shader::Reloaded& r :
         {m_irradiance->reloadShaders(changed), m_sampler->reloadShaders(changed),
          m_renderer->reloadShaders(changed),
          m_local ? m_local->reloadShaders(changed) : shader::Reloaded{}}) {
        out.rebuilt += r.rebuilt;
        if (out.problem.empty()) out.problem = r.problem;
    }
    if (out.rebuilt > 0) {
        m_lightReady = false;
        m_running = false;
    }
    return out;
}

shader::Records Pipeline::shaderRecords() const {
    shader::Records out;
    for (const auto& [name, r] : m_irradiance->shaderRecords())
        out["irradiance:" + name] = r;
    out["sample:texspace_sample.comp"] = m_sampler->record();
    for (const auto& [name, r] : m_renderer->shaderRecords())
        out["render:" + name] = r;
    if (m_local)
        for (const auto& [name, r] : m_local->records())
            out["hybrid:" + name] = r;
    return out;
}

namespace {

litsphere::Image plus(litsphere::Image im, const std::vector<glm::vec4>& local) {
    if (local.size() * 3 != im.mean.size()) return im;
    for (size_t p = 0; p < local.size(); ++p)
        for (int c = 0; c < 3; ++c)
            im.mean[3 * p + size_t(c)] += local[p][c];
    return im;
}

} // namespace

litsphere::Image Pipeline::radiance() const {
    return plus(meanImage(m_width, m_height, m_setsDone, m_sumL, m_sumL2), m_localL);
}
litsphere::Image Pipeline::exitance() const {
    return plus(meanImage(m_width, m_height, m_setsDone, m_sumM, m_sumM2), m_localM);
}
litsphere::Image Pipeline::globalRadiance() const {
    if (m_localL.empty()) return {};
    return meanImage(m_width, m_height, m_setsDone, m_sumL, m_sumL2);
}
litsphere::Image Pipeline::localRadiance() const {
    litsphere::Image im;
    if (m_localL.empty()) return im;
    im.width = m_width, im.height = m_height;
    im.mean.assign(m_localL.size() * 3, 0.0f);
    im.variance.assign(m_localL.size() * 3, 0.0f);
    return plus(im, m_localL);
}

} // namespace texspace
