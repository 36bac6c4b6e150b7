// The hybrid local/global method of seed 004 §3.3 (hybrid.h).
#include "texspace/hybrid.h"

#include "core/core.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace texspace {

void validateHybrid(const HybridSettings& s) {
    auto fail = [](const std::string& m) { throw core::Error("hybrid", 0, m); };
    if (!(s.k > 0) || !std::isfinite(s.k)) fail("k must be a finite number > 0");
    if (!(s.lowerBound > 0) || !std::isfinite(s.lowerBound))
        fail("lower_bound must be a finite number > 0");
    if (s.rings < 1 || s.rings > 64) fail("rings must lie in [1, 64]");
    if (s.perRing < 1 || s.perRing > 64) fail("per_ring must lie in [1, 64]");
    if (s.rings * s.perRing + 1 > 1024) fail("at most 1024 taps (rings × per_ring + 1)");
    if (s.lightMapSize < 16 || s.lightMapSize > 4096) fail("light_map_size must lie in [16, 4096]");
}

double localWeight(double r, double rp, double k) {
    return r <= rp ? 1.0 - 0.5 * std::exp((r - rp) * k) : 0.5 * std::exp(-(r - rp) * k);
}

double findRp(const std::vector<double>& r, const std::vector<double>& R, double bound) {
    const size_t n = std::min(r.size(), R.size());
    auto imp = [&](size_t k) { return R[k] * 2.0 * M_PI * r[k]; };
    for (size_t k = n; k-- > 0;) { // the last entry at or above the bound, then the crossing
        const double a = imp(k);
        if (!(a >= bound)) continue;
        if (k + 1 == n) return r[k];
        const double b = imp(k + 1);
        return r[k] + (r[k + 1] - r[k]) * (a - bound) / (a - b);
    }
    return 0.0;
}

glm::vec3 findRp(const render::ProfileTable& t, double bound) {
    glm::vec3 rp(0.0f);
    const int n = int(t.values.size());
    std::vector<double> r(static_cast<size_t>(n)), v(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k)
        r[size_t(k)] = render::profileRadius(t.rMax, k, n);
    for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < n; ++k)
            v[size_t(k)] = double(t.values[size_t(k)][c]);
        rp[c] = float(findRp(r, v, bound));
    }
    return rp;
}

