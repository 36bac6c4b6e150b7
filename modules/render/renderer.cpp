// render: the Renderer — GL resources, the profile table, the frame's targets, the resumable
// traversal dispatches and the tone map (see render.h; the algorithms are in the shaders; the
// G-buffer pass: gbuffer_pass.cpp; the state both share: renderer_state.h).
#include "render/renderer_state.h"

#include "core/core.h"
#include "core/text.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>

namespace render {

using namespace renderer_detail;

namespace {

// SSBO and image bindings of shaders/octree_render.comp (and common/octree_*.glsl)
enum : GLuint {
    kDescriptors = 0,
    kNodes = 1,
    kPoints = 2,
    kStats = 3,
    kProfile = 4,
    kExitance = 5,
    kState = 6,
    kControl = 7,
};

// The images of octree_render.comp: the G-buffer's position and normal, the HDR output (the
// renderer's bindings and warmTraversal's, which must agree for the driver's code to match).
void bindTraversalImages(GLuint position, GLuint normal, GLuint hdr) {
    glBindImageTexture(0, position, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, normal, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(2, hdr, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
}

} // namespace

void renderer_detail::validate(const Settings& s) {
    auto fail = [](const std::string& m) { throw core::Error("render", 0, m); };
    if (s.width < 1 || s.height < 1 || s.width > kMaxSide || s.height > kMaxSide)
        fail("image size must lie in [1, " + std::to_string(kMaxSide) + "]², got " +
             std::to_string(s.width) + "x" + std::to_string(s.height));
    if (!std::isfinite(s.eps) || s.eps < 0.0f)
        fail("eps must be finite and >= 0, got " + core::formatNumber(s.eps, 6));
    if (s.maxSteps < 1) fail("maxSteps must be >= 1");
    if (s.stackSize < 1 || s.stackSize > octree::kStackSize)
        fail("stackSize must lie in [1, " + std::to_string(octree::kStackSize) + "], got " +
             std::to_string(s.stackSize));
    if (!std::isfinite(s.gamma) || s.gamma <= 0.0f)
        fail("gamma must be > 0, got " + core::formatNumber(s.gamma, 6));
    if (!std::isfinite(s.exposure)) fail("exposure must be finite");
    const Camera& c = s.camera;
    if (!std::isfinite(c.distance) || c.distance <= 0.0f || !std::isfinite(c.fovY) ||
        c.fovY <= 0.0f || c.fovY >= 3.1f)
        fail("camera distance must be > 0 and fovY in (0, 3.1) rad");
}

octree::Criterion Settings::criterion() const {
    octree::Criterion c;
    c.eps = eps;
    c.boundingBox = boundingBoxCriterion;
    c.secondOrder = secondOrder;
    c.maxSteps = maxSteps;
    c.stackSize = stackSize;
    return c;
}

namespace {

const std::vector<std::pair<GLenum, std::string>> kGbufferStages = {
    {GL_VERTEX_SHADER, "render_gbuffer.vert"}, {GL_FRAGMENT_SHADER, "render_gbuffer.frag"}};
const std::vector<std::pair<GLenum, std::string>> kTonemapStages = {
    {GL_COMPUTE_SHADER, "render_tonemap.comp"}};
} // namespace

Renderer::Renderer(shader::Sources src) : m(std::make_unique<State>()) {
    m->src = std::move(src);
    m->gbufferProgram = shader::build(m->src, kGbufferStages, m->records["render_gbuffer"]);
    m->tonemapProgram = shader::build(m->src, kTonemapStages, m->records["render_tonemap.comp"]);
    const float dummy[8] = {};
    m->tableBuffer = gl::createBuffer(sizeof(dummy), dummy);
    const uint32_t zero[4] = {};
    m->control = gl::createBuffer(sizeof(zero), zero);
    m->invalidCounts = gl::createBuffer(sizeof(zero), zero);
}

Renderer::~Renderer() = default;

void Renderer::setMesh(const mesh::Mesh& input) {
    if (input.vertices.empty() || input.triangles.empty())
        throw core::Error("render", 0, "mesh has no triangles");
    mesh::Mesh copy;
    const mesh::Mesh* mp = &input;
    if (input.normals.size() != input.vertices.size()) {
        copy = input;
        mesh::computeVertexNormals(copy);
        mp = &copy;
    }
    const mesh::Mesh& msh = *mp;
    std::vector<float> interleaved;
    interleaved.reserve(msh.vertices.size() * 6);
    glm::vec3 lo(msh.vertices[0][0], msh.vertices[0][1], msh.vertices[0][2]), hi = lo;
    for (size_t i = 0; i < msh.vertices.size(); ++i) {
        const auto& v = msh.vertices[i];
        const auto& n = msh.normals[i];
        interleaved.insert(interleaved.end(), {v[0], v[1], v[2], n[0], n[1], n[2]});
        lo = glm::min(lo, glm::vec3(v[0], v[1], v[2]));
        hi = glm::max(hi, glm::vec3(v[0], v[1], v[2]));
    }
    gl::Buffer vbo = gl::createBuffer(interleaved.size() * sizeof(float), interleaved.data());
    gl::Buffer ebo =
        gl::createBuffer(msh.triangles.size() * 3 * sizeof(uint32_t), msh.triangles.data());
    GLuint vao = 0;
    glCreateVertexArrays(1, &vao);
    glVertexArrayVertexBuffer(vao, 0, vbo.id(), 0, 6 * sizeof(float));
    glVertexArrayElementBuffer(vao, ebo.id());
    glEnableVertexArrayAttrib(vao, 0);
    glEnableVertexArrayAttrib(vao, 1);
    glVertexArrayAttribFormat(vao, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribFormat(vao, 1, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float));
    glVertexArrayAttribBinding(vao, 0, 0);
    glVertexArrayAttribBinding(vao, 1, 0);
    m->vao = gl::VertexArray(vao);
    m->vbo = std::move(vbo);
    m->ebo = std::move(ebo);
    m->indexCount = static_cast<GLsizei>(msh.triangles.size() * 3);
    m->meshLo = lo;
    m->meshHi = hi;
    m->hasMesh = true;
}

void Renderer::setOctree(const octree::Octree& t) {
    if (t.descriptors.empty() || t.points.empty() || t.nodes.size() != t.descriptors.size())
        throw core::Error("render", 0, "octree is empty or inconsistent");
    m->descriptors =
        gl::createBuffer(t.descriptors.size() * sizeof(uint32_t), t.descriptors.data());
    m->nodes = gl::createBuffer(t.nodes.size() * sizeof(octree::NodeRecord), t.nodes.data());
    m->points = gl::createBuffer(t.points.size() * sizeof(octree::PointRecord), t.points.data());
    m->nodeCount = static_cast<uint32_t>(t.nodes.size());
    m->pointCount = static_cast<uint32_t>(t.points.size());
    glm::vec3 lo(t.points[0].positionArea[0], t.points[0].positionArea[1],
                 t.points[0].positionArea[2]);
    glm::vec3 hi = lo;
    for (const auto& p : t.points) {
        const glm::vec3 q(p.positionArea[0], p.positionArea[1], p.positionArea[2]);
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    m->treeLo = lo;
    m->treeHi = hi;
    m->hasOctree = true;
}

void Renderer::updateAttributes(const octree::Octree& t) {
    if (!m->hasOctree || t.nodes.size() != m->nodeCount || t.points.size() != m->pointCount) {
        setOctree(t);
        return;
    }
    glNamedBufferSubData(m->nodes.id(), 0,
                         static_cast<GLsizeiptr>(t.nodes.size() * sizeof(octree::NodeRecord)),
                         t.nodes.data());
    glNamedBufferSubData(m->points.id(), 0,
                         static_cast<GLsizeiptr>(t.points.size() * sizeof(octree::PointRecord)),
                         t.points.data());
}

void Renderer::setModel(const bssrdf::Model& model) {
    shader::Records records = m->records; // replaced only when every program builds
    gl::Program render = bssrdf::buildModelProgram(model, "octree_render.comp", m->src,
                                                   records["octree_render.comp"]);
    gl::Program pairs =
        bssrdf::buildModelProgram(model, "render_pairs.comp", m->src, records["render_pairs.comp"]);
    gl::Program profile;
    records.erase("pencil_profile.comp");
    if (model.attrs.radial)
        profile = bssrdf::buildModelProgram(model, "pencil_profile.comp", m->src,
                                            records["pencil_profile.comp"]);
    m->records = std::move(records);
    m->values =
        m->model ? bssrdf::carryOver(model, *m->model, m->values) : bssrdf::defaultValues(model);
    m->model = model;
    m->renderProgram = std::move(render);
    m->pairsProgram = std::move(pairs);
    m->profileProgram = std::move(profile);
    m->tableValid = false;
    m->table = {};
    m->iterations = kIterationsPerDispatch;
}

shader::Reloaded Renderer::reloadShaders(const std::vector<std::filesystem::path>& changed) {
    shader::Reloaded out;
    for (auto& [name, record] : m->records) {
        if (!record.dependencies.containsAny(changed)) continue;
        try {
            if (name == "render_gbuffer") {
                m->gbufferProgram = shader::build(m->src, kGbufferStages, record);
            } else if (name == "render_tonemap.comp") {
                m->tonemapProgram = shader::build(m->src, kTonemapStages, record);
            } else if (m->model) {
                gl::Program p = bssrdf::buildModelProgram(*m->model, name, m->src, record);
                if (name == "octree_render.comp") {
                    m->renderProgram = std::move(p);
                } else if (name == "render_pairs.comp") {
                    m->pairsProgram = std::move(p);
                } else if (name == "pencil_profile.comp") {
                    m->profileProgram = std::move(p);
                    m->tableValid = false;
                    m->table = {};
                }
            }
            ++out.rebuilt;
        } catch (const core::Error& e) {
            if (out.problem.empty()) out.problem = e.what();
        }
    }
    return out;
}

const shader::Records& Renderer::shaderRecords() const {
    return m->records;
}

void Renderer::setMaterial(const bssrdf::ParamValues& values, const bssrdf::Builtins& b) {
    m->values = values;
    m->builtins = b;
    m->tableValid = false;
}

bool Renderer::ready() const {
    return m->hasMesh && m->hasOctree && m->model.has_value();
}

const ProfileTable& Renderer::profileTable() const {
    return m->table;
}

const ProfileTable& Renderer::prepareProfileTable() {
    if (!ready()) throw core::Error("render", 0, "not ready: mesh, octree and model first");
    if (m->model->attrs.radial) m->ensureProfile();
    return m->table;
}

const bssrdf::Builtins& Renderer::builtins() const {
    return m->builtins;
}

// Rows per band: all of them when the frame's state fits the storage block limit, else the most
// that fit, a multiple of the rows that keep each band's offset into stats and exitance (16
// bytes a pixel) a multiple of GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT (at most 256: 16 rows).
int Renderer::State::rowsPerBand(int w, int h) const {
    int64_t limit = storageBlockLimit;
    if (limit <= 0) glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &limit);
    const int64_t rowBytes = int64_t(w) * int64_t(kPixelStateBytes);
    const int64_t fit = limit / rowBytes;
    if (fit >= h) return h;
    GLint align = 1;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
    int step = 1;
    while ((int64_t(step) * w * 16) % std::max(align, 1) != 0)
        ++step;
    return static_cast<int>(std::max<int64_t>(step, fit - fit % step));
}

void Renderer::State::resize(int w, int h) {
    const int rows = rowsPerBand(w, h);
    if (w == width && h == height && fbo && rows == bandRows) return;
    position = gl::createTexture2D(GL_RGBA32F, w, h, GL_NEAREST);
    normal = gl::createTexture2D(GL_RGBA32F, w, h, GL_NEAREST);
    depth = gl::createTexture2D(GL_DEPTH_COMPONENT32F, w, h, GL_NEAREST);
    hdr = gl::createTexture2D(GL_RGBA32F, w, h, GL_NEAREST);
    ldr = gl::createTexture2D(GL_RGBA8, w, h, GL_LINEAR);
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    fbo = gl::FramebufferId(id);
    glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT0, position.id(), 0);
    glNamedFramebufferTexture(id, GL_COLOR_ATTACHMENT1, normal.id(), 0);
    glNamedFramebufferTexture(id, GL_DEPTH_ATTACHMENT, depth.id(), 0);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(id, 2, buffers);
    const GLenum status = glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw core::Error(
            "render", 0, "G-buffer framebuffer incomplete (status " + std::to_string(status) + ")");
    const size_t pixels = size_t(w) * size_t(h);
    stats = gl::createBuffer(pixels * 16, nullptr);
    exitance = gl::createBuffer(pixels * 16, nullptr);
    state = gl::createBuffer(size_t(w) * size_t(rows) * kPixelStateBytes, nullptr);
    bandRows = rows;
    width = w;
    height = h;
}

void Renderer::State::ensureProfile() {
    const glm::vec3 lo = glm::min(meshLo, treeLo), hi = glm::max(meshHi, treeHi);
    const glm::vec3 d = hi - lo;
    const double diag = std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z);
    const double cap = diag * double(builtins.scale) * (1.0 + 1e-3) + 1e-9;
    if (tableValid && cap == tableCap) return;
    gl::ScopedStageTimer timer("render.profile");
    table = buildProfileTable(profileProgram.id(), *model, values, builtins, cap);
    std::vector<float> data(table.values.size() * 4);
    for (size_t k = 0; k < table.values.size(); ++k) {
        data[4 * k] = table.values[k].x;
        data[4 * k + 1] = table.values[k].y;
        data[4 * k + 2] = table.values[k].z;
        data[4 * k + 3] = profileRadius(table.rMax, int(k), int(table.values.size()));
    }
    tableBuffer = gl::createBuffer(data.size() * sizeof(float), data.data());
    tableValid = true;
    tableCap = cap;
}

// Runs the traversal dispatches of one frame; returns the number of dispatches. Sets
// loopLimit when a dispatch was cut short by the driver's loop limit.
void Renderer::State::bindTraverse(const Settings& s, uint32_t perDispatch, int band) {
    const int first = band * bandRows, end = std::min(height, first + bandRows);
    // the band's share of the frame's stats and exitance, and the band's state
    const auto pixelsBefore = GLintptr(first) * GLintptr(width);
    const auto bandPixels = GLsizeiptr(end - first) * GLsizeiptr(width);
    const GLuint prog = renderProgram.id();
    bssrdf::setUniforms(prog, *model, values, builtins); // also glUseProgram
    auto loc = [&](const char* n) { return glGetUniformLocation(prog, n); };
    Camera cam = s.camera;
    cam.aspect = float(width) / float(height);
    const glm::vec3 eye = cam.position();
    glUniform2i(loc("RenderSize"), width, height);
    glUniform2i(loc("RenderRows"), first, end);
    glUniform1i(loc("RenderBruteForce"), s.bruteForce ? 1 : 0);
    glUniform1i(loc("RenderBoundingBox"), s.boundingBoxCriterion ? 1 : 0);
    glUniform1i(loc("RenderDirect"), s.directBssrdf ? 1 : 0);
    glUniform1i(loc("RenderSecondOrder"), s.secondOrder ? 1 : 0);
    glUniform1f(loc("RenderEps"), s.eps);
    glUniform1ui(loc("RenderMaxSteps"), s.maxSteps);
    glUniform1ui(loc("RenderStackSize"), static_cast<GLuint>(s.stackSize));
    glUniform1ui(loc("RenderIterations"), perDispatch);
    glUniform1ui(loc("RenderPointCount"), pointCount);
    glUniform3f(loc("RenderCameraPosition"), eye.x, eye.y, eye.z);
    glUniform1ui(loc("RenderSentinel"), 2u);
    glUniform1i(loc("RenderWeightGlobal"), s.weight.global ? 1 : 0);
    glUniform3f(loc("RenderWeightRp"), s.weight.rp.x, s.weight.rp.y, s.weight.rp.z);
    glUniform1f(loc("RenderWeightK"), s.weight.k);
    glUniform1f(loc("ProfileRMax"), table.rMax > 0.0f ? table.rMax : 1.0f);
    glUniform1ui(loc("ProfileCount"),
                 static_cast<GLuint>(std::max<size_t>(table.values.size(), 2)));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kDescriptors, descriptors.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kNodes, nodes.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kPoints, points.id());
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kStats, stats.id(), pixelsBefore * 16,
                      bandPixels * 16);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kProfile, tableBuffer.id());
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kExitance, exitance.id(), pixelsBefore * 16,
                      bandPixels * 16);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, kState, state.id(), 0,
                      bandPixels * GLsizeiptr(kPixelStateBytes));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kControl, control.id());
    bindTraversalImages(position.id(), normal.id(), hdr.id());
}

