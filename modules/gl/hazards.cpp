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
// every plain sampler one with it off (NVIDIA reports the mismatch; Mesa says nothing), and that
// no storage block the program reads or writes is bound over more bytes than the driver's
// GL_MAX_SHADER_STORAGE_BLOCK_SIZE (hazards_bindings.cpp), and it fills storage made without data
// with a pattern (hazards_poison.cpp). What a program reads and writes comes from its interface
// and its sources (hazards_program.cpp). What is only written is not
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
#include "detail/hazard_state.h"
#include "gl.h"

#include <epoxy/egl.h>

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

std::mutex g_mutex;
std::map<void*, State> g_states; // by EGL context (GLX windows share one entry)
bool g_requested = false;
bool g_installed = false;

} // namespace

State& state() {
    return g_states[reinterpret_cast<void*>(eglGetCurrentContext())];
}

void reportOnce(State& st, const std::string& message, const std::string& key) {
    if (!st.reported.insert(key.empty() ? message : key).second) return;
    detail::reportDebugMessage(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR,
                               GL_DEBUG_SEVERITY_HIGH, message);
}

void need(State& st, std::map<GLuint, Pending>& objects, GLuint id, GLbitfield bit,
          const std::string& call, const char* what) {
    if (id == 0) return;
    auto it = objects.find(id);
    if (it == objects.end() || !(it->second.bits & bit)) return;
    const Pending& p = it->second;
    // once per reader, kind of object, writer and bit (a buffer made anew each frame is one)
    reportOnce(st,
               "barrier missing: " + call + " reads " + what + " " + std::to_string(id) +
                   ", which " + p.writer + " wrote, with no glMemoryBarrier(" + bitName(bit) +
                   ") in between (OpenGL 4.5 section 7.13.2)",
               call + "|" + what + "|" + p.writer + "|" + bitName(bit));
    it->second.bits &= ~bit;
}

namespace {

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
            if (!data) poisonBuffer(buffer, size, g_glClearNamedBufferData);
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
    BlockQualifiers q = blockQualifiers(stages);
    std::lock_guard<std::mutex> lock(g_mutex);
    State& st = state();
    st.readonlyBlocks[program] = std::move(q.readonly);
    st.writeonlyBlocks[program] = std::move(q.writeonly);
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
