// irradiance/stage_occluded: image based lighting with occlusion (thesis 3.3.2, last
// paragraphs; irradiance.h): shared environment samples, one shadow map per sample, running sums
// Σ Y and Σ Y² per point in a ping-pong pair of SSBOs (shaders/irradiance_occluded.comp).
#include "core/core.h"
#include "irradiance/env_sampling.h"
#include "irradiance/irradiance.h"
#include "irradiance/shadow_maps.h"

#include <glm/gtc/type_ptr.hpp>
#include <glm/vec4.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace irradiance {
namespace {

std::vector<glm::vec4> readVec4(GLuint buffer, size_t count) {
    std::vector<glm::vec4> v(count);
    if (count)
        glGetNamedBufferSubData(buffer, 0, static_cast<GLsizeiptr>(count * sizeof(glm::vec4)),
                                v.data());
    return v;
}
} // namespace

Stage::OccludedSamples Stage::occludedSamples(const Settings& s) const {
    const std::vector<EnvSample> samples = sampleEnvironment(m_env, s.occludedTotalSamples, s.seed);
    const glm::mat3 R = worldFromEnvironment(s.envRotation);
    OccludedSamples out;
    out.dirs.resize(samples.size());
    out.weights.resize(samples.size());
    for (size_t k = 0; k < samples.size(); ++k) {
        out.dirs[k] = glm::vec4(glm::normalize(R * samples[k].direction), 0.0f);
        out.weights[k] = glm::vec4(samples[k].weight * s.envIntensity, 0.0f);
    }
    return out;
}

std::vector<glm::vec3> Stage::occludedUnshadowed(const Settings& s,
                                                 const std::vector<glm::vec3>& normals) const {
    if (!hasEnvironment())
        throw core::Error("irradiance: image based lighting needs an environment map");
    Settings checked = s;
    checked.mode = LightMode::OccludedIbl;
    validateSettings(checked);
    const OccludedSamples samples = occludedSamples(checked);
    const double k = double(samples.dirs.size());
    std::vector<glm::vec3> out(normals.size());
    tbb::parallel_for(size_t(0), normals.size(), [&](size_t i) {
        const glm::dvec3 n(normals[i]);
        glm::dvec3 sum(0.0);
        for (size_t j = 0; j < samples.dirs.size(); ++j) {
            const double c = glm::dot(n, glm::dvec3(samples.dirs[j]));
            if (c <= 0) continue;
            sum += glm::dvec3(samples.weights[j]) * (fresnelTransmittance(c, checked.ior) * c);
        }
        out[i] = glm::vec3(sum / k);
    });
    return out;
}

void Stage::beginOccluded(const Settings& s, glm::vec2 shift) {
    GLint maxTex = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTex);
    Settings checked = s;
    checked.mode = LightMode::OccludedIbl;
    validateSettings(checked, maxTex);
    if (!m_points) throw core::Error("irradiance: no scene (call setScene first)");
    if (!hasEnvironment())
        throw core::Error("irradiance: image based lighting needs an environment map");
    cancelOccluded();
    m_occ.settings = checked;
    m_occ.samples = occludedSamples(checked);
    for (auto& b : m_sums)
        glClearNamedBufferData(b.id(), GL_RGBA32F, GL_RGBA, GL_FLOAT, nullptr);
    m_occ.current = 0;
    m_occ.done = 0;
    m_occ.total = checked.occludedTotalSamples;
    m_occ.shift = shift;
    m_occ.active = true;
}

std::vector<glm::vec3> Stage::occludedShifted(const Settings& s, glm::vec2 shift) {
    beginOccluded(s, shift);
    while (!stepOccluded()) {
    }
    return occludedResult();
}

std::vector<glm::vec3> Stage::occludedRasterSpread(const Settings& s) {
    if (s.mode != LightMode::OccludedIbl)
        throw core::Error("irradiance: only occluded image based lighting sums its shadow maps");
    if (!m_points) throw core::Error("irradiance: no scene (call setScene first)");
    if (!hasEnvironment())
        throw core::Error("irradiance: image based lighting needs an environment map");
    GLint maxTex = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTex);
    validateSettings(s, maxTex);
    cancelOccluded();
    const OccludedSamples samples = occludedSamples(s);
    m_shadow->ensure(s.shadowMapSize, s.occludedSamplesPerStep);
    // each sample's term Y_k alone: its map, then the pass adding it to sums of zero
    const size_t bytes = 2 * m_pointCount * sizeof(glm::vec4);
    const gl::Buffer zero = gl::createBuffer(bytes, nullptr),
                     term = gl::createBuffer(bytes, nullptr);
    glClearNamedBufferData(zero.id(), GL_RGBA32F, GL_RGBA, GL_FLOAT, nullptr);
    auto termOf = [&](int k, glm::vec2 shift) {
        dispatchOccluded(s, samples, k, 1, zero.id(), term.id(), shift);
        return readVec4(term.id(), 2 * m_pointCount); // ΣY at 2i (dispatchPoints' barrier)
    };
    std::vector<glm::vec3> spread(m_pointCount, glm::vec3(0.0f));
    for (int k = 0; k < int(samples.dirs.size()); ++k) {
        const std::vector<glm::vec4> y = termOf(k, glm::vec2(0.0f));
        std::vector<glm::vec3> worst(m_pointCount, glm::vec3(0.0f));
        for (const glm::vec2 shift : rasterShifts()) {
            const std::vector<glm::vec4> moved = termOf(k, shift);
            for (size_t i = 0; i < m_pointCount; ++i)
                worst[i] = glm::max(worst[i], glm::abs(glm::vec3(moved[2 * i] - y[2 * i])));
        }
        for (size_t i = 0; i < m_pointCount; ++i)
            spread[i] += worst[i];
    }
    const float kSamples = float(std::max<size_t>(samples.dirs.size(), 1));
    for (glm::vec3& x : spread)
        x /= kSamples;
    compute(s); // last: compute(s)'s state
    return spread;
}

