// gl hazards: the memory-barrier rules of OpenGL 4.5 core §7.13.2 checked while the program runs.
// Writes by shaders to buffers (shader storage blocks) and to images (image stores) are
// incoherent: a later command sees them only after a glMemoryBarrier with the bit for the way it
// reads them (a dispatch's storage block: SHADER_STORAGE; a sampler: TEXTURE_FETCH; an image
// load: SHADER_IMAGE_ACCESS; glGet/glBuffer/glClear/glCopy*BufferSubData: BUFFER_UPDATE;
// glGetTextureImage, glTextureSubImage: TEXTURE_UPDATE; framebuffer reads and clears:
// FRAMEBUFFER; vertex, index and indirect buffers: VERTEX_ATTRIB_ARRAY, ELEMENT_ARRAY, COMMAND).
// Mesa llvmpipe runs every dispatch to its end before the next command, so a missing barrier
// never shows there; a GPU reads stale caches. This tracker records, per buffer and texture, the
// barrier bits owed since the last dispatch or draw that may have written it (every storage
// block not declared `readonly`, every image unit bound with write access), clears them at each
// glMemoryBarrier, and reports a read that comes before its bit as a GL debug message of type
// UNDEFINED_BEHAVIOR (the tests fail on it: tests/support/gl_debug_guard.cpp). It also checks, at
// each dispatch and draw, that every shadow sampler meets a depth texture with comparison on and
// every plain sampler one with it off (NVIDIA reports the mismatch; Mesa says nothing), and it
// fills storage made without data with a pattern ("poison" below). At each dispatch and draw it
// also checks that no storage block the program reads or writes is bound over more bytes than the
// driver's GL_MAX_SHADER_STORAGE_BLOCK_SIZE (llvmpipe: 2^27, and it addresses more anyway; a GPU
// need not: NVIDIA's is 2^31 - 1). What is only written is not
// read: a storage block declared `writeonly` or an image unit bound GL_WRITE_ONLY may be written
// again by the next dispatch without a barrier (two dispatches' writes to one location are not
// checked).
//
// It sits between the program and the driver by replacing libepoxy's function pointers of the
// calls it watches (epoxy_glDispatchCompute, ...) with its own, which call the driver's
// function (eglGetProcAddress). Written by hand: OpenGL has no validation layer for barriers
// (Vulkan's synchronisation validation has no GL counterpart), and no packaged library checks
// them. Granularity: whole objects (a read of one range of a buffer written elsewhere counts).
#include "detail/hazards.h"
#include "gl.h"

#include <epoxy/egl.h>

