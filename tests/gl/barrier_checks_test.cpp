// The barrier checks (modules/gl/hazards.cpp), which run in every gl test: a read of what a
// shader wrote, with no glMemoryBarrier of the bit for that kind of read in between, is reported
// as undefined behaviour, naming the call, the object, the writer and the bit; the right
// barrier, a readonly block or a read-only image unit make it go away.
#include "../support/gl_debug_guard.h"
#include "core/core.h"
#include "gl/gl.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

gl::Context& context() {
    static auto ctx = gl::createHeadlessContext();
    ctx->makeCurrent();
    return *ctx;
}

const char* kWriter = R"(#version 450
layout(local_size_x = 64) in;
layout(std430, binding = 0) writeonly buffer Out { float v[]; };
layout(std430, binding = 1) readonly buffer In { float w[]; };
void main() { v[gl_GlobalInvocationID.x] = w[gl_GlobalInvocationID.x] + 1.0; })";

const char* kImageWriter = R"(#version 450
layout(local_size_x = 8, local_size_y = 8) in;
layout(rgba32f, binding = 0) uniform writeonly image2D Target;
void main() { imageStore(Target, ivec2(gl_GlobalInvocationID.xy), vec4(1.0)); })";

const char* kSampler = R"(#version 450
layout(local_size_x = 1) in;
layout(binding = 3) uniform sampler2D Source;
layout(std430, binding = 0) writeonly buffer Out { vec4 v[]; };
void main() { v[0] = texelFetch(Source, ivec2(0), 0); })";

struct Buffers {
    gl::Buffer out = gl::createBuffer(64 * sizeof(float), nullptr);
    gl::Buffer in = gl::createBuffer(64 * sizeof(float), std::vector<float>(64, 2.0f).data());
};

void dispatchWriter(const gl::Program& p, const Buffers& b) {
    glUseProgram(p.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, b.out.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, b.in.id());
    glDispatchCompute(1, 1, 1);
}

} // namespace

TEST(BarrierChecks, AreOnInEveryTest) {
    context();
    EXPECT_TRUE(gl::barrierChecksActive());
}

TEST(BarrierChecks, AHostReadWithoutBufferUpdateBarrierIsReported) {
    context();
    gl::Program p = gl::buildProgram({{GL_COMPUTE_SHADER, kWriter}});
    Buffers b;
    std::vector<float> out(64);
    dispatchWriter(p, b);
    EXPECT_NONFATAL_FAILURE(glGetNamedBufferSubData(b.out.id(), 0, 64 * sizeof(float), out.data()),
                            "barrier missing: glGetNamedBufferSubData reads buffer");
    // a barrier of another kind does not help; the right one does
    dispatchWriter(p, b);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    {
        bwtest::ExpectedGlErrors expected;
        glGetNamedBufferSubData(b.out.id(), 0, 64 * sizeof(float), out.data());
        EXPECT_EQ(expected.count(), 0); // reported once per call site and writer, not again
    }
    dispatchWriter(p, b);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(b.out.id(), 0, 64 * sizeof(float), out.data());
    EXPECT_EQ(out[5], 3.0f);
    // the readonly block was never written: reading it needs no barrier
    glGetNamedBufferSubData(b.in.id(), 0, 64 * sizeof(float), out.data());
}