std::vector<RingTap> ringFilter(const render::ProfileTable& t, const glm::vec3& rp, double k,
                                int rings, int perRing) {
    const int n = int(t.values.size());
    if (n < 2) return {};
    // the mixture of the channels' normalised R·W_l·2πr on the table's radii, its CDF (trapezoid)
    std::vector<double> r(static_cast<size_t>(n)), f(static_cast<size_t>(n), 0.0);
    for (int i = 0; i < n; ++i)
        r[size_t(i)] = render::profileRadius(t.rMax, i, n);
    for (int c = 0; c < 3; ++c) {
        std::vector<double> g(static_cast<size_t>(n));
        double total = 0;
        for (int i = 0; i < n; ++i) {
            g[size_t(i)] = std::max(0.0, double(t.values[size_t(i)][c])) *
                           localWeight(r[size_t(i)], rp[c], k) * 2.0 * M_PI * r[size_t(i)];
            if (i > 0)
                total +=
                    0.5 * (g[size_t(i)] + g[size_t(i - 1)]) * (r[size_t(i)] - r[size_t(i - 1)]);
        }
        if (total > 0 && std::isfinite(total))
            for (int i = 0; i < n; ++i)
                f[size_t(i)] += g[size_t(i)] / total;
    }
    std::vector<double> cdf(static_cast<size_t>(n), 0.0);
    for (int i = 1; i < n; ++i)
        cdf[size_t(i)] = cdf[size_t(i - 1)] + 0.5 * (f[size_t(i)] + f[size_t(i - 1)]) *
                                                  (r[size_t(i)] - r[size_t(i - 1)]);
    const double total = cdf.back();
    if (!(total > 0)) return {};
    auto radiusAt = [&](double q) { // the radius where the CDF reaches q · total (linear)
        const double target = q * total;
        const auto it = std::lower_bound(cdf.begin(), cdf.end(), target);
        if (it == cdf.begin()) return 0.0;
        if (it == cdf.end()) return r.back();
        const size_t i = size_t(it - cdf.begin());
        const double span = cdf[i] - cdf[i - 1];
        return r[i - 1] + (span > 0 ? (target - cdf[i - 1]) / span : 0.0) * (r[i] - r[i - 1]);
    };
    auto mixtureAt = [&](double x) { // f at x, linear between entries
        const auto it = std::lower_bound(r.begin(), r.end(), x);
        if (it == r.begin()) return f.front();
        if (it == r.end()) return f.back();
        const size_t i = size_t(it - r.begin());
        const double span = r[i] - r[i - 1];
        return f[i - 1] + (span > 0 ? (x - r[i - 1]) / span : 0.0) * (f[i] - f[i - 1]);
    };
    const double strata = double(rings + 1);
    std::vector<RingTap> taps;
    // the centre: the disk of the first stratum, where R·W_l is nearly constant
    const double b0 = radiusAt(1.0 / strata);
    taps.push_back({glm::vec2(0.0f), float(M_PI * b0 * b0)});
    for (int j = 1; j <= rings; ++j) {
        // ring j: the middle quantile of its stratum; a tap stands for 1/((L+1)·C) of the
        // importance, i.e. for the area 2πr·total / (f(r)·(L+1)·C) (the estimator's 1/pdf)
        const double mid = radiusAt((double(j) + 0.5) / strata);
        const double fm = mixtureAt(mid);
        if (!(fm > 0)) continue;
        const double area = 2.0 * M_PI * mid * total / (fm * strata * double(perRing));
        for (int c = 0; c < perRing; ++c) {
            const double phi = 2.0 * M_PI * (double(c) + 0.5 * double(j % 2)) / double(perRing);
            taps.push_back(
                {glm::vec2(float(mid * std::cos(phi)), float(mid * std::sin(phi))), float(area)});
        }
    }
    return taps;
}

LocalTerm::LocalTerm(const shader::Sources& src)
    : m_src(src), m_mapProgram(shader::build(src,
                                             {{GL_VERTEX_SHADER, "render_gbuffer.vert"},
                                              {GL_FRAGMENT_SHADER, "render_gbuffer.frag"}},
                                             m_mapRecord)),
      m_localProgram(
          shader::build(src, {{GL_COMPUTE_SHADER, "hybrid_local.comp"}}, m_localRecord)) {}

LocalTerm::~LocalTerm() = default;

void LocalTerm::setMesh(const mesh::Mesh& input) {
    mesh::Mesh m = input;
    if (m.normals.size() != m.vertices.size()) mesh::computeVertexNormals(m);
    std::vector<float> interleaved;
    interleaved.reserve(m.vertices.size() * 6);
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        const auto& v = m.vertices[i];
        const auto& nn = m.normals[i];
        interleaved.insert(interleaved.end(), {v[0], v[1], v[2], nn[0], nn[1], nn[2]});
    }
    m_vertices = gl::createBuffer(interleaved.size() * sizeof(float), interleaved.data());
    m_indices = gl::createBuffer(m.triangles.size() * 3 * sizeof(uint32_t), m.triangles.data());
    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    glVertexArrayVertexBuffer(vao, 0, m_vertices.id(), 0, 6 * sizeof(float));
    glVertexArrayElementBuffer(vao, m_indices.id());
    for (GLuint a = 0; a < 2; ++a) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, a * 3 * sizeof(float));
        glVertexArrayAttribBinding(vao, a, 0);
    }
    m_vao = gl::VertexArray(vao);
    m_indexCount = GLsizei(m.triangles.size() * 3);
    m_mesh = std::move(m);
}

