// irradiance/stage: scene upload, projected texture, environment and irradiance cubemap, the
// Directional / Filtered / Ibl passes (irradiance.h). Occluded IBL is in stage_occluded.cpp.
#include "irradiance/irradiance.h"

#include "core/core.h"
#include "irradiance/programs.h"
#include "irradiance/projected_texture.h"
#include "irradiance/shadow_maps.h"

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace irradiance {
namespace {
constexpr GLuint kGroup = 64;                 // local_size_x of the point shaders
constexpr GLuint kMaxGroups = 65535;          // the guaranteed GL_MAX_COMPUTE_WORK_GROUP_COUNT
constexpr uint32_t kNodesPerDispatch = 16384; // cubemap quadrature chunk (llvmpipe loop limit)

bool finite3(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void requireColour(const glm::vec3& c, const char* what) {
    if (!finite3(c) || c.x < 0 || c.y < 0 || c.z < 0)
        throw core::Error(std::string("irradiance setting '") + what +
                          "' must be finite and >= 0 in every channel");
}

int maxTextureSize() {
    GLint v = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &v);
    return v;
}
} // namespace

double fresnelTransmittance(double cosI, double eta) {
    if (cosI <= 0) return 0;
    const double sin2T = (1.0 - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0) return 0;
    const double cosT = std::sqrt(1.0 - sin2T);
    const double rs = (cosI - eta * cosT) / (cosI + eta * cosT);
    const double rp = (eta * cosI - cosT) / (eta * cosI + cosT);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
}

void validateSettings(const Settings& s, int maxTex) {
    const float len = glm::length(s.direction);
    if (!finite3(s.direction) || !(len > 0.0f))
        throw core::Error("irradiance setting 'direction' must be a finite, non-zero vector");
    const int maxSize = maxTex > 0 ? std::min(8192, maxTex) : 8192;
    if (s.shadowMapSize < 16 || s.shadowMapSize > maxSize)
        throw core::Error(
            "irradiance setting 'shadowMapSize' = " + std::to_string(s.shadowMapSize) +
            " is outside [16, " + std::to_string(maxSize) + "]");
    requireColour(s.irradiance, "irradiance");
    if (!std::isfinite(s.depthOffset) || s.depthOffset < 0)
        throw core::Error("irradiance setting 'depthOffset' must be finite and >= 0");
    if (!std::isfinite(s.slopeOffset) || s.slopeOffset < 0)
        throw core::Error("irradiance setting 'slopeOffset' must be finite and >= 0");
    if (s.jitterSamples < 1 || s.jitterSamples > 16)
        throw core::Error("irradiance setting 'jitterSamples' must be in [1, 16]");
    if (!std::isfinite(s.jitterRadius) || s.jitterRadius < 0 || s.jitterRadius > 64)
        throw core::Error("irradiance setting 'jitterRadius' must be in [0, 64] texels");
    if (!(s.ior >= 1.0f && s.ior <= 4.0f))
        throw core::Error("irradiance setting 'ior' must be in [1, 4]");
    if (!std::isfinite(s.envIntensity) || s.envIntensity < 0)
        throw core::Error("irradiance setting 'envIntensity' must be finite and >= 0");
    if (!std::isfinite(s.envRotation))
        throw core::Error("irradiance setting 'envRotation' must be finite");
    if (s.occludedSamplesPerStep < 1 || s.occludedSamplesPerStep > 64)
        throw core::Error("irradiance setting 'occludedSamplesPerStep' must be in [1, 64]");
    if (s.occludedTotalSamples < 1 || s.occludedTotalSamples > (1 << 20))
        throw core::Error("irradiance setting 'occludedTotalSamples' must be in [1, 2^20]");
    if (s.mode == LightMode::OccludedIbl) {
        const double bytes =
            4.0 * s.shadowMapSize * double(s.shadowMapSize) * s.occludedSamplesPerStep;
        if (bytes > 512.0 * 1024 * 1024)
            throw core::Error("irradiance settings: occludedSamplesPerStep shadow maps of " +
                              std::to_string(s.shadowMapSize) + "² texels need more than 512 MiB");
    }
}

namespace {
using Stages = std::vector<std::pair<GLenum, std::string>>;
// The module's programs, built in this order.
const std::vector<std::pair<std::string, Stages>>& programs() {
    static const std::vector<std::pair<std::string, Stages>> table = {
        {"irradiance_shadow",
         {{GL_VERTEX_SHADER, "irradiance_shadow.vert"},
          {GL_FRAGMENT_SHADER, "irradiance_shadow.frag"}}},
        {"irradiance_direct.comp", {{GL_COMPUTE_SHADER, "irradiance_direct.comp"}}},
        {"irradiance_ibl.comp", {{GL_COMPUTE_SHADER, "irradiance_ibl.comp"}}},
        {"irradiance_cubemap.comp", {{GL_COMPUTE_SHADER, "irradiance_cubemap.comp"}}},
        {"irradiance_occluded.comp", {{GL_COMPUTE_SHADER, "irradiance_occluded.comp"}}},
    };
    return table;
}
} // namespace

Stage::Stage(std::filesystem::path shaderDir) : m_sources(shader::Sources::forFolder(shaderDir)) {
    for (const auto& [name, stages] : programs())
        install(name, shader::build(m_sources, stages, m_records[name]));
    useCheckerTexture();
}

void Stage::install(const std::string& name, gl::Program program) {
    if (name == "irradiance_shadow") {
        if (m_shadow)
            m_shadow->setProgram(std::move(program));
        else
            m_shadow = std::make_unique<ShadowMaps>(std::move(program));
    } else if (name == "irradiance_direct.comp") {
        m_direct = std::move(program);
    } else if (name == "irradiance_ibl.comp") {
        m_ibl = std::move(program);
    } else if (name == "irradiance_cubemap.comp") {
        m_cubeProgram = std::move(program);
        m_cubeGeneration = ~0ull; // the cubemap is recomputed with the new program
    } else if (name == "irradiance_occluded.comp") {
        m_occluded = std::move(program);
    }
}

shader::Reloaded Stage::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    shader::Reloaded out;
    for (const auto& [name, stages] : programs()) {
        shader::Record& record = m_records[name];
        if (!record.dependencies.containsAny(changed)) continue;
        try {
            install(name, shader::build(m_sources, stages, record));
            ++out.rebuilt;
        } catch (const core::Error& e) {
            if (out.problem.empty()) out.problem = e.what();
        }
    }
    return out;
}