#include <cctype>
#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace gl {
namespace barriers { // named: the unity build puts timing.cpp's anonymous namespace beside this
namespace {

constexpr GLbitfield kBufferWrite =
    GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT |
    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
    GL_PIXEL_BUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_ATOMIC_COUNTER_BARRIER_BIT |
    GL_CLIENT_MAPPED_BUFFER_BARRIER_BIT | GL_QUERY_BUFFER_BARRIER_BIT;
constexpr GLbitfield kTextureWrite = GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                                     GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                                     GL_FRAMEBUFFER_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT;

const char* bitName(GLbitfield bit) {
    switch (bit) {
    case GL_SHADER_STORAGE_BARRIER_BIT:
        return "GL_SHADER_STORAGE_BARRIER_BIT";
    case GL_BUFFER_UPDATE_BARRIER_BIT:
        return "GL_BUFFER_UPDATE_BARRIER_BIT";
    case GL_UNIFORM_BARRIER_BIT:
        return "GL_UNIFORM_BARRIER_BIT";
    case GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT:
        return "GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT";
    case GL_ELEMENT_ARRAY_BARRIER_BIT:
        return "GL_ELEMENT_ARRAY_BARRIER_BIT";
    case GL_COMMAND_BARRIER_BIT:
        return "GL_COMMAND_BARRIER_BIT";
    case GL_PIXEL_BUFFER_BARRIER_BIT:
        return "GL_PIXEL_BUFFER_BARRIER_BIT";
    case GL_TEXTURE_FETCH_BARRIER_BIT:
        return "GL_TEXTURE_FETCH_BARRIER_BIT";
    case GL_SHADER_IMAGE_ACCESS_BARRIER_BIT:
        return "GL_SHADER_IMAGE_ACCESS_BARRIER_BIT";
    case GL_TEXTURE_UPDATE_BARRIER_BIT:
        return "GL_TEXTURE_UPDATE_BARRIER_BIT";
    case GL_FRAMEBUFFER_BARRIER_BIT:
        return "GL_FRAMEBUFFER_BARRIER_BIT";
    default:
        return "a barrier bit";
    }
}

// What a program reads and writes, from its interface (queried once per program).
struct ProgramIo {
    std::string name;                    // its label: the template's path
    std::vector<GLuint> storageBindings; // the active storage blocks not declared writeonly
    std::vector<GLuint> writtenBindings; // those not declared readonly
    std::vector<GLuint> uniformBindings; // active uniform blocks
    struct Sampler {
        GLint location = -1;
        GLenum binding = 0; // the binding query of its target
        bool shadow = false;
    };
    std::vector<Sampler> samplers;
    std::vector<GLint> images; // locations of image uniforms
    bool queried = false;
};

struct Pending {
    GLbitfield bits = 0; // barrier bits still owed
    std::string writer;  // the program that wrote it last
};

struct State {
    std::map<GLuint, Pending> buffers, textures;
    std::map<GLuint, ProgramIo> programs;
    std::map<GLuint, std::set<std::string>> readonlyBlocks; // by program, from its sources
    std::map<GLuint, std::set<std::string>> writeonlyBlocks;
    std::set<std::string> reported;
};

std::mutex g_mutex;
std::map<void*, State> g_states; // by EGL context (GLX windows share one entry)
bool g_requested = false;
bool g_installed = false;

State& state() {
    return g_states[reinterpret_cast<void*>(eglGetCurrentContext())];
}

GLenum samplerBinding(GLenum type) {
    switch (type) {
    case GL_SAMPLER_2D:
    case GL_SAMPLER_2D_SHADOW:
    case GL_INT_SAMPLER_2D:
    case GL_UNSIGNED_INT_SAMPLER_2D:
        return GL_TEXTURE_BINDING_2D;
    case GL_SAMPLER_3D:
    case GL_INT_SAMPLER_3D:
    case GL_UNSIGNED_INT_SAMPLER_3D:
        return GL_TEXTURE_BINDING_3D;
    case GL_SAMPLER_CUBE:
    case GL_SAMPLER_CUBE_SHADOW:
        return GL_TEXTURE_BINDING_CUBE_MAP;
    case GL_SAMPLER_2D_ARRAY:
    case GL_SAMPLER_2D_ARRAY_SHADOW:
    case GL_INT_SAMPLER_2D_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_2D_ARRAY:
        return GL_TEXTURE_BINDING_2D_ARRAY;
    case GL_SAMPLER_1D:
        return GL_TEXTURE_BINDING_1D;
    default:
        return 0;
    }
}

bool isImage(GLenum type) {
    switch (type) {
    case GL_IMAGE_2D:
    case GL_IMAGE_3D:
    case GL_IMAGE_CUBE:
    case GL_IMAGE_2D_ARRAY:
    case GL_INT_IMAGE_2D:
    case GL_UNSIGNED_INT_IMAGE_2D:
    case GL_INT_IMAGE_3D:
    case GL_UNSIGNED_INT_IMAGE_3D:
    case GL_INT_IMAGE_2D_ARRAY:
    case GL_UNSIGNED_INT_IMAGE_2D_ARRAY:
    case GL_IMAGE_1D:
    case GL_IMAGE_BUFFER:
        return true;
    default:
        return false;
    }
}

std::string resourceName(GLuint program, GLenum interface, GLuint index) {
    char name[256] = {0};
    GLsizei length = 0;
    glGetProgramResourceName(program, interface, index, sizeof name, &length, name);
    return std::string(name, static_cast<size_t>(length));
}

ProgramIo& programIo(State& st, GLuint program) {
    ProgramIo& io = st.programs[program];
    if (io.queried) return io;
    io.queried = true;
    char label[512] = {0};
    GLsizei length = 0;
    glGetObjectLabel(GL_PROGRAM, program, sizeof label, &length, label);
    io.name = length > 0 ? std::string(label, static_cast<size_t>(length))
                         : "program " + std::to_string(program);
    const std::set<std::string>& readonly = st.readonlyBlocks[program];
    const std::set<std::string>& writeonly = st.writeonlyBlocks[program];
    GLint count = 0;
    glGetProgramInterfaceiv(program, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &count);
    for (GLint i = 0; i < count; ++i) {
        const GLenum prop = GL_BUFFER_BINDING;
        GLint binding = 0;
        glGetProgramResourceiv(program, GL_SHADER_STORAGE_BLOCK, static_cast<GLuint>(i), 1, &prop,
                               1, nullptr, &binding);
        const std::string block =
            resourceName(program, GL_SHADER_STORAGE_BLOCK, static_cast<GLuint>(i));
        if (!writeonly.count(block)) io.storageBindings.push_back(static_cast<GLuint>(binding));
        if (!readonly.count(block)) io.writtenBindings.push_back(static_cast<GLuint>(binding));
    }
    glGetProgramInterfaceiv(program, GL_UNIFORM_BLOCK, GL_ACTIVE_RESOURCES, &count);
    for (GLint i = 0; i < count; ++i) {
        const GLenum prop = GL_BUFFER_BINDING;
        GLint binding = 0;
        glGetProgramResourceiv(program, GL_UNIFORM_BLOCK, static_cast<GLuint>(i), 1, &prop, 1,
                               nullptr, &binding);
        io.uniformBindings.push_back(static_cast<GLuint>(binding));
    }
    glGetProgramInterfaceiv(program, GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
    for (GLint i = 0; i < count; ++i) {
        const GLenum props[] = {GL_TYPE, GL_LOCATION};
        GLint v[2] = {0, -1};
        glGetProgramResourceiv(program, GL_UNIFORM, static_cast<GLuint>(i), 2, props, 2, nullptr,
                               v);
        if (v[1] < 0) continue;
        const GLenum type = static_cast<GLenum>(v[0]);
        if (const GLenum b = samplerBinding(type))
            io.samplers.push_back({v[1], b,
                                   type == GL_SAMPLER_2D_SHADOW || type == GL_SAMPLER_CUBE_SHADOW ||
                                       type == GL_SAMPLER_2D_ARRAY_SHADOW});
        if (isImage(type)) io.images.push_back(v[1]);
    }
    return io;
}

void report(State& st, const std::string& call, const std::string& what, GLuint id,
            const Pending& p, GLbitfield bit) {
    const std::string key = call + "|" + what + "|" + p.writer + "|" + bitName(bit);
    if (!st.reported.insert(key).second) return;
    detail::reportDebugMessage(
        GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR, GL_DEBUG_SEVERITY_HIGH,
        "barrier missing: " + call + " reads " + what + " " + std::to_string(id) + ", which " +
            p.writer + " wrote, with no glMemoryBarrier(" + bitName(bit) +
            ") in between (OpenGL 4.5 section 7.13.2)");
}

void need(State& st, std::map<GLuint, Pending>& objects, GLuint id, GLbitfield bit,
          const std::string& call, const char* what) {
    if (id == 0) return;
    auto it = objects.find(id);
    if (it == objects.end() || !(it->second.bits & bit)) return;
    report(st, call, what, id, it->second, bit);
    it->second.bits &= ~bit;
}

// A shadow sampler must meet a depth texture with comparison on, a plain sampler one with it off
// (OpenGL 4.5 §8.23.1 and §11.1.3.5: otherwise the results are undefined; NVIDIA reports it).
// The comparison mode comes from the sampler object bound to the unit, else from the texture.
void checkComparison(State& st, const std::string& by, bool shadow, GLuint texture,
                     GLuint samplerObject, GLint unit) {
    if (texture == 0) {
        if (!shadow) return;
        const std::string message = "sampler state: " + by + " has a shadow sampler on unit " +
                                    std::to_string(unit) + ", which has no texture bound";
        if (!st.reported.insert(message).second) return;
        detail::reportDebugMessage(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR,
                                   GL_DEBUG_SEVERITY_HIGH, message);
        return;
    }
    GLint depthBits = 0;
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_DEPTH_SIZE, &depthBits);
    if (depthBits == 0) return; // comparisons apply to depth textures only
    GLint mode = GL_NONE;
    if (samplerObject)
        glGetSamplerParameteriv(samplerObject, GL_TEXTURE_COMPARE_MODE, &mode);
    else
        glGetTextureParameteriv(texture, GL_TEXTURE_COMPARE_MODE, &mode);
    if (shadow == (mode != GL_NONE)) return;
    const std::string where = samplerObject ? "sampler object " + std::to_string(samplerObject)
                                            : "texture " + std::to_string(texture) + "'s own state";
    const std::string message =
        "sampler state: " + by + " samples depth texture " + std::to_string(texture) + " on unit " +
        std::to_string(unit) + " through a " +
        (shadow ? "shadow sampler, but " + where + " has depth comparison off"
                : "non-shadow sampler, but " + where + " has depth comparison on") +
        " (undefined results, OpenGL 4.5 section 11.1.3.5)";
    if (!st.reported.insert(message).second) return;
    detail::reportDebugMessage(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR,
                               GL_DEBUG_SEVERITY_HIGH, message);
}

GLuint indexedBinding(GLenum target, GLuint index) {
    GLint id = 0;
    glGetIntegeri_v(target, index, &id);
    return static_cast<GLuint>(id);
}

// The texture and sampler on each of the program's sampler units: their comparison mode, and
// with `fetch` (a dispatch or draw, which reads them) the texture-fetch barrier owed.
void samplerState(State& st, GLuint program, const ProgramIo& io, const std::string& by,
                  bool fetch) {
    if (io.samplers.empty()) return;
    GLint active = 0;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
    for (const ProgramIo::Sampler& sampler : io.samplers) {
        GLint unit = 0;
        glGetUniformiv(program, sampler.location, &unit);
        glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
        GLint texture = 0, samplerObject = 0;
        glGetIntegerv(sampler.binding, &texture);
        glGetIntegerv(GL_SAMPLER_BINDING, &samplerObject);
        if (fetch)
            need(st, st.textures, static_cast<GLuint>(texture), GL_TEXTURE_FETCH_BARRIER_BIT, by,
                 "texture");
        checkComparison(st, by, sampler.shadow, static_cast<GLuint>(texture),
                        static_cast<GLuint>(samplerObject), unit);
    }
    glActiveTexture(static_cast<GLenum>(active));
}

// Every storage block of the program bound over at most GL_MAX_SHADER_STORAGE_BLOCK_SIZE bytes
// (a range, or the whole buffer from its start): a larger binding addresses storage the driver
// does not promise to reach (gl::requireStorageBlock is the program's own check).
void storageBlockSizes(State& st, const ProgramIo& io, const std::string& by) {
    const int64_t limit = maxStorageBlockBytes();
    std::set<GLuint> bindings(io.storageBindings.begin(), io.storageBindings.end()); // read
    bindings.insert(io.writtenBindings.begin(), io.writtenBindings.end());
    for (GLuint b : bindings) {
        const GLuint id = indexedBinding(GL_SHADER_STORAGE_BUFFER_BINDING, b);
        if (id == 0) continue;
        GLint64 size = 0, start = 0;
        glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, b, &size);
        glGetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, b, &start);
        if (size == 0) { // glBindBufferBase: the whole buffer
            glGetNamedBufferParameteri64v(id, GL_BUFFER_SIZE, &size);
            size -= start;
        }
        if (size <= limit) continue;
        const std::string message =
            "storage block too large: " + by + " binds " + std::to_string(size) +
            " bytes of buffer " + std::to_string(id) + " at binding " + std::to_string(b) +
            ", more than GL_MAX_SHADER_STORAGE_BLOCK_SIZE (" + std::to_string(limit) + ")";
        if (!st.reported.insert(message).second) continue;
        detail::reportDebugMessage(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR,
                                   GL_DEBUG_SEVERITY_HIGH, message);
    }
}