void LocalTerm::renderLightMap(const glm::vec3& towardsLight, int size, glm::vec2 shift) {
    if (!m_vao) throw core::Error("hybrid", 0, "no mesh");
    m_frame = irradiance::makeLightFrame(towardsLight, irradiance::boundingSphere(m_mesh, {}));
    if (size != m_mapSize) {
        m_lightPosition = gl::createTexture2D(GL_RGBA32F, size, size);
        m_lightNormal = gl::createTexture2D(GL_RGBA32F, size, size);
        m_lightDepth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, size, size);
        GLuint id = 0;
        glCreateFramebuffers(1, &id);
        m_fbo = gl::FramebufferId(id);
        glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT0, m_lightPosition.id(), 0);
        glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT1, m_lightNormal.id(), 0);
        glNamedFramebufferTexture(id, GL_DEPTH_ATTACHMENT, m_lightDepth.id(), 0);
        const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
        glNamedFramebufferDrawBuffers(id, 2, buffers);
        if (glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw core::Error("hybrid", 0, "light-view map framebuffer incomplete");
        m_mapSize = size;
    }
    const gl::ScopedDrawTarget draw(m_fbo.id(), size, size);
    const float zero[4] = {0, 0, 0, 0}, one = 1.0f;
    glClearNamedFramebufferfv(m_fbo.id(), GL_COLOR, 0, zero);
    glClearNamedFramebufferfv(m_fbo.id(), GL_COLOR, 1, zero);
    glClearNamedFramebufferfv(m_fbo.id(), GL_DEPTH, 0, &one);
    glUseProgram(m_mapProgram.id());
    glm::mat4 clip = m_frame.clipFromWorld();
    if (shift != glm::vec2(0.0f)) { // a texel is 2/size in clip space
        glm::mat4 t(1.0f);
        t[3] = glm::vec4(2.0f * shift / float(size), 0.0f, 1.0f);
        clip = t * clip;
    }
    glUniformMatrix4fv(glGetUniformLocation(m_mapProgram.id(), "RenderViewProjection"), 1, GL_FALSE,
                       &clip[0][0]);
    const glm::vec3 snap = m_snap.clipAmplitude(size, size);
    glUniform3fv(glGetUniformLocation(m_mapProgram.id(), "VertexSnap"), 1, &snap.x);
    glUniform1ui(glGetUniformLocation(m_mapProgram.id(), "VertexSnapSeed"), m_snap.seed);
    glBindVertexArray(m_vao.id());
    glDrawElements(GL_TRIANGLES, m_indexCount, GL_UNSIGNED_INT, nullptr);
    glBindVertexArray(0);
    // barrier: the light-view G-buffer's draw → hybrid_local.comp's image loads of it
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

void LocalTerm::begin(GLuint gPosition, GLuint gNormal, int width, int height,
                      const glm::vec3& cameraPosition, const render::ProfileTable& table,
                      const std::vector<RingTap>& taps, const glm::vec3& rp, float k,
                      const glm::vec3& irradiance, float ior, float scaleMm) {
    if (m_mapSize == 0) throw core::Error("hybrid", 0, "no light-view map");
    if (taps.size() > 1024) throw core::Error("hybrid", 0, "at most 1024 taps");
    const size_t pixels = size_t(width) * size_t(height);
    gl::requireStorageBlock(pixels * sizeof(glm::vec4), "hybrid", "pixels", sizeof(glm::vec4));
    std::vector<float> tableData(table.values.size() * 4);
    for (size_t i = 0; i < table.values.size(); ++i) {
        tableData[4 * i] = table.values[i].x;
        tableData[4 * i + 1] = table.values[i].y;
        tableData[4 * i + 2] = table.values[i].z;
        tableData[4 * i + 3] = render::profileRadius(table.rMax, int(i), int(table.values.size()));
    }
    std::vector<glm::vec4> tapData;
    for (const RingTap& t : taps)
        tapData.emplace_back(t.offsetMm.x, t.offsetMm.y, t.areaMm2, 0.0f);
    if (tapData.empty()) tapData.emplace_back(0.0f);
    if (tableData.empty()) tableData.assign(8, 0.0f);
    m_tableBuffer = gl::createBuffer(tableData.size() * sizeof(float), tableData.data());
    m_tapBuffer = gl::createBuffer(tapData.size() * sizeof(glm::vec4), tapData.data());
    m_exitance = gl::createBuffer(pixels * sizeof(glm::vec4), nullptr);
    m_radiance = gl::createBuffer(pixels * sizeof(glm::vec4), nullptr);
    m_gPosition = gPosition, m_gNormal = gNormal;
    m_width = width, m_height = height, m_row = 0;
    m_tapCount = int(taps.size());
    const GLuint p = m_localProgram.id();
    glUseProgram(p);
    auto loc = [&](const char* n) { return glGetUniformLocation(p, n); };
    glUniform2i(loc("LocalSize"), width, height);
    glUniform1i(loc("LocalTapCount"), m_tapCount);
    glUniform1i(loc("LightMapSize"), m_mapSize);
    glUniform3fv(loc("LightCentre"), 1, &m_frame.centre.x);
    glUniform3fv(loc("LightU"), 1, &m_frame.u.x);
    glUniform3fv(loc("LightV"), 1, &m_frame.v.x);
    glUniform3fv(loc("LightW"), 1, &m_frame.w.x);
    glUniform1f(loc("LightExtent"), m_frame.extent);
    glUniform3fv(loc("LightIrradiance"), 1, &irradiance.x);
    glUniform1f(loc("LocalIor"), ior);
    glUniform1f(loc("LocalScale"), scaleMm);
    glUniform3fv(loc("LocalRp"), 1, &rp.x);
    glUniform1f(loc("LocalK"), k);
    glUniform3fv(loc("LocalCamera"), 1, &cameraPosition.x);
    glUniform1f(loc("ProfileRMax"), table.rMax > 0 ? table.rMax : 1.0f);
    glUniform1ui(loc("ProfileCount"), GLuint(std::max<size_t>(table.values.size(), 2)));
}