Stage::~Stage() = default;

void Stage::setScene(const mesh::Mesh& m, const std::vector<glm::vec3>& positions,
                     const std::vector<glm::vec3>& normals) {
    if (positions.size() != normals.size())
        throw core::Error("irradiance: " + std::to_string(positions.size()) + " positions but " +
                          std::to_string(normals.size()) + " normals");
    if (positions.size() > 0xffffffffu / 2) throw core::Error("irradiance: too many points");
    std::vector<glm::vec4> gpu(2 * positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        const float len = glm::length(normals[i]);
        if (!finite3(positions[i]) || !finite3(normals[i]) || !(len > 0.0f))
            throw core::Error("irradiance: point " + std::to_string(i) +
                              " has a non-finite position or a zero / non-finite normal");
        gpu[2 * i] = glm::vec4(positions[i], 1.0f);
        gpu[2 * i + 1] = glm::vec4(normals[i] / len, 0.0f);
    }
    for (const auto& v : m.vertices)
        if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
            throw core::Error("irradiance: the mesh has a non-finite vertex");
    cancelOccluded();
    m_shadow->setMesh(m);
    m_bounds = boundingSphere(m, positions);
    m_pointCount = positions.size();
    const size_t n = std::max<size_t>(m_pointCount, 1);
    m_points = gpu.empty() ? gl::createBuffer(2 * sizeof(glm::vec4), nullptr)
                           : gl::createBuffer(gpu.size() * sizeof(glm::vec4), gpu.data());
    m_result = gl::createBuffer(n * sizeof(glm::vec4), nullptr);
    for (auto& b : m_sums)
        b = gl::createBuffer(2 * n * sizeof(glm::vec4), nullptr);
}

void Stage::setScene(const mesh::Mesh& m, const pointcloud::PointCloud& cloud) {
    std::vector<glm::vec3> p(cloud.points.size()), n(cloud.points.size());
    for (size_t i = 0; i < p.size(); ++i) {
        const auto& q = cloud.points[i];
        p[i] = glm::vec3(q.p[0], q.p[1], q.p[2]);
        n[i] = glm::vec3(q.n[0], q.n[1], q.n[2]);
    }
    setScene(m, p, n);
}