// What the current program reads (checked) and may write (recorded) in a dispatch or draw.
void programAccess(const std::string& call) {
    GLint program = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &program);
    if (program == 0) return;
    State& st = state();
    const ProgramIo& io = programIo(st, static_cast<GLuint>(program));
    const std::string by = call + " of " + io.name;
    storageBlockSizes(st, io, by);
    for (GLuint b : io.storageBindings)
        need(st, st.buffers, indexedBinding(GL_SHADER_STORAGE_BUFFER_BINDING, b),
             GL_SHADER_STORAGE_BARRIER_BIT, by, "storage buffer");
    for (GLuint b : io.uniformBindings)
        need(st, st.buffers, indexedBinding(GL_UNIFORM_BUFFER_BINDING, b), GL_UNIFORM_BARRIER_BIT,
             by, "uniform buffer");
    std::vector<GLuint> writtenImages;
    for (GLint location : io.images) {
        GLint unit = 0;
        glGetUniformiv(static_cast<GLuint>(program), location, &unit);
        const GLuint texture = indexedBinding(GL_IMAGE_BINDING_NAME, static_cast<GLuint>(unit));
        const GLuint access = indexedBinding(GL_IMAGE_BINDING_ACCESS, static_cast<GLuint>(unit));
        if (access != static_cast<GLuint>(GL_WRITE_ONLY))
            need(st, st.textures, texture, GL_SHADER_IMAGE_ACCESS_BARRIER_BIT, by, "image");
        if (texture && access != static_cast<GLuint>(GL_READ_ONLY))
            writtenImages.push_back(texture);
    }
    samplerState(st, static_cast<GLuint>(program), io, by, true);
    for (GLuint b : io.writtenBindings)
        if (GLuint id = indexedBinding(GL_SHADER_STORAGE_BUFFER_BINDING, b))
            st.buffers[id] = {kBufferWrite, "the " + call + " of " + io.name};
    for (GLuint id : writtenImages)
        st.textures[id] = {kTextureWrite, "the " + call + " of " + io.name};
}