void Stage::dispatchOccluded(const Settings& s, const OccludedSamples& samples, int first,
                             int count, GLuint prev, GLuint next, glm::vec2 shift) {
    // per sample: direction (the frame's w), weight, u, v
    std::vector<glm::vec4> block(4 * static_cast<size_t>(count));
    for (int k = 0; k < count; ++k) {
        const size_t g = static_cast<size_t>(first + k);
        const LightFrame f = makeLightFrame(glm::vec3(samples.dirs[g]), m_bounds);
        m_shadow->render(k, f, shift);
        block[4 * k] = glm::vec4(f.w, 0.0f);
        block[4 * k + 1] = samples.weights[g];
        block[4 * k + 2] = glm::vec4(f.u, 0.0f);
        block[4 * k + 3] = glm::vec4(f.v, 0.0f);
    }
    const gl::Buffer blockBuf = gl::createBuffer(block.size() * sizeof(glm::vec4), block.data());
    const GLuint p = m_occluded.id();
    glUseProgram(p);
    setShadowUniforms(m_occluded, s);
    glProgramUniform1ui(p, gl::uniformLocation(m_occluded, "SampleCount"),
                        static_cast<GLuint>(count));
    glProgramUniform1ui(p, gl::uniformLocation(m_occluded, "FirstSample"),
                        static_cast<GLuint>(first));
    glProgramUniform3fv(p, gl::uniformLocation(m_occluded, "LightCentre"), 1,
                        glm::value_ptr(m_bounds.centre));
    glProgramUniform1f(p, gl::uniformLocation(m_occluded, "LightExtent"),
                       makeLightFrame(glm::vec3(0, 1, 0), m_bounds).extent);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_points.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, prev);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, next);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, blockBuf.id());
    m_shadow->bind();
    dispatchPoints(m_occluded);
    glUseProgram(0); // no program stays current whose shadow samplers meet unbound units
    m_shadow->unbind();
}

bool Stage::stepOccluded() {
    if (!m_occ.active) return false;
    const Settings& s = m_occ.settings;
    const int count = std::min(s.occludedSamplesPerStep, m_occ.total - m_occ.done);
    m_shadow->ensure(s.shadowMapSize, s.occludedSamplesPerStep);
    dispatchOccluded(s, m_occ.samples, m_occ.done, count, m_sums[m_occ.current].id(),
                     m_sums[1 - m_occ.current].id(), m_occ.shift);
    m_occ.current = 1 - m_occ.current;
    m_occ.done += count;
    if (m_occ.done >= m_occ.total) {
        m_occ.active = false;
        return true;
    }
    return false;
}

float Stage::occludedProgress() const {
    return m_occ.total > 0 ? static_cast<float>(m_occ.done) / static_cast<float>(m_occ.total)
                           : 0.0f;
}

std::vector<glm::vec3> Stage::occludedResult() const {
    if (m_occ.done == 0) return {};
    const std::vector<glm::vec4> sums = readVec4(m_sums[m_occ.current].id(), 2 * m_pointCount);
    std::vector<glm::vec3> out(m_pointCount);
    const float k = static_cast<float>(m_occ.done);
    for (size_t i = 0; i < m_pointCount; ++i)
        out[i] = glm::vec3(sums[2 * i]) / k;
    return out;
}

std::vector<glm::vec3> Stage::occludedStdError() const {
    if (m_occ.done == 0) return {};
    const std::vector<glm::vec4> sums = readVec4(m_sums[m_occ.current].id(), 2 * m_pointCount);
    std::vector<glm::vec3> out(m_pointCount, glm::vec3(0.0f));
    const double k = m_occ.done;
    if (m_occ.done < 2) return out;
    for (size_t i = 0; i < m_pointCount; ++i)
        for (int c = 0; c < 3; ++c) {
            const double mean = sums[2 * i][c] / k;
            const double var = std::max(0.0, (sums[2 * i + 1][c] - k * mean * mean) / (k - 1.0));
            out[i][c] = static_cast<float>(std::sqrt(var / k));
        }
    return out;
}

void Stage::cancelOccluded() {
    m_occ.active = false;
    m_occ.done = 0;
    m_occ.total = 0;
    m_occ.samples = {};
}

} // namespace irradiance
