// Stage 2 of texture-space sampling on the GPU (gpu_sampler.h).
#include "texspace/gpu_sampler.h"

#include "core/core.h"

namespace texspace {

GpuSampler::GpuSampler(const shader::Sources& src)
    : m_src(src),
      m_program(shader::build(src, {{GL_COMPUTE_SHADER, "texspace_sample.comp"}}, m_record)) {}

shader::Reloaded GpuSampler::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    shader::Reloaded out;
    if (!m_record.dependencies.containsAny(changed)) return out;
    try {
        m_program = shader::build(m_src, {{GL_COMPUTE_SHADER, "texspace_sample.comp"}}, m_record);
        ++out.rebuilt;
    } catch (const core::Error& e) {
        out.problem = e.what();
    }
    return out;
}

void GpuSampler::setCdf(const MipCdf& cdf) {
    if (cdf.levels.size() > 16) throw core::Error("texture space", 0, "at most 16 mip levels");
    std::vector<float> all;
    m_offsets.clear();
    for (const auto& level : cdf.levels) {
        m_offsets.push_back(uint32_t(all.size()));
        for (double w : level)
            all.push_back(float(w));
    }
    m_levels = gl::createBuffer(all.size() * sizeof(float), all.data());
    m_size = cdf.size;
}

std::vector<GpuSample> GpuSampler::draw(uint64_t count, uint64_t seed, uint64_t first) const {
    if (!m_levels) throw core::Error("texture space", 0, "no CDF uploaded");
    if (count == 0) return {};
    const GLuint p = m_program.id();
    glUseProgram(p);
    auto loc = [&](const char* n) { return glGetUniformLocation(p, n); };
    glUniform1ui(loc("SampleCount"), GLuint(count));
    glUniform1ui(loc("LevelCount"), GLuint(m_offsets.size()));
    glUniform1ui(loc("TextureSize"), GLuint(m_size));
    glUniform2ui(loc("SampleSeed"), GLuint(seed), GLuint(seed >> 32));
    glUniform2ui(loc("SampleFirst"), GLuint(first), GLuint(first >> 32));
    glUniform1uiv(loc("LevelOffset"), GLsizei(m_offsets.size()), m_offsets.data());
    gl::Buffer out = gl::createBuffer(count * 2 * sizeof(uint32_t), nullptr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_levels.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glDispatchCompute(GLuint((count + 63) / 64), 1, 1);
    // barrier: texspace_sample.comp's samples → the readback below
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<uint32_t> raw(count * 2);
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(raw.size() * sizeof(uint32_t)), raw.data());
    std::vector<GpuSample> s(count);
    for (size_t i = 0; i < count; ++i)
        s[i] = {raw[2 * i], double(raw[2 * i + 1]) * 0x1p-24};
    return s;
}

} // namespace texspace
