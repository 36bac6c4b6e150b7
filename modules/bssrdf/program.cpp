// bssrdf GPU half: program building with #line source maps, uniforms, consumer dispatch.
#include "bssrdf/program.h"

#include "bssrdf/loop_budget.h"
#include "detail/run_batch.h"

#include "core/core.h"

#include <glm/common.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace bssrdf {

ParamValues defaultValues(const Model& m) {
    ParamValues v;
    for (const auto& p : m.params)
        v[p.name] = p.value;
    return v;
}

std::vector<std::string> valuesOffTheDefaults(const Model& m, const ParamValues& v) {
    std::vector<std::string> out;
    for (const auto& p : m.params) {
        auto it = v.find(p.name);
        const int n = p.type == ParamType::Color ? 3 : 1;
        bool differs = false;
        for (int c = 0; it != v.end() && c < n; ++c)
            differs |= it->second[size_t(c)] != p.value[size_t(c)];
        if (differs) out.push_back(p.name);
    }
    return out;
}

ParamValues carryOver(const Model& newModel, const Model& oldModel, const ParamValues& old) {
    ParamValues v = defaultValues(newModel);
    for (const auto& p : newModel.params) {
        const Param* before = oldModel.findParam(p.name);
        auto it = old.find(p.name);
        if (!before || before->type != p.type || it == old.end()) continue;
        auto value = it->second;
        if (p.type == ParamType::Float) value[0] = std::clamp(value[0], p.min, p.max);
        v[p.name] = value;
    }
    return v;
}

gl::Program buildModelProgram(const Model& m, const std::string& templateName,
                              const shader::Sources& src, shader::Record& record) {
    gl::Program program =
        shader::build(src, {{GL_COMPUTE_SHADER, templateName}}, record, modelExtension(&m), m.path);
    // the loop budget holds from the start, even for a dispatch that forgets LoopFaults::arm
    if (const GLint loc = glGetUniformLocation(program.id(), "BwLoopBudget"); loc >= 0)
        glProgramUniform1ui(program.id(), loc, loopBudget());
    return program;
}

gl::Program buildModelProgram(const Model& m, const std::string& templateName,
                              const shader::Sources& src) {
    shader::Record record;
    return buildModelProgram(m, templateName, src, record);
}

void setUniforms(GLuint program, const Model& m, const ParamValues& values, const Builtins& b) {
    glUseProgram(program);
    auto loc = [&](const char* n) { return glGetUniformLocation(program, n); };
    glUniform3fv(loc("SigmaA"), 1, glm::value_ptr(b.sigmaA));
    glUniform3fv(loc("SigmaS"), 1, glm::value_ptr(b.sigmaS));
    glUniform1f(loc("G"), b.g);
    glUniform1f(loc("IOR"), b.ior);
    glUniform1f(loc("Scale"), b.scale);
    for (const auto& p : m.params) {
        auto it = values.find(p.name);
        auto v = it != values.end() ? it->second : p.value;
        GLint l = loc(p.name.c_str());
        if (l < 0) continue; // declared but unused: the driver removed it
        switch (p.type) {
        case ParamType::Float:
            glUniform1f(l, v[0]);
            break;
        case ParamType::Bool:
            glUniform1i(l, v[0] != 0.0f ? 1 : 0);
            break;
        case ParamType::Color:
            glUniform3f(l, v[0], v[1], v[2]);
            break;
        }
    }
}

std::vector<double> radiusGrid(double rMaxMm, int samples) {
    std::vector<double> r(static_cast<size_t>(samples));
    for (int i = 0; i < samples; ++i) {
        // computed in float exactly as the GPU will see it, so CSV radii match the evaluation
        r[i] = static_cast<double>(static_cast<float>(rMaxMm * i / (samples - 1)));
    }
    return r;
}

namespace detail {
std::vector<float> runBatch(const Model& m, GLuint program, const std::vector<float>& in,
                            size_t count, size_t inVec4, GLuint queries, GLuint sentinel,
                            const std::vector<float>* outInit) {
    const size_t bytes = count * 4 * sizeof(float);
    gl::Buffer inBuf = gl::createBuffer(bytes * inVec4, in.data());
    gl::Buffer outBuf = gl::createBuffer(bytes, outInit ? outInit->data() : nullptr);
    glUseProgram(program);
    glUniform1ui(glGetUniformLocation(program, "Count"), static_cast<GLuint>(count));
    if (GLint q = glGetUniformLocation(program, "Queries"); q >= 0) glUniform1ui(q, queries);
    if (GLint q = glGetUniformLocation(program, "Sentinel"); q >= 0) glUniform1ui(q, sentinel);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, inBuf.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, outBuf.id());
    LoopFaults faults;
    faults.arm(program);
    glDispatchCompute(static_cast<GLuint>((count + 63) / 64), 1, 1);
    // barrier: the batch's values (pencil_profile.comp, invert_rdr.comp) → the readback below
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<float> out(count * 4);
    glGetNamedBufferSubData(outBuf.id(), 0, static_cast<GLsizeiptr>(bytes), out.data());
    faults.check(m);
    return out;
}
std::vector<float> queryInputs(const std::vector<Query>& queries) {
    std::vector<float> in(queries.size() * 12, 0.0f);
    for (size_t i = 0; i < queries.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            in[12 * i + c] = queries[i].xo[c];
            in[12 * i + 4 + c] = queries[i].wi[c];
            in[12 * i + 8 + c] = queries[i].wo[c];
        }
    return in;
}
} // namespace detail
using detail::runBatch;