bool Renderer::State::dispatchOnce(const Settings& s, uint32_t perDispatch, int band, int dispatch,
                                   bool& loopLimit) {
    // Loop iterations a pixel can need: each step is one visit plus at most one move to the
    // next node and one pop; every point evaluation is one more (<= N), a second-order node's
    // terms two more (<= 2·steps).
    const double need = 4.0 * double(s.maxSteps) + double(pointCount) + 2.0;
    const int maxDispatches = static_cast<int>(std::ceil(need / double(perDispatch))) + 2;
    if (dispatch >= maxDispatches)
        throw core::Error("render", 0,
                          "traversal did not finish within " + std::to_string(maxDispatches) +
                              " dispatches");
    bindTraverse(s, perDispatch, band);
    const GLuint prog = renderProgram.id();
    const int rows = std::min(height - band * bandRows, bandRows);
    const auto gx = static_cast<GLuint>((width + kLocal - 1) / kLocal);
    const auto gy = static_cast<GLuint>((rows + kLocal - 1) / kLocal);
    const GLuint zero = 0;
    glClearNamedBufferData(control.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    glUniform1i(glGetUniformLocation(prog, "RenderFirst"), dispatch == 0 ? 1 : 0);
    // barrier: the control word's clear and the previous dispatch's suspended stacks → this one
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    loopFaults.arm(prog);
    glDispatchCompute(gx, gy, 1);
    // barrier: octree_render.comp's control word, stacks and HDR image → the readback below, the
    // next dispatch and the tone map
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    uint32_t ctl[2] = {0, 0};
    glGetNamedBufferSubData(control.id(), 0, sizeof(ctl), ctl);
    loopFaults.check(*model);
    loopLimit = ctl[1] != 0;
    return !loopLimit && ctl[0] == 0;
}

InvalidPixels Renderer::State::tonemap(const Settings& s) {
    gl::ScopedStageTimer timer("render.tonemap");
    const GLuint prog = tonemapProgram.id();
    glUseProgram(prog);
    auto loc = [&](const char* n) { return glGetUniformLocation(prog, n); };
    glUniform2i(loc("TonemapSize"), width, height);
    glUniform1f(loc("TonemapExposure"), s.exposure);
    glUniform1f(loc("TonemapGamma"), s.gamma);
    glUniform3f(loc("TonemapBackground"), s.background.x, s.background.y, s.background.z);
    glBindImageTexture(0, hdr.id(), 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, ldr.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
    uint32_t counts[4] = {};
    glNamedBufferSubData(invalidCounts.id(), 0, sizeof(counts), counts);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, invalidCounts.id());
    glDispatchCompute(static_cast<GLuint>((width + kLocal - 1) / kLocal),
                      static_cast<GLuint>((height + kLocal - 1) / kLocal), 1);
    // barrier: render_tonemap.comp's LDR image and invalid-pixel counts → the readback below,
    // the display (ImGui samples the image) and the image's readback
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT |
                    GL_TEXTURE_UPDATE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(invalidCounts.id(), 0, sizeof(counts), counts);
    return {counts[0], counts[1], counts[2], counts[3]};
}

void warmTraversal(GLuint program, int width, int height) {
    if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide)
        throw core::Error("render", 0,
                          "image size must lie in [1, " + std::to_string(kMaxSide) + "]², got " +
                              std::to_string(width) + "x" + std::to_string(height));
    // the images of State::resize and State::bindTraverse, at the frame's size
    const gl::Texture position = gl::createTexture2D(GL_RGBA32F, width, height, GL_NEAREST);
    const gl::Texture normal = gl::createTexture2D(GL_RGBA32F, width, height, GL_NEAREST);
    const gl::Texture hdr = gl::createTexture2D(GL_RGBA32F, width, height, GL_NEAREST);
    glUseProgram(program);
    glUniform2i(glGetUniformLocation(program, "RenderSize"), 0, 0); // every invocation returns
    const gl::Buffer none = gl::createBuffer(64, nullptr); // no buffer binding left undefined
    for (GLuint b : {kDescriptors, kNodes, kPoints, kStats, kProfile, kExitance, kState, kControl})
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, none.id());
    bindTraversalImages(position.id(), normal.id(), hdr.id());
    glDispatchCompute(1, 1, 1);
    glFinish();
    for (GLuint unit = 0; unit < 3; ++unit)
        glBindImageTexture(unit, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
}

