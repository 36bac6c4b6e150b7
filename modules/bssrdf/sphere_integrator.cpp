// bssrdf sphere integrator host side (see sphere_integrator.h): validation, uniforms,
// dispatches and the double accumulation of the per-dispatch float sums.
#include "bssrdf/sphere_integrator.h"

#include "bssrdf/loop_budget.h"
#include "core/text.h"

#include "core/core.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bssrdf {

namespace {

constexpr GLuint kSumsBinding = 0; // shaders/sphere_bssrdf.comp
constexpr int kLocalSize = 8;      // local_size_x = local_size_y = 8
constexpr int kMaxSide = 8192;

} // namespace

void SphereIntegrator::reset(const litsphere::Setup& setup) {
    const std::string what = "lit sphere";
    if (!std::isfinite(setup.radiusMm) || setup.radiusMm <= 0)
        throw core::Error(what, 0,
                          "radius must be a finite length > 0 mm, got " +
                              core::formatNumber(setup.radiusMm, 6));
    if (setup.width < 1 || setup.height < 1 || setup.width > kMaxSide || setup.height > kMaxSide)
        throw core::Error(what, 0,
                          "image size must lie in [1, " + std::to_string(kMaxSide) + "]², got " +
                              std::to_string(setup.width) + "x" + std::to_string(setup.height));
    const double* l = setup.lightDir;
    const double len = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if (!std::isfinite(len) || len <= 0)
        throw core::Error(what, 0, "light direction must be a finite non-zero vector");
    const size_t pixels = static_cast<size_t>(setup.width) * static_cast<size_t>(setup.height);
    gl::requireStorageBlock(pixels * 8 * sizeof(float), what, "pixels", 8 * sizeof(float));
    m_setup = setup;
    for (int c = 0; c < 3; ++c)
        m_lightDir[c] = l[c] / len;
    m_sums = gl::createBuffer(pixels * 8 * sizeof(float), nullptr);
    m_readback.assign(pixels * 8, 0.0f);
    m_sum.assign(pixels * 3, 0.0);
    m_sumSq.assign(pixels * 3, 0.0);
    m_samples = 0;
    m_seconds = 0;
    m_samplesPerDispatch = kMaxSamplesPerDispatch;
}

void SphereIntegrator::step(GLuint program, const Model& m, const ParamValues& values,
                            const Builtins& b, int samplesPerPixel) {
    if (samplesPerPixel <= 0 || !m_sums) return;
    core::Stopwatch clock;
    gl::ScopedStageTimer timer("sphere BSSRDF integration");
    setUniforms(program, m, values, b); // also glUseProgram
    auto loc = [&](const char* n) { return glGetUniformLocation(program, n); };
    const litsphere::Setup& s = m_setup;
    glUniform2i(loc("SphereSize"), s.width, s.height);
    glUniform1f(loc("SphereRadius"), static_cast<float>(s.radiusMm));
    glUniform1f(loc("SphereExtent"), static_cast<float>(s.extent()));
    glUniform3f(loc("SphereLightDir"), static_cast<float>(m_lightDir[0]),
                static_cast<float>(m_lightDir[1]), static_cast<float>(m_lightDir[2]));
    glUniform2ui(loc("SphereSeed"), static_cast<GLuint>(s.seed), static_cast<GLuint>(s.seed >> 32));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kSumsBinding, m_sums.id());
    const auto groupsX = static_cast<GLuint>((s.width + kLocalSize - 1) / kLocalSize);
    const auto groupsY = static_cast<GLuint>((s.height + kLocalSize - 1) / kLocalSize);
    const size_t pixels = m_sum.size() / 3;
    glUniform1ui(loc("SphereSentinel"), 2u);
    LoopFaults faults;
    for (int done = 0; done < samplesPerPixel;) {
        const int k = std::min(m_samplesPerDispatch, samplesPerPixel - done);
        glUniform2ui(loc("SphereFirstSample"), static_cast<GLuint>(m_samples),
                     static_cast<GLuint>(m_samples >> 32));
        glUniform1ui(loc("SphereSamples"), static_cast<GLuint>(k));
        faults.arm(program);
        glDispatchCompute(groupsX, groupsY, 1);
        // barrier: sphere_bssrdf.comp's per-pixel sums → glGetNamedBufferSubData below
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(m_sums.id(), 0,
                                static_cast<GLsizeiptr>(m_readback.size() * sizeof(float)),
                                m_readback.data());
        faults.check(m);
        bool complete = true;
        for (size_t p = 0; p < pixels && complete; ++p)
            complete = m_readback[8 * p + 3] == 1.0f && m_readback[8 * p + 7] == 1.0f;
        if (!complete) { // the driver's loop budget ran out: fewer samples, the same ones again
            if (k == 1)
                throw core::Error(
                    m.name, 0,
                    "Bssrdf() runs more loop iterations than the driver allows in one "
                    "invocation (Mesa llvmpipe: 65535 in all): the sphere cannot be integrated");
            m_samplesPerDispatch = std::max(1, k / 2);
            continue;
        }
        for (size_t p = 0; p < pixels; ++p)
            for (size_t c = 0; c < 3; ++c) {
                m_sum[3 * p + c] += m_readback[8 * p + c];
                m_sumSq[3 * p + c] += m_readback[8 * p + 4 + c];
            }
        m_samples += static_cast<uint64_t>(k);
        done += k;
    }
    m_seconds += clock.ms() * 1e-3;
}

litsphere::Image SphereIntegrator::image() const {
    litsphere::Image img;
    img.width = m_sum.empty() ? 0 : m_setup.width;
    img.height = m_sum.empty() ? 0 : m_setup.height;
    img.mean.assign(m_sum.size(), 0.0f);
    img.variance.assign(m_sum.size(), 0.0f);
    const auto pixels = static_cast<uint64_t>(m_sum.size() / 3);
    img.samples = m_samples * pixels;
    if (m_samples == 0) return img;
    const auto n = static_cast<double>(m_samples);
    for (size_t i = 0; i < m_sum.size(); ++i) {
        const double mean = m_sum[i] / n;
        double var = 0.0;
        if (m_samples >= 2)
            var = std::max(0.0, (m_sumSq[i] / n - mean * mean) / (n - 1.0));
        else if (m_sum[i] != 0.0 || m_sumSq[i] != 0.0)
            var = std::numeric_limits<double>::infinity();
        img.mean[i] = static_cast<float>(mean);
        img.variance[i] = static_cast<float>(var);
    }
    return img;
}

} // namespace bssrdf