void Stage::setProjectedTexture(int width, int height, const std::vector<float>& rgb,
                                const std::string& name) {
    EnvironmentMap check; // same checks as an environment: size, finite, >= 0
    check.width = width;
    check.height = height;
    check.rgb = rgb;
    validateEnvironment(check, name);
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    gl::Texture tex(id);
    glTextureStorage2D(id, 1, GL_RGB32F, width, height);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    // image row 0 (the top) is v near 1: upload the rows bottom-up
    std::vector<float> flipped(rgb.size());
    const size_t row = 3 * static_cast<size_t>(width);
    for (int y = 0; y < height; ++y)
        std::copy_n(rgb.begin() + static_cast<std::ptrdiff_t>(row * y), row,
                    flipped.begin() + static_cast<std::ptrdiff_t>(row * (height - 1 - y)));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(id, 0, 0, 0, width, height, GL_RGB, GL_FLOAT, flipped.data());
    m_projected = std::move(tex);
    m_projectedSide = std::max(width, height);
    const auto [lo, hi] = std::minmax_element(rgb.begin(), rgb.end());
    m_projectedMin = *lo;
    m_projectedMax = *hi;
}

void Stage::loadProjectedTexture(const std::filesystem::path& path) {
    const detail::RgbImage img = detail::loadRgbImage(path);
    setProjectedTexture(img.width, img.height, img.rgb, path.string());
}

void Stage::useCheckerTexture() {
    const detail::RgbImage img = detail::checkerImage();
    setProjectedTexture(img.width, img.height, img.rgb, "checker");
}

void Stage::setEnvironment(const EnvironmentMap& env, const std::string& name) {
    validateEnvironment(env, name);
    cancelOccluded();
    m_env = env;
    ++m_envGeneration;
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    gl::Texture tex(id);
    glTextureStorage2D(id, 1, GL_RGB32F, env.width, env.height);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(id, 0, 0, 0, env.width, env.height, GL_RGB, GL_FLOAT, env.rgb.data());
    m_envTexture = std::move(tex);
}

void Stage::loadEnvironment(const std::filesystem::path& exr) {
    setEnvironment(readEnvironment(exr), exr.string());
}

GLuint Stage::shadowMapTexture() const {
    return m_shadow->view();
}

void Stage::ensureCubemap(float ior) {
    if (m_cube && m_cubeGeneration == m_envGeneration && m_cubeIor == ior) return;
    std::vector<QuadratureNode> nodes = quadratureNodes(m_env);
    if (nodes.empty()) nodes.push_back({glm::vec3(0, 1, 0), glm::vec3(0.0f)}); // black map
    std::vector<glm::vec4> gpu(2 * nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) {
        gpu[2 * i] = glm::vec4(nodes[i].direction, 0.0f);
        gpu[2 * i + 1] = glm::vec4(nodes[i].weight, 0.0f);
    }
    const gl::Buffer nodeBuf = gl::createBuffer(gpu.size() * sizeof(glm::vec4), gpu.data());
    constexpr int N = kCubeFaceSize;
    const GLuint texels = 6 * N * N;
    // kept: irradiance_ibl.comp filters its lookups from these texels (not the sampler)
    gl::Buffer acc = gl::createBuffer(texels * sizeof(glm::vec4), nullptr);
    glClearNamedBufferData(acc.id(), GL_RGBA32F, GL_RGBA, GL_FLOAT, nullptr);
    const GLuint p = m_cubeProgram.id();
    glUseProgram(p);
    glProgramUniform1i(p, gl::uniformLocation(m_cubeProgram, "FaceSize"), N);
    glProgramUniform1f(p, gl::uniformLocation(m_cubeProgram, "Eta"), ior);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, nodeBuf.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, acc.id());
    for (size_t first = 0; first < nodes.size(); first += kNodesPerDispatch) {
        const size_t count = std::min<size_t>(kNodesPerDispatch, nodes.size() - first);
        glProgramUniform1ui(p, gl::uniformLocation(m_cubeProgram, "FirstNode"),
                            static_cast<GLuint>(first));
        glProgramUniform1ui(p, gl::uniformLocation(m_cubeProgram, "NodeCount"),
                            static_cast<GLuint>(count));
        glDispatchCompute((texels + kGroup - 1) / kGroup, 1, 1);
        // barrier: irradiance_cubemap.comp's sums → the next batch of nodes, which adds to them
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &id);
    gl::Texture cube(id);
    glTextureStorage2D(id, 1, GL_RGBA32F, N, N);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    // barrier: irradiance_cubemap.comp's sums → glTextureSubImage3D's unpack from them
    glMemoryBarrier(GL_PIXEL_BUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, acc.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage3D(id, 0, 0, 0, 0, N, N, 6, GL_RGBA, GL_FLOAT, nullptr);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    m_cube = std::move(cube);
    m_cubeTexels = std::move(acc);
    m_cubeGeneration = m_envGeneration;
    m_cubeIor = ior;
}

