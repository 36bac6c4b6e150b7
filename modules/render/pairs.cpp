// render: BSSRDF values for explicit argument lists on the GPU (shaders/render_pairs.comp),
// the values the CPU replica of the traversal accumulates (see render.h).
#include "render/render.h"

#include "bssrdf/loop_budget.h"

#include <algorithm>

namespace render {

std::vector<glm::vec3> evaluatePairs(GLuint program, const bssrdf::Model& m,
                                     const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                                     const std::vector<BssrdfPair>& pairs) {
    std::vector<glm::vec3> out(pairs.size());
    if (pairs.empty()) return out;
    bssrdf::setUniforms(program, m, values, b); // also glUseProgram
    const GLint countLoc = glGetUniformLocation(program, "Count");
    constexpr size_t kChunk = size_t(1) << 20; // pairs per dispatch (16384 groups of 64)
    for (size_t first = 0; first < pairs.size(); first += kChunk) {
        const size_t count = std::min(kChunk, pairs.size() - first);
        std::vector<glm::vec4> in(count * 4);
        for (size_t i = 0; i < count; ++i) {
            const BssrdfPair& p = pairs[first + i];
            in[4 * i] = glm::vec4(p.xi, 0.0f);
            in[4 * i + 1] = glm::vec4(p.wi, 0.0f);
            in[4 * i + 2] = glm::vec4(p.xo, 0.0f);
            in[4 * i + 3] = glm::vec4(p.wo, 0.0f);
        }
        gl::Buffer inBuf = gl::createBuffer(in.size() * sizeof(glm::vec4), in.data());
        gl::Buffer outBuf = gl::createBuffer(count * sizeof(glm::vec4), nullptr);
        glUniform1ui(countLoc, static_cast<GLuint>(count));
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, inBuf.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, outBuf.id());
        bssrdf::LoopFaults faults;
        faults.arm(program);
        glDispatchCompute(static_cast<GLuint>((count + 63) / 64), 1, 1);
        // barrier: render_pairs.comp's values → the readback below
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<glm::vec4> res(count);
        glGetNamedBufferSubData(outBuf.id(), 0, static_cast<GLsizeiptr>(count * sizeof(glm::vec4)),
                                res.data());
        faults.check(m);
        for (size_t i = 0; i < count; ++i)
            out[first + i] = glm::vec3(res[i]);
    }
    return out;
}

std::vector<BssrdfPair> tracePairs(const octree::Trace& t, float scale) {
    std::vector<BssrdfPair> out;
    out.reserve(t.evaluations.size());
    const glm::vec3 sxo = scale * t.xo;
    for (const auto& e : t.evaluations)
        out.push_back({scale * e.xi, e.wi, sxo, t.no});
    return out;
}

} // namespace render