// NVIDIA validates the current program's sampler state at clears as at draws (seen: "a sampler
// (0) that has depth comparisons disabled, with a texture object (0) ... shadow sampler" at the
// shadow pass's depth clear while the irradiance program stayed current with its maps unbound).
void currentProgramSamplers(const std::string& call) {
    GLint program = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &program);
    if (program == 0) return;
    State& st = state();
    const ProgramIo& io = programIo(st, static_cast<GLuint>(program));
    samplerState(st, static_cast<GLuint>(program), io, call + " while " + io.name + " is current",
                 false);
}

void framebufferAccess(GLenum binding, const std::string& call) {
    GLint fbo = 0;
    glGetIntegerv(binding, &fbo);
    if (fbo == 0) return;
    State& st = state();
    for (GLenum attachment : {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                              GL_COLOR_ATTACHMENT3, GL_DEPTH_ATTACHMENT}) {
        GLint type = GL_NONE, name = 0;
        glGetNamedFramebufferAttachmentParameteriv(static_cast<GLuint>(fbo), attachment,
                                                   GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
        if (type != GL_TEXTURE) continue;
        glGetNamedFramebufferAttachmentParameteriv(static_cast<GLuint>(fbo), attachment,
                                                   GL_FRAMEBUFFER_ATTACHMENT_OBJECT_NAME, &name);
        need(st, st.textures, static_cast<GLuint>(name), GL_FRAMEBUFFER_BARRIER_BIT, call,
             "framebuffer texture");
    }
}

void drawAccess(const std::string& call) {
    framebufferAccess(GL_DRAW_FRAMEBUFFER_BINDING, call);
    programAccess(call);
    State& st = state();
    GLint vao = 0;
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
    if (vao == 0) return;
    GLint element = 0;
    glGetVertexArrayiv(static_cast<GLuint>(vao), GL_ELEMENT_ARRAY_BUFFER_BINDING, &element);
    need(st, st.buffers, static_cast<GLuint>(element), GL_ELEMENT_ARRAY_BARRIER_BIT, call,
         "index buffer");
    for (GLuint i = 0; i < 8; ++i) {
        GLint enabled = 0, buffer = 0;
        glGetVertexArrayIndexediv(static_cast<GLuint>(vao), i, GL_VERTEX_ATTRIB_ARRAY_ENABLED,
                                  &enabled);
        if (!enabled) continue;
        glGetVertexArrayIndexediv(static_cast<GLuint>(vao), i,
                                  GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &buffer);
        need(st, st.buffers, static_cast<GLuint>(buffer), GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT, call,
             "vertex buffer");
    }
}

void bufferUpdate(GLuint buffer, const char* call) {
    State& st = state();
    need(st, st.buffers, buffer, GL_BUFFER_UPDATE_BARRIER_BIT, call, "buffer");
}

GLuint boundBuffer(GLenum target);

void textureUpdate(GLuint texture, const char* call) {
    State& st = state();
    need(st, st.textures, texture, GL_TEXTURE_UPDATE_BARRIER_BIT, call, "texture");
}

// A pixel transfer from or to a bound pixel buffer reads or writes that buffer.
void pixelBuffer(GLenum target, const char* call) {
    State& st = state();
    need(st, st.buffers, boundBuffer(target), GL_PIXEL_BUFFER_BARRIER_BIT, call, "pixel buffer");
}

GLuint boundBuffer(GLenum target) {
    GLenum binding = 0;
    switch (target) {
    case GL_ARRAY_BUFFER:
        binding = GL_ARRAY_BUFFER_BINDING;
        break;
    case GL_SHADER_STORAGE_BUFFER:
        binding = GL_SHADER_STORAGE_BUFFER_BINDING;
        break;
    case GL_UNIFORM_BUFFER:
        binding = GL_UNIFORM_BUFFER_BINDING;
        break;
    case GL_PIXEL_PACK_BUFFER:
        binding = GL_PIXEL_PACK_BUFFER_BINDING;
        break;
    case GL_PIXEL_UNPACK_BUFFER:
        binding = GL_PIXEL_UNPACK_BUFFER_BINDING;
        break;
    case GL_COPY_READ_BUFFER:
        binding = GL_COPY_READ_BUFFER_BINDING;
        break;
    case GL_COPY_WRITE_BUFFER:
        binding = GL_COPY_WRITE_BUFFER_BINDING;
        break;
    case GL_DISPATCH_INDIRECT_BUFFER:
        binding = GL_DISPATCH_INDIRECT_BUFFER_BINDING;
        break;
    default:
        return 0;
    }
    GLint id = 0;
    glGetIntegerv(binding, &id);
    return static_cast<GLuint>(id);
}

void forget(std::map<GLuint, Pending>& objects, GLsizei n, const GLuint* ids) {
    for (GLsizei i = 0; i < n; ++i)
        objects.erase(ids[i]);
}

// ---- poison -------------------------------------------------------------------------------------
// Storage made without data is undefined (OpenGL 4.5 §6.2, §8.19): Mesa hands out zeros, other
// drivers whatever the memory held. With the checks on, new storage is filled with a pattern
// instead (a quiet NaN in each 32-bit float, 0xAB in each byte of a normalized texel, 0xDEADBEEF in
// each integer), so code that reads it before writing it fails here as it would elsewhere. Depth
// textures are left as they are (every use clears them first).
constexpr GLuint kPoisonWord = 0x7FC0DEADu; // a quiet NaN as a float

void poisonBuffer(GLuint buffer, GLsizeiptr size);
void poisonTexture(GLuint texture, GLenum internalFormat);

// ---- the hooks ----------------------------------------------------------------------------------
// Each replaces epoxy's pointer; g_<name> holds the driver's function. `before` runs with the
// tracker's lock held, then the driver's function, then `after`.
#define BW_HOOK(name, params, args, before, after)                                                 \
    decltype(epoxy_##name) g_##name = nullptr;                                                     \
    void GLAPIENTRY hook_##name params {                                                           \
        {                                                                                          \
            std::lock_guard<std::mutex> lock(g_mutex);                                             \
            before;                                                                                \
        }                                                                                          \
        g_##name args;                                                                             \
        {                                                                                          \
            std::lock_guard<std::mutex> lock(g_mutex);                                             \
            after;                                                                                 \
        }                                                                                          \
    }

BW_HOOK(glDispatchCompute, (GLuint x, GLuint y, GLuint z), (x, y, z),
        programAccess("glDispatchCompute"), )
BW_HOOK(
    glDispatchComputeIndirect, (GLintptr offset), (offset), {
        State& st = state();
        need(st, st.buffers, boundBuffer(GL_DISPATCH_INDIRECT_BUFFER), GL_COMMAND_BARRIER_BIT,
             "glDispatchComputeIndirect", "indirect buffer");
        programAccess("glDispatchComputeIndirect");
    }, )
BW_HOOK(glDrawArrays, (GLenum mode, GLint first, GLsizei count), (mode, first, count),
        drawAccess("glDrawArrays"), )
BW_HOOK(glDrawElements, (GLenum mode, GLsizei count, GLenum type, const void* indices),
        (mode, count, type, indices), drawAccess("glDrawElements"), )
BW_HOOK(glMemoryBarrier, (GLbitfield bits), (bits), , {
    for (auto& [context, st] : g_states) {
        for (auto& [id, p] : st.buffers)
            p.bits &= ~bits;
        for (auto& [id, p] : st.textures)
            p.bits &= ~bits;
    }
})
BW_HOOK(glGetNamedBufferSubData, (GLuint buffer, GLintptr offset, GLsizeiptr size, void* data),
        (buffer, offset, size, data), bufferUpdate(buffer, "glGetNamedBufferSubData"), )
BW_HOOK(glGetBufferSubData, (GLenum target, GLintptr offset, GLsizeiptr size, void* data),
        (target, offset, size, data), bufferUpdate(boundBuffer(target), "glGetBufferSubData"), )
BW_HOOK(glNamedBufferSubData, (GLuint buffer, GLintptr offset, GLsizeiptr size, const void* data),
        (buffer, offset, size, data), bufferUpdate(buffer, "glNamedBufferSubData"), )
BW_HOOK(glBufferSubData, (GLenum target, GLintptr offset, GLsizeiptr size, const void* data),
        (target, offset, size, data), bufferUpdate(boundBuffer(target), "glBufferSubData"), )
BW_HOOK(glClearNamedBufferData,
        (GLuint buffer, GLenum internalformat, GLenum format, GLenum type, const void* data),
        (buffer, internalformat, format, type, data),
        bufferUpdate(buffer, "glClearNamedBufferData"), )
BW_HOOK(glClearNamedBufferSubData,
        (GLuint buffer, GLenum internalformat, GLintptr offset, GLsizeiptr size, GLenum format,
         GLenum type, const void* data),
        (buffer, internalformat, offset, size, format, type, data),
        bufferUpdate(buffer, "glClearNamedBufferSubData"), )
BW_HOOK(
    glCopyNamedBufferSubData,
    (GLuint from, GLuint to, GLintptr readOffset, GLintptr writeOffset, GLsizeiptr size),
    (from, to, readOffset, writeOffset, size), {
        bufferUpdate(from, "glCopyNamedBufferSubData");
        bufferUpdate(to, "glCopyNamedBufferSubData");
    }, )
BW_HOOK(
    glGetTextureImage,
    (GLuint texture, GLint level, GLenum format, GLenum type, GLsizei size, void* pixels),
    (texture, level, format, type, size, pixels), {
        textureUpdate(texture, "glGetTextureImage");
        pixelBuffer(GL_PIXEL_PACK_BUFFER, "glGetTextureImage");
    }, )
BW_HOOK(glGetTextureSubImage,
        (GLuint texture, GLint level, GLint x, GLint y, GLint z, GLsizei w, GLsizei h, GLsizei d,
         GLenum format, GLenum type, GLsizei size, void* pixels),
        (texture, level, x, y, z, w, h, d, format, type, size, pixels),
        textureUpdate(texture, "glGetTextureSubImage"), )
BW_HOOK(
    glTextureSubImage2D,
    (GLuint texture, GLint level, GLint x, GLint y, GLsizei w, GLsizei h, GLenum format,
     GLenum type, const void* pixels),
    (texture, level, x, y, w, h, format, type, pixels), {
        textureUpdate(texture, "glTextureSubImage2D");
        pixelBuffer(GL_PIXEL_UNPACK_BUFFER, "glTextureSubImage2D");
    }, )
BW_HOOK(
    glTextureSubImage3D,
    (GLuint texture, GLint level, GLint x, GLint y, GLint z, GLsizei w, GLsizei h, GLsizei d,
     GLenum format, GLenum type, const void* pixels),
    (texture, level, x, y, z, w, h, d, format, type, pixels), {
        textureUpdate(texture, "glTextureSubImage3D");
        pixelBuffer(GL_PIXEL_UNPACK_BUFFER, "glTextureSubImage3D");
    }, )
BW_HOOK(
    glCopyImageSubData,
    (GLuint src, GLenum srcTarget, GLint srcLevel, GLint srcX, GLint srcY, GLint srcZ, GLuint dst,
     GLenum dstTarget, GLint dstLevel, GLint dstX, GLint dstY, GLint dstZ, GLsizei w, GLsizei h,
     GLsizei d),
    (src, srcTarget, srcLevel, srcX, srcY, srcZ, dst, dstTarget, dstLevel, dstX, dstY, dstZ, w, h,
     d),
    {
        if (srcTarget != GL_RENDERBUFFER) textureUpdate(src, "glCopyImageSubData");
        if (dstTarget != GL_RENDERBUFFER) textureUpdate(dst, "glCopyImageSubData");
    }, )
BW_HOOK(
    glReadPixels,
    (GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, void* pixels),
    (x, y, w, h, format, type, pixels), {
        framebufferAccess(GL_READ_FRAMEBUFFER_BINDING, "glReadPixels");
        pixelBuffer(GL_PIXEL_PACK_BUFFER, "glReadPixels");
    }, )
BW_HOOK(
    glClearNamedFramebufferfv,
    (GLuint framebuffer, GLenum buffer, GLint drawbuffer, const GLfloat* value),
    (framebuffer, buffer, drawbuffer, value), {
        GLint current = 0;
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &current);
        if (static_cast<GLuint>(current) == framebuffer)
            framebufferAccess(GL_DRAW_FRAMEBUFFER_BINDING, "glClearNamedFramebufferfv");
        currentProgramSamplers("glClearNamedFramebufferfv");
    }, )