Frame Renderer::render(const Settings& s) {
    begin(s);
    while (!advance(1e30)) {
    }
    return m->progress.frame;
}

void Renderer::begin(const Settings& s) {
    validate(s);
    if (!ready())
        throw core::Error("render", 0,
                          std::string("not ready: ") + (m->hasMesh ? "" : "no mesh; ") +
                              (m->hasOctree ? "" : "no octree; ") + (m->model ? "" : "no model"));
    m->resize(s.width, s.height);
    State::Progress& p = m->progress;
    p = State::Progress{};
    p.settings = s;
    Frame& f = p.frame;
    f.width = s.width;
    f.height = s.height;
    f.bands = (m->height + m->bandRows - 1) / m->bandRows;

    core::Stopwatch clock;
    m->gbuffer(s, m->fbo.id(), m->width, m->height);
    m->useGiven();
    glFinish();
    f.gbufferMs = clock.ms();

    clock.reset();
    const bool table = m->model->attrs.radial && !s.directBssrdf;
    if (table) m->ensureProfile();
    glFinish();
    f.profileMs = clock.ms();
    f.iterationsPerDispatch = std::min(
        m->iterations, s.iterationsPerDispatch ? s.iterationsPerDispatch : kIterationsPerDispatch);
    f.ldr = m->ldr.id();
    f.hdr = m->hdr.id();
    f.position = m->position.id();
    f.normal = m->normal.id();
    p.active = true;
}

