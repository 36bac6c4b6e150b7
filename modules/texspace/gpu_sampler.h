// texspace/gpu_sampler: stage 2 of texture-space sampling on the GPU (Chang 2007, Algorithm 3.1
// in a shader, shaders/texspace_sample.comp): the mip-ordered CDF uploaded as float, N texels
// drawn by the descent, each with the u it used, so the CPU replica (sampleMip) can be checked
// against it. Needs a current OpenGL 4.5 context.
#pragma once

#include "gl/gl.h"
#include "shader/program.h"
#include "texspace/texture_space.h"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace texspace {

struct GpuSample {
    uint32_t texel; // row-major index
    double u;       // the uniform number it was drawn with (a multiple of 2^-24)
};

class GpuSampler {
  public:
    // Builds shaders/texspace_sample.comp from `src`; throws core::Error naming file and line.
    explicit GpuSampler(const shader::Sources& src);
    // Uploads the pyramid (as float); at most 16 levels (K <= 32768).
    void setCdf(const MipCdf& cdf);
    // Samples first … first + count − 1 under `seed`.
    std::vector<GpuSample> draw(uint64_t count, uint64_t seed, uint64_t first = 0) const;
    // Hot reload: builds the program again when one of `changed` is among its files; a failure
    // keeps the last good program.
    shader::Reloaded reloadShaders(const std::vector<std::filesystem::path>& changed);
    const shader::Record& record() const { return m_record; }

  private:
    shader::Sources m_src;
    shader::Record m_record; // before m_program: the build fills it
    gl::Program m_program;
    gl::Buffer m_levels;
    std::vector<uint32_t> m_offsets;
    int m_size = 0;
};

} // namespace texspace