BW_HOOK(
    glClear, (GLbitfield mask), (mask), {
        framebufferAccess(GL_DRAW_FRAMEBUFFER_BINDING, "glClear");
        currentProgramSamplers("glClear");
    }, )
BW_HOOK(glNamedBufferStorage, (GLuint buffer, GLsizeiptr size, const void* data, GLbitfield flags),
        (buffer, size, data, flags), , {
            if (!data) poisonBuffer(buffer, size);
        })
BW_HOOK(glTextureStorage2D, (GLuint texture, GLsizei levels, GLenum format, GLsizei w, GLsizei h),
        (texture, levels, format, w, h), , poisonTexture(texture, format))
BW_HOOK(glTextureStorage3D,
        (GLuint texture, GLsizei levels, GLenum format, GLsizei w, GLsizei h, GLsizei d),
        (texture, levels, format, w, h, d), , poisonTexture(texture, format))
BW_HOOK(glCreateBuffers, (GLsizei n, GLuint* ids), (n, ids), , forget(state().buffers, n, ids))
BW_HOOK(glCreateTextures, (GLenum target, GLsizei n, GLuint* ids), (target, n, ids), ,
        forget(state().textures, n, ids))
BW_HOOK(glGenTextures, (GLsizei n, GLuint* ids), (n, ids), , forget(state().textures, n, ids))
BW_HOOK(glLinkProgram, (GLuint program), (program), , state().programs.erase(program))
#undef BW_HOOK