bool Renderer::advance(double budgetMs) {
    State::Progress& p = m->progress;
    if (!p.active) return true;
    Frame& f = p.frame;
    const Settings& s = p.settings;
    core::Stopwatch clock;
    bool done = false;
    {
        gl::ScopedStageTimer timer("render.traverse");
        while (!done && clock.ms() < budgetMs) {
            bool loopLimit = false;
            const bool bandDone =
                m->dispatchOnce(s, f.iterationsPerDispatch, p.band, p.dispatch, loopLimit);
            ++p.dispatch;
            ++f.dispatches;
            if (bandDone) { // the next band starts at its first dispatch
                ++p.band;
                p.dispatch = 0;
                done = p.band * m->bandRows >= m->height;
            }
            if (!loopLimit) continue;
            if (f.iterationsPerDispatch <= kMinIterations) {
                core::logWarn("render: the driver's loop limit cut the traversal short even "
                              "at " +
                              std::to_string(f.iterationsPerDispatch) + " iterations per dispatch");
                // mark every unfinished-looking pixel: the shader cannot tell, so flag all hits
                std::vector<glm::uvec4> st(size_t(m->width) * size_t(m->height));
                glGetNamedBufferSubData(m->stats.id(), 0,
                                        static_cast<GLsizeiptr>(st.size() * sizeof(glm::uvec4)),
                                        st.data());
                for (auto& v : st)
                    v.z |= kFlagLoopLimit;
                glNamedBufferSubData(m->stats.id(), 0,
                                     static_cast<GLsizeiptr>(st.size() * sizeof(glm::uvec4)),
                                     st.data());
                done = true;
                break;
            }
            // Redo the band's traversal with half the iterations per dispatch (the bands before
            // it are done: the split does not change a pixel's result).
            m->iterations = f.iterationsPerDispatch / 2;
            f.iterationsPerDispatch = m->iterations;
            p.dispatch = 0;
            core::logInfo("render: the driver's loop limit was hit; retrying with " +
                          std::to_string(m->iterations) + " iterations per dispatch");
        }
        glFinish();
    }
    p.traverseMs += clock.ms();
    f.traverseMs = p.traverseMs;
    if (!done) return false;
    clock.reset();
    f.invalid = m->tonemap(s);
    glFinish();
    f.tonemapMs = clock.ms();
    p.active = false;
    return true;
}