TEST(BarrierChecks, ADispatchReadingAnotherDispatchsOutputNeedsShaderStorage) {
    context();
    gl::Program p = gl::buildProgram({{GL_COMPUTE_SHADER, kWriter}});
    Buffers first, second;
    dispatchWriter(p, first);
    glUseProgram(p.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, second.out.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, first.out.id()); // the first one's output
    EXPECT_NONFATAL_FAILURE(glDispatchCompute(1, 1, 1), "GL_SHADER_STORAGE_BARRIER_BIT");
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

TEST(BarrierChecks, ImageStoresNeedTheirBitBeforeSamplingOrReadingBack) {
    context();
    gl::Program writer = gl::buildProgram({{GL_COMPUTE_SHADER, kImageWriter}});
    gl::Program sampler = gl::buildProgram({{GL_COMPUTE_SHADER, kSampler}});
    gl::Texture t = gl::createTexture2D(GL_RGBA32F, 8, 8);
    gl::Buffer out = gl::createBuffer(4 * sizeof(float), nullptr);
    const auto write = [&] {
        glUseProgram(writer.id());
        glBindImageTexture(0, t.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glDispatchCompute(1, 1, 1);
    };
    write();
    glUseProgram(sampler.id());
    glBindTextureUnit(3, t.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, out.id());
    EXPECT_NONFATAL_FAILURE(glDispatchCompute(1, 1, 1), "GL_TEXTURE_FETCH_BARRIER_BIT");
    std::vector<float> px(8 * 8 * 4);
    write();
    EXPECT_NONFATAL_FAILURE(
        glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, int(px.size() * sizeof(float)), px.data()),
        "GL_TEXTURE_UPDATE_BARRIER_BIT");
    write();
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glUseProgram(sampler.id());
    glDispatchCompute(1, 1, 1);
    glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, int(px.size() * sizeof(float)), px.data());
    EXPECT_EQ(px[0], 1.0f);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

TEST(BarrierChecks, TheMessageNamesTheWritersTemplate) {
    context();
    gl::Program p = gl::buildProgram({{GL_COMPUTE_SHADER, kWriter}});
    glObjectLabel(GL_PROGRAM, p.id(), -1, "shaders/example.comp");
    Buffers b;
    std::vector<float> out(64);
    dispatchWriter(p, b);
    EXPECT_NONFATAL_FAILURE(glGetNamedBufferSubData(b.out.id(), 0, 16, out.data()),
                            "which the glDispatchCompute of shaders/example.comp wrote, with no "
                            "glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT)");
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

// A compute program that samples a depth texture through a shadow sampler on `unit`.
static gl::Program shadowSamplingProgram(int unit) {
    const std::string src = R"(#version 450
layout(local_size_x = 1) in;
layout(binding = )" + std::to_string(unit) +
                            R"() uniform sampler2DShadow Depth;
layout(std430, binding = 0) writeonly buffer Out { float v[]; };
void main() { v[0] = texture(Depth, vec3(0.5, 0.5, 0.5)); })";
    return gl::buildProgram({{GL_COMPUTE_SHADER, src}});
}

// NVIDIA reports a shadow sampler that meets a depth texture with comparison off (Mesa does not):
// the checks report it on every driver, naming the unit and where the state comes from.
TEST(BarrierChecks, AShadowSamplerNeedsDepthComparisonOn) {
    context();
    gl::Program p = shadowSamplingProgram(2);
    gl::Texture depth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, 4, 4);
    gl::Buffer out = gl::createBuffer(sizeof(float), nullptr);
    glUseProgram(p.id());
    glBindTextureUnit(2, depth.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, out.id());
    // (NVIDIA adds its own message: "a sampler (0) that has depth comparisons disabled")
    bwtest::expectGlProblem([] { glDispatchCompute(1, 1, 1); },
                            "through a shadow sampler, but texture " + std::to_string(depth.id()) +
                                "'s own state has depth comparison off");
    glTextureParameteri(depth.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glDispatchCompute(1, 1, 1); // defined now
    GLuint sampler = 0;
    glCreateSamplers(1, &sampler); // a sampler object's state wins over the texture's
    glBindSampler(2, sampler);
    bwtest::expectGlProblem([] { glDispatchCompute(1, 1, 1); }, "but sampler object");
    glBindSampler(2, 0);
    glDeleteSamplers(1, &sampler);
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
}

// NVIDIA checks the current program's samplers at clears too: the irradiance program, left
// current after its dispatch with its shadow maps unbound, made the shadow pass's depth clear
// report "a sampler (0) ... with a texture object (0) ... shadow sampler", and its next dispatch
// read zeros (then the context was reset). The checks report it at every clear, on any driver.
TEST(BarrierChecks, AClearWhileAShadowSamplingProgramIsCurrentNeedsItsMaps) {
    context();
    gl::Program p = shadowSamplingProgram(3);
    gl::Texture depth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, 4, 4);
    GLuint fbo = 0;
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, depth.id(), 0);
    const float one = 1.0f;
    glUseProgram(p.id());
    glBindTextureUnit(3, 0);
    bwtest::expectGlProblem([&] { glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &one); },
                            "glClearNamedFramebufferfv while program " + std::to_string(p.id()) +
                                " is current has a shadow sampler on unit 3, which has no "
                                "texture bound");
    glUseProgram(0); // what the irradiance stage does after its dispatch: nothing to check
    glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &one);
    glDeleteFramebuffers(1, &fbo);
}