void poisonBuffer(GLuint buffer, GLsizeiptr size) {
    if (!g_glClearNamedBufferData || size <= 0) return;
    if (size % 4 == 0) {
        g_glClearNamedBufferData(buffer, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &kPoisonWord);
    } else {
        const GLubyte b = 0xAB;
        g_glClearNamedBufferData(buffer, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &b);
    }
}

void poisonTexture(GLuint texture, GLenum internalFormat) {
    static const GLuint words[4] = {kPoisonWord, kPoisonWord, kPoisonWord, kPoisonWord};
    static const GLuint integers[4] = {0xDEADBEEFu, 0xDEADBEEFu, 0xDEADBEEFu, 0xDEADBEEFu};
    static const GLubyte bytes[4] = {0xAB, 0xAB, 0xAB, 0xAB};
    switch (internalFormat) {
    case GL_RGBA32F:
    case GL_RGB32F:
    case GL_RG32F:
    case GL_R32F:
    case GL_RGBA16F:
    case GL_RGB16F:
    case GL_RG16F:
    case GL_R16F:
        glClearTexImage(texture, 0, GL_RGBA, GL_FLOAT, words);
        break;
    case GL_RGBA8:
    case GL_SRGB8_ALPHA8:
    case GL_RGB8:
    case GL_RG8:
    case GL_R8:
        glClearTexImage(texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, bytes);
        break;
    case GL_R32UI:
    case GL_RG32UI:
    case GL_RGBA32UI:
        glClearTexImage(texture, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, integers);
        break;
    case GL_R32I:
    case GL_RG32I:
    case GL_RGBA32I:
        glClearTexImage(texture, 0, GL_RGBA_INTEGER, GL_INT, integers);
        break;
    default:
        break; // depth and others: left undefined
    }
}