void Renderer::setStorageBlockLimit(int64_t bytes) {
    m->storageBlockLimit = bytes;
}

bool Renderer::inProgress() const {
    return m->progress.active;
}
const Frame& Renderer::currentFrame() const {
    return m->progress.frame;
}

Readback Renderer::readback() const {
    Readback r;
    if (!m->fbo) return r;
    r.width = m->width;
    r.height = m->height;
    const size_t n = size_t(r.width) * size_t(r.height);
    readTexels(m->hdr.id(), n, r.hdr);
    readTexels(m->position.id(), n, r.position);
    readTexels(m->normal.id(), n, r.normal);
    r.exitance.resize(n);
    glGetNamedBufferSubData(m->exitance.id(), 0, static_cast<GLsizeiptr>(n * sizeof(glm::vec4)),
                            r.exitance.data());
    r.stats.resize(n);
    glGetNamedBufferSubData(m->stats.id(), 0, static_cast<GLsizeiptr>(n * sizeof(glm::uvec4)),
                            r.stats.data());
    r.ldr.resize(n * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(m->ldr.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(n * 4),
                      r.ldr.data());
    return r;
}

std::vector<glm::vec3> Renderer::evaluatePairs(const std::vector<BssrdfPair>& pairs) const {
    if (!m->model) throw core::Error("render", 0, "no model");
    return render::evaluatePairs(m->pairsProgram.id(), *m->model, m->values, m->builtins, pairs);
}

} // namespace render