void Stage::setShadowUniforms(const gl::Program& prog, const Settings& s) const {
    const GLuint p = prog.id();
    glProgramUniform1i(p, gl::uniformLocation(prog, "ShadowFilter"), static_cast<int>(s.filter));
    glProgramUniform1f(p, gl::uniformLocation(prog, "ShadowTexel"), 1.0f / s.shadowMapSize);
    glProgramUniform1f(p, gl::uniformLocation(prog, "DepthOffset"), s.depthOffset);
    glProgramUniform1f(p, gl::uniformLocation(prog, "SlopeOffset"), s.slopeOffset);
    glProgramUniform1i(p, gl::uniformLocation(prog, "JitterSamples"), s.jitterSamples);
    glProgramUniform1f(p, gl::uniformLocation(prog, "JitterRadius"), s.jitterRadius);
    glProgramUniform1f(p, gl::uniformLocation(prog, "Eta"), s.ior);
    glProgramUniform1ui(p, gl::uniformLocation(prog, "PointCount"),
                        static_cast<GLuint>(m_pointCount));
}

void Stage::dispatchPoints(const gl::Program& prog) const {
    const GLint offset = gl::uniformLocation(prog, "PointOffset");
    const size_t perDispatch = static_cast<size_t>(kMaxGroups) * kGroup;
    for (size_t first = 0; first < m_pointCount; first += perDispatch) {
        const size_t count = std::min(perDispatch, m_pointCount - first);
        glProgramUniform1ui(prog.id(), offset, static_cast<GLuint>(first));
        glDispatchCompute(static_cast<GLuint>((count + kGroup - 1) / kGroup), 1, 1);
    }
    // barrier: the irradiance programs' per-point values → their readback and the renderer's
    // dispatches, which read them
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

std::vector<glm::vec3> Stage::readResult() const {
    std::vector<glm::vec4> v(m_pointCount);
    if (!v.empty())
        glGetNamedBufferSubData(m_result.id(), 0,
                                static_cast<GLsizeiptr>(v.size() * sizeof(glm::vec4)), v.data());
    std::vector<glm::vec3> out(v.size());
    for (size_t i = 0; i < v.size(); ++i)
        out[i] = glm::vec3(v[i]);
    return out;
}

std::vector<glm::vec3> Stage::computeDirect(const Settings& s, glm::vec2 shift) {
    const LightFrame frame = makeLightFrame(s.direction, m_bounds);
    m_lastFrame = frame;
    m_shadow->ensure(s.shadowMapSize, 1);
    m_shadow->render(0, frame, shift);
    const GLuint p = m_direct.id();
    glUseProgram(p);
    setShadowUniforms(m_direct, s);
    glProgramUniform3fv(p, gl::uniformLocation(m_direct, "LightCentre"), 1,
                        glm::value_ptr(frame.centre));
    glProgramUniform1f(p, gl::uniformLocation(m_direct, "LightExtent"), frame.extent);
    glProgramUniform3fv(p, gl::uniformLocation(m_direct, "LightU"), 1, glm::value_ptr(frame.u));
    glProgramUniform3fv(p, gl::uniformLocation(m_direct, "LightV"), 1, glm::value_ptr(frame.v));
    glProgramUniform3fv(p, gl::uniformLocation(m_direct, "LightW"), 1, glm::value_ptr(frame.w));
    glProgramUniform3fv(p, gl::uniformLocation(m_direct, "Irradiance"), 1,
                        glm::value_ptr(s.irradiance));
    glProgramUniform1i(p, gl::uniformLocation(m_direct, "UseProjected"),
                       s.mode == LightMode::Filtered ? 1 : 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_points.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m_result.id());
    m_shadow->bind();
    glBindTextureUnit(2, m_projected.id());
    dispatchPoints(m_direct);
    glUseProgram(0); // no program stays current whose shadow samplers meet unbound units
    m_shadow->unbind();
    return readResult();
}

std::vector<glm::vec3> Stage::computeIbl(const Settings& s) {
    ensureCubemap(s.ior);
    const GLuint p = m_ibl.id();
    glUseProgram(p);
    glProgramUniform1ui(p, gl::uniformLocation(m_ibl, "PointCount"),
                        static_cast<GLuint>(m_pointCount));
    const glm::mat3 envFromWorld = glm::transpose(worldFromEnvironment(s.envRotation));
    glProgramUniformMatrix3fv(p, gl::uniformLocation(m_ibl, "EnvFromWorld"), 1, GL_FALSE,
                              glm::value_ptr(envFromWorld));
    glProgramUniform1f(p, gl::uniformLocation(m_ibl, "EnvIntensity"), s.envIntensity);
    glProgramUniform1i(p, gl::uniformLocation(m_ibl, "FaceSize"), kCubeFaceSize);
    glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS); // the cubemap's display samples it
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m_points.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m_result.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m_cubeTexels.id());
    dispatchPoints(m_ibl);
    return readResult();
}