void LocalTerm::bindInputs(int mode) const {
    const GLuint p = m_localProgram.id();
    glUseProgram(p); // uniforms set by begin() stay with the program
    glUniform1i(glGetUniformLocation(p, "LocalTapMode"), mode);
    glUniform2fv(glGetUniformLocation(p, "LocalLookupShift"), 1, &m_lookupShift.x);
    glBindImageTexture(0, m_gPosition, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, m_gNormal, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(2, m_lightPosition.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(3, m_lightNormal.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, m_tableBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, m_tapBuffer.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, m_exitance.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, m_radiance.id());
}

bool LocalTerm::step(int rows) {
    if (!m_exitance) throw core::Error("hybrid", 0, "no local evaluation begun");
    if (m_row >= m_height) return true;
    const int n = std::clamp(rows, 1, m_height - m_row);
    bindInputs(0);
    glUniform1i(glGetUniformLocation(m_localProgram.id(), "LocalRowOffset"), m_row);
    glDispatchCompute(GLuint((m_width + 7) / 8), GLuint((n + 7) / 8), 1);
    // barrier: hybrid_local.comp's band of results → the readback and the next band's dispatch
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
    glFinish(); // the band's time is spent here, not in a later call
    m_row += n;
    return m_row >= m_height;
}

size_t LocalTerm::tapsPerPass() const {
    const uint64_t perPixel = uint64_t(std::max(m_tapCount, 1)) * 2 * sizeof(glm::vec4);
    const uint64_t limit =
        std::min<uint64_t>(uint64_t(gl::maxStorageBlockBytes()), uint64_t(1) << 28);
    return size_t(std::max<uint64_t>(limit / perPixel, 1));
}

void LocalTerm::beginTaps(const std::vector<uint32_t>& pixels) {
    if (!m_exitance) throw core::Error("hybrid", 0, "no local evaluation begun");
    if (pixels.empty() || pixels.size() > tapsPerPass())
        throw core::Error("hybrid", 0,
                          "a pass of the taps lists 1 to " + std::to_string(tapsPerPass()) +
                              " pixels, not " + std::to_string(pixels.size()));
    for (uint32_t px : pixels)
        if (size_t(px) >= size_t(m_width) * size_t(m_height))
            throw core::Error("hybrid", 0,
                              "pixel " + std::to_string(px) + " lies outside the frame");
    const size_t taps = size_t(std::max(m_tapCount, 1)) * pixels.size();
    m_tapPixels = gl::createBuffer(pixels.size() * sizeof(uint32_t), pixels.data());
    m_tapOwn = gl::createBuffer(taps * sizeof(glm::vec4), nullptr);
    m_tapSpread = gl::createBuffer(2 * taps * sizeof(glm::vec4), nullptr);
    m_tapPixelCount = pixels.size();
    raiseTaps(-1);
}

void LocalTerm::raiseTaps(int group) {
    if (!m_tapPixels) throw core::Error("hybrid", 0, "no taps begun");
    bindInputs(group < 0 ? 1 : 2);
    const GLuint p = m_localProgram.id();
    glUniform1ui(glGetUniformLocation(p, "LocalPixelCount"), GLuint(m_tapPixelCount));
    glUniform1i(glGetUniformLocation(p, "LocalTapGroup"), std::max(group, 0));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 8, m_tapPixels.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 9, m_tapOwn.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, m_tapSpread.id());
    glDispatchCompute(GLuint((m_tapPixelCount + 63) / 64), 1, 1);
    // barrier: the taps' terms and spreads → the next pass's reads of them and tapSpreads()'s
    // readback; the map drawn next into the textures this pass reads waits for it
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_FRAMEBUFFER_BARRIER_BIT);
}