template <typename Fn>
void install(Fn& slot, Fn& driver, Fn hook, const char* name, ProcResolver resolve) {
    auto f = reinterpret_cast<Fn>(resolve(name));
    if (!f) return; // the driver lacks it: nothing to check
    driver = f;
    slot = hook;
}

} // namespace
} // namespace barriers

namespace detail {
void noteProgramSources(GLuint program, const std::vector<ShaderStage>& stages) {
    using namespace barriers;
    if (!g_installed) return;
    // `layout(...) readonly buffer Name {`: memory qualifiers stand between the declaration's
    // start (after `)`, `;`, `{` or `}`) and `buffer`
    const auto word = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    };
    std::set<std::string> readonly, writeonly;
    for (const ShaderStage& s : stages) {
        const std::string& t = s.source;
        for (size_t at = t.find("buffer"); at != std::string::npos; at = t.find("buffer", at + 6)) {
            if ((at > 0 && word(t[at - 1])) || (at + 6 < t.size() && word(t[at + 6]))) continue;
            size_t name = t.find_first_not_of(" \t\r\n", at + 6);
            size_t end = name;
            while (end < t.size() && word(t[end]))
                ++end;
            const size_t brace = t.find_first_not_of(" \t\r\n", end);
            if (name == std::string::npos || end == name || brace == std::string::npos ||
                t[brace] != '{')
                continue;
            const size_t start = t.find_last_of(");{}", at);
            const std::string qualifiers = t.substr(start == std::string::npos ? 0 : start,
                                                    at - (start == std::string::npos ? 0 : start));
            if (qualifiers.find("readonly") != std::string::npos)
                readonly.insert(t.substr(name, end - name));
            if (qualifiers.find("writeonly") != std::string::npos)
                writeonly.insert(t.substr(name, end - name));
        }
    }
    std::lock_guard<std::mutex> lock(g_mutex);
    State& st = state();
    st.readonlyBlocks[program] = std::move(readonly);
    st.writeonlyBlocks[program] = std::move(writeonly);
    st.programs.erase(program);
}
} // namespace detail