Stage::Factors Stage::factors(const Settings& s) {
    if (!hasVisibilityFactor(s.mode))
        throw core::Error("irradiance: only directional and filtered light have a visibility "
                          "factor");
    Settings unshadowed = s;
    unshadowed.filter = ShadowFilter::None;
    Factors f;
    f.unshadowed = compute(unshadowed);
    compute(s);
    std::vector<glm::vec4> v(m_pointCount);
    if (!v.empty()) // compute() read the same buffer after its barrier
        glGetNamedBufferSubData(m_result.id(), 0,
                                static_cast<GLsizeiptr>(v.size() * sizeof(glm::vec4)), v.data());
    f.visibility.resize(v.size());
    for (size_t i = 0; i < v.size(); ++i)
        f.visibility[i] = v[i].w;
    return f;
}

std::vector<glm::vec4> Stage::computeShifted(const Settings& s, glm::vec2 shift) {
    if (!hasVisibilityFactor(s.mode))
        throw core::Error("irradiance: only directional and filtered light have a shadow map to "
                          "move");
    validateSettings(s, maxTextureSize());
    if (!m_points) throw core::Error("irradiance: no scene (call setScene first)");
    computeDirect(s, shift);
    std::vector<glm::vec4> v(m_pointCount);
    if (!v.empty()) // computeDirect read the same buffer after its barrier
        glGetNamedBufferSubData(m_result.id(), 0,
                                static_cast<GLsizeiptr>(v.size() * sizeof(glm::vec4)), v.data());
    return v;
}

void Stage::setVertexSnap(const gl::VertexSnap& snap) {
    m_shadow->setVertexSnap(snap);
}

std::vector<float> Stage::visibilitySpread(const Settings& s) {
    std::vector<std::vector<glm::vec4>> moved;
    for (const glm::vec2 shift : rasterShifts())
        moved.push_back(computeShifted(s, shift));
    const std::vector<glm::vec4> v = computeShifted(s, glm::vec2(0.0f)); // last: compute(s)'s state
    std::vector<float> spread(v.size(), 0.0f);
    for (size_t i = 0; i < v.size(); ++i)
        for (const std::vector<glm::vec4>& m : moved)
            spread[i] = std::max(spread[i], std::abs(m[i].w - v[i].w));
    return spread;
}

double Stage::unshadowedSpread(const Settings& s) const {
    if (s.mode != LightMode::Filtered) return 0.0;
    const double delta = 8.0 / 16777216.0;
    const double e0 = std::max({s.irradiance.x, s.irradiance.y, s.irradiance.z});
    return 2.0 * m_projectedSide * delta * (double(m_projectedMax) - m_projectedMin) * e0;
}

std::vector<glm::vec3> Stage::compute(const Settings& s) {
    validateSettings(s, maxTextureSize());
    if (!m_points) throw core::Error("irradiance: no scene (call setScene first)");
    if ((s.mode == LightMode::Ibl || s.mode == LightMode::OccludedIbl) && !hasEnvironment())
        throw core::Error("irradiance: image based lighting needs an environment map");
    switch (s.mode) {
    case LightMode::Directional:
    case LightMode::Filtered:
        return computeDirect(s);
    case LightMode::Ibl:
        return computeIbl(s);
    case LightMode::OccludedIbl:
        break;
    }
    beginOccluded(s);
    while (!stepOccluded()) {
    }
    const std::vector<glm::vec3> mean = occludedResult();
    std::vector<glm::vec4> gpu(mean.size());
    for (size_t i = 0; i < mean.size(); ++i)
        gpu[i] = glm::vec4(mean[i], 1.0f);
    if (!gpu.empty())
        glNamedBufferSubData(m_result.id(), 0, static_cast<GLsizeiptr>(gpu.size() * sizeof(gpu[0])),
                             gpu.data());
    return mean;
}

} // namespace irradiance