std::vector<glm::vec3> LocalTerm::tapSpreads() const {
    if (!m_tapSpread) throw core::Error("hybrid", 0, "no taps begun");
    const size_t taps = size_t(std::max(m_tapCount, 1));
    std::vector<glm::vec4> spread(2 * taps * m_tapPixelCount);
    glGetNamedBufferSubData(m_tapSpread.id(), 0, GLsizeiptr(spread.size() * sizeof(glm::vec4)),
                            spread.data());
    std::vector<glm::vec3> out(m_tapPixelCount, glm::vec3(0.0f));
    for (size_t j = 0; j < m_tapPixelCount; ++j)
        for (size_t t = 0; t < size_t(m_tapCount); ++t) {
            const size_t k = j * taps + t;
            out[j] += glm::vec3(spread[2 * k]) + glm::vec3(spread[2 * k + 1]);
        }
    return out;
}

LocalTerm::Result LocalTerm::result() const {
    Result out;
    if (!m_exitance || m_row < m_height) throw core::Error("hybrid", 0, "local term not finished");
    const size_t pixels = size_t(m_width) * size_t(m_height);
    out.exitance.resize(pixels);
    out.radiance.resize(pixels);
    glGetNamedBufferSubData(m_exitance.id(), 0, GLsizeiptr(pixels * sizeof(glm::vec4)),
                            out.exitance.data());
    glGetNamedBufferSubData(m_radiance.id(), 0, GLsizeiptr(pixels * sizeof(glm::vec4)),
                            out.radiance.data());
    return out;
}

LocalTerm::Result LocalTerm::evaluate(GLuint gPosition, GLuint gNormal, int width, int height,
                                      const glm::vec3& cameraPosition,
                                      const render::ProfileTable& table,
                                      const std::vector<RingTap>& taps, const glm::vec3& rp,
                                      float k, const glm::vec3& irradiance, float ior,
                                      float scaleMm) {
    begin(gPosition, gNormal, width, height, cameraPosition, table, taps, rp, k, irradiance, ior,
          scaleMm);
    while (!step(height)) {
    }
    return result();
}

shader::Reloaded LocalTerm::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    shader::Reloaded out;
    auto again = [&](shader::Record& rec, gl::Program& prog,
                     const std::vector<std::pair<GLenum, std::string>>& stages) {
        if (!rec.dependencies.containsAny(changed)) return;
        try {
            prog = shader::build(m_src, stages, rec);
            ++out.rebuilt;
        } catch (const core::Error& e) {
            if (out.problem.empty()) out.problem = e.what();
        }
    };
    again(m_mapRecord, m_mapProgram,
          {{GL_VERTEX_SHADER, "render_gbuffer.vert"}, {GL_FRAGMENT_SHADER, "render_gbuffer.frag"}});
    again(m_localRecord, m_localProgram, {{GL_COMPUTE_SHADER, "hybrid_local.comp"}});
    return out;
}

shader::Records LocalTerm::records() const {
    return {{"render_gbuffer (light view)", m_mapRecord}, {"hybrid_local.comp", m_localRecord}};
}

} // namespace texspace