void requestBarrierChecks() {
    using namespace barriers;
    g_requested = true;
}

bool barrierChecksActive() {
    using namespace barriers;
    return g_installed;
}

void installBarrierChecks(ProcResolver resolve) {
    using namespace barriers;
    const char* env = std::getenv("BSSRDF_WORKBENCH_GL_BARRIERS");
    if (env && *env && std::string(env) != "0") g_requested = true;
    std::lock_guard<std::mutex> lock(g_mutex);
    if (!g_requested || g_installed) return;
    g_installed = true;
#define BW_INSTALL(name) install(epoxy_##name, g_##name, hook_##name, #name, resolve)
    BW_INSTALL(glDispatchCompute);
    BW_INSTALL(glDispatchComputeIndirect);
    BW_INSTALL(glDrawArrays);
    BW_INSTALL(glDrawElements);
    BW_INSTALL(glMemoryBarrier);
    BW_INSTALL(glGetNamedBufferSubData);
    BW_INSTALL(glGetBufferSubData);
    BW_INSTALL(glNamedBufferSubData);
    BW_INSTALL(glBufferSubData);
    BW_INSTALL(glClearNamedBufferData);
    BW_INSTALL(glClearNamedBufferSubData);
    BW_INSTALL(glCopyNamedBufferSubData);
    BW_INSTALL(glGetTextureImage);
    BW_INSTALL(glGetTextureSubImage);
    BW_INSTALL(glTextureSubImage2D);
    BW_INSTALL(glTextureSubImage3D);
    BW_INSTALL(glCopyImageSubData);
    BW_INSTALL(glReadPixels);
    BW_INSTALL(glClearNamedFramebufferfv);
    BW_INSTALL(glClear);
    BW_INSTALL(glNamedBufferStorage);
    BW_INSTALL(glTextureStorage2D);
    BW_INSTALL(glTextureStorage3D);
    BW_INSTALL(glCreateBuffers);
    BW_INSTALL(glCreateTextures);
    BW_INSTALL(glGenTextures);
    BW_INSTALL(glLinkProgram);
#undef BW_INSTALL
}

void checkTextureFetch(GLuint texture, const char* reader) {
    using namespace barriers;
    if (!g_installed) return;
    std::lock_guard<std::mutex> lock(g_mutex);
    State& st = state();
    need(st, st.textures, texture, GL_TEXTURE_FETCH_BARRIER_BIT, reader, "texture");
}

void forgetBarrierState() {
    using namespace barriers;
    std::lock_guard<std::mutex> lock(g_mutex);
    g_states.erase(reinterpret_cast<void*>(eglGetCurrentContext()));
}

} // namespace gl