// Storage made without data is undefined: Mesa gives zeros, other drivers what the memory held.
// With the checks on it holds a pattern (a NaN per float), so code that reads it first fails.
TEST(BarrierChecks, StorageMadeWithoutDataIsPoisoned) {
    context();
    gl::Buffer b = gl::createBuffer(4 * sizeof(float), nullptr);
    float v[4] = {0, 0, 0, 0};
    glGetNamedBufferSubData(b.id(), 0, sizeof v, v);
    for (float x : v)
        EXPECT_TRUE(std::isnan(x)) << x;
    gl::Texture t = gl::createTexture2D(GL_RGBA32F, 2, 2);
    std::vector<float> px(16);
    glGetTextureImage(t.id(), 0, GL_RGBA, GL_FLOAT, int(px.size() * sizeof(float)), px.data());
    EXPECT_TRUE(std::isnan(px[0]));
    gl::Texture u = gl::createTexture2D(GL_RGBA8, 2, 2);
    std::vector<unsigned char> bytes(16);
    glGetTextureImage(u.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, int(bytes.size()), bytes.data());
    EXPECT_EQ(bytes[0], 0xAB);
    // with data, the data
    const float one[4] = {1, 1, 1, 1};
    gl::Buffer c = gl::createBuffer(sizeof one, one);
    glGetNamedBufferSubData(c.id(), 0, sizeof v, v);
    EXPECT_EQ(v[2], 1.0f);
}

// A storage block bound over more bytes than the driver's GL_MAX_SHADER_STORAGE_BLOCK_SIZE is
// reported at the dispatch (llvmpipe addresses more, a GPU need not: NVIDIA's limit is 2^31 - 1),
// the whole buffer or a range alike; a range of exactly the limit is not. The program's own check,
// gl::requireStorageBlock, names what needs the bytes and how many units the limit allows.
TEST(BarrierChecks, AStorageBlockOverTheDriversLimitIsReported) {
    context();
    const int64_t limit = gl::maxStorageBlockBytes();
    ASSERT_GE(limit, int64_t(1) << 27);
    gl::Program p = gl::buildProgram({{GL_COMPUTE_SHADER, kWriter}});
    Buffers b;
    const gl::Buffer big = gl::createBuffer(size_t(limit) + 256, nullptr);
    glUseProgram(p.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, big.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, b.in.id());
    EXPECT_NONFATAL_FAILURE(glDispatchCompute(1, 1, 1),
                            "storage block too large: glDispatchCompute of");
    glMemoryBarrier(GL_ALL_BARRIER_BITS);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, big.id(), 256, GLsizeiptr(limit));
    glDispatchCompute(1, 1, 1); // exactly the limit: nothing to report
    glMemoryBarrier(GL_ALL_BARRIER_BITS);

    EXPECT_NO_THROW(gl::requireStorageBlock(uint64_t(limit), "hybrid", "pixels", 16));
    try {
        gl::requireStorageBlock(uint64_t(limit) + 1, "hybrid", "pixels", 16);
        ADD_FAILURE() << "no error over the limit";
    } catch (const core::Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("hybrid"), std::string::npos) << m;
        EXPECT_NE(m.find("needs " + std::to_string(limit + 1) + " bytes in one storage buffer"),
                  std::string::npos)
            << m;
        EXPECT_NE(m.find("GL_MAX_SHADER_STORAGE_BLOCK_SIZE (" + std::to_string(limit) +
                         " bytes: at most " + std::to_string(limit / 16) + " pixels)"),
                  std::string::npos)
            << m;
    }
}