Profile evaluateProfile(GLuint program, const Model& m, const ParamValues& values,
                        const Builtins& b, const std::vector<double>& radii) {
    setUniforms(program, m, values, b);
    std::vector<float> in(radii.size() * 4, 0.0f);
    for (size_t i = 0; i < radii.size(); ++i)
        in[4 * i] = static_cast<float>(radii[i]);
    auto out = runBatch(m, program, in, radii.size());
    Profile p;
    p.r = radii;
    p.value.resize(radii.size());
    for (size_t i = 0; i < radii.size(); ++i)
        p.value[i] = {out[4 * i], out[4 * i + 1], out[4 * i + 2]};
    return p;
}

std::vector<glm::dvec3> evaluateQueries(GLuint program, const Model& m, const ParamValues& values,
                                        const Builtins& b, const std::vector<Query>& queries) {
    if (queries.empty()) return {};
    if (glGetUniformLocation(program, "Queries") < 0)
        throw core::Error("shaders/pencil_profile.comp", 0,
                          "the template has no `Queries` uniform: it cannot evaluate at given "
                          "directions");
    setUniforms(program, m, values, b);
    const std::vector<float> in = detail::queryInputs(queries);
    std::vector<glm::dvec3> r(queries.size());
    // batches keep one dispatch short on a software rasteriser
    constexpr size_t kBatch = size_t(1) << 16;
    for (size_t first = 0; first < queries.size(); first += kBatch) {
        const size_t n = std::min(kBatch, queries.size() - first);
        std::vector<float> part(in.begin() + std::ptrdiff_t(12 * first),
                                in.begin() + std::ptrdiff_t(12 * (first + n)));
        auto out = runBatch(m, program, part, n, 3, 1);
        for (size_t i = 0; i < n; ++i)
            r[first + i] = {out[4 * i], out[4 * i + 1], out[4 * i + 2]};
    }
    return r;
}

std::vector<glm::dvec3> integrateDiffuseReflectance(GLuint pencilProgram, const Model& m,
                                                    const ParamValues& values, const Builtins& b,
                                                    const std::vector<glm::dvec3>& alphaPrime) {
    constexpr int kPoints = 2048;
    constexpr double kRMin = 1e-6, kRMaxCap = 1e5, kLdMultiple = 60.0;
    std::vector<glm::dvec3> out(alphaPrime.size());
    const double twoPi = 2.0 * 3.14159265358979323846;
    for (size_t k = 0; k < alphaPrime.size(); ++k) {
        const glm::dvec3 a = glm::clamp(alphaPrime[k], glm::dvec3(0.0), glm::dvec3(1.0));
        double rMax = 0;
        for (int c = 0; c < 3; ++c) {
            const double ld = 1.0 / std::sqrt(3.0 * std::max(1.0 - a[c], 1e-300));
            rMax = std::max(rMax, std::min(kRMaxCap, kLdMultiple * ld));
        }
        std::vector<double> radii(kPoints);
        const double u0 = std::log(kRMin), u1 = std::log(rMax), du = (u1 - u0) / (kPoints - 1);
        for (int i = 0; i < kPoints; ++i)
            radii[size_t(i)] = std::exp(u0 + du * i);
        Builtins bk = b;
        bk.sigmaA = glm::vec3(1.0 - a);
        bk.sigmaS = glm::vec3(a / std::max(1.0 - double(b.g), 1e-12));
        const Profile prof = evaluateProfile(pencilProgram, m, values, bk, radii);
        glm::dvec3 sum = prof.value[0] * (radii[0] * radii[0] / 2.0); // below r_min
        for (int i = 0; i + 1 < kPoints; ++i) {
            const double r0 = radii[size_t(i)], r1 = radii[size_t(i) + 1];
            sum +=
                0.5 * du * (prof.value[size_t(i)] * r0 * r0 + prof.value[size_t(i) + 1] * r1 * r1);
        }
        out[k] = twoPi * sum;
    }
    return out;
}

std::vector<glm::dvec3> evaluateDiffuseReflectance(GLuint program, const Model& m,
                                                   const ParamValues& values, const Builtins& b,
                                                   const std::vector<glm::dvec3>& alphaPrime) {
    setUniforms(program, m, values, b);
    std::vector<float> in(alphaPrime.size() * 4, 0.0f);
    for (size_t i = 0; i < alphaPrime.size(); ++i)
        for (int c = 0; c < 3; ++c)
            in[4 * i + c] = static_cast<float>(alphaPrime[i][c]);
    auto out = runBatch(m, program, in, alphaPrime.size());
    std::vector<glm::dvec3> r(alphaPrime.size());
    for (size_t i = 0; i < r.size(); ++i)
        r[i] = {out[4 * i], out[4 * i + 1], out[4 * i + 2]};
    return r;
}

} // namespace bssrdf
