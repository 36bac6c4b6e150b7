// gl RAII objects, render targets, program building and KHR_debug output.
#include "gl.h"

#include "detail/hazards.h"

#include <atomic>
#include <mutex>

#include "core/core.h"

#include <algorithm>
#include <cstring>

namespace gl {

// After a reset the objects went with the context: nothing to delete (contextLost()).
void deleteBuffer(GLuint id) {
    if (!contextLost()) glDeleteBuffers(1, &id);
}
void deleteTexture(GLuint id) {
    if (!contextLost()) glDeleteTextures(1, &id);
}
void deleteFramebuffer(GLuint id) {
    if (!contextLost()) glDeleteFramebuffers(1, &id);
}
void deleteProgram(GLuint id) {
    if (contextLost()) return;
    // A program deleted while it is current stays in use under a name that is no longer valid:
    // whoever saves and restores GL_CURRENT_PROGRAM (ImGui's renderer does, every frame) then
    // calls glUseProgram with it, GL_INVALID_VALUE. Unbind it first.
    GLint current = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    if (GLuint(current) == id) glUseProgram(0);
    glDeleteProgram(id);
}
void deleteVertexArray(GLuint id) {
    if (!contextLost()) glDeleteVertexArrays(1, &id);
}

Buffer createBuffer(size_t bytes, const void* data, GLbitfield flags) {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    glNamedBufferStorage(id, static_cast<GLsizeiptr>(bytes), data, flags);
    return Buffer(id);
}

Texture createTexture2D(GLenum internalFormat, int width, int height, GLenum filter) {
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    glTextureStorage2D(id, 1, internalFormat, width, height);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GLint(filter));
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GLint(filter));
    glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return Texture(id);
}

void RenderTarget::resize(int width, int height, GLenum internalFormat) {
    if (width == m_width && height == m_height && internalFormat == m_format && m_fbo) return;
    m_width = width;
    m_height = height;
    m_format = internalFormat;
    GLuint tex = 0, fbo = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    glTextureStorage2D(tex, 1, internalFormat, width, height);
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, tex, 0);
    GLenum status = glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER);
    m_color = Texture(tex);
    m_fbo = FramebufferId(fbo);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw core::Error("framebuffer incomplete (status 0x" + std::to_string(status) + ")");
}

void RenderTarget::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, m_fbo.id());
    glViewport(0, 0, m_width, m_height);
}

void uploadRGBA8(Texture& texture, int width, int height, const unsigned char* rgba) {
    GLint w = 0, h = 0;
    if (texture) {
        glGetTextureLevelParameteriv(texture.id(), 0, GL_TEXTURE_WIDTH, &w);
        glGetTextureLevelParameteriv(texture.id(), 0, GL_TEXTURE_HEIGHT, &h);
    }
    if (!texture || w != width || h != height) {
        GLuint id = 0;
        glCreateTextures(GL_TEXTURE_2D, 1, &id);
        glTextureStorage2D(id, 1, GL_RGBA8, width, height);
        glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        texture = Texture(id);
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(texture.id(), 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
}

namespace {
std::string shaderLog(GLuint shader) {
    GLint len = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
    glGetShaderInfoLog(shader, len, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    return log;
}
std::string programLog(GLuint program) {
    GLint len = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &len);
    std::string log(static_cast<size_t>(std::max(len, 1)), '\0');
    glGetProgramInfoLog(program, len, nullptr, log.data());
    log.resize(std::strlen(log.c_str()));
    return log;
}
} // namespace

Program buildProgram(const std::vector<ShaderStage>& stages) {
    Program program(glCreateProgram());
    std::vector<GLuint> shaders;
    auto cleanup = [&] {
        for (GLuint s : shaders)
            glDeleteShader(s);
    };
    for (const auto& st : stages) {
        GLuint s = glCreateShader(st.type);
        shaders.push_back(s);
        const char* src = st.source.c_str();
        glShaderSource(s, 1, &src, nullptr);
        glCompileShader(s);
        GLint ok = 0;
        glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            std::string log = shaderLog(s);
            cleanup();
            throw ProgramError(st.type, log.empty() ? "compile failed (empty log)" : log);
        }
        glAttachShader(program.id(), s);
    }
    glLinkProgram(program.id());
    cleanup();
    GLint ok = 0;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log = programLog(program.id());
        throw ProgramError(0, log.empty() ? "link failed (empty log)" : log);
    }
    detail::noteProgramSources(program.id(), stages);
    return program;
}

GLint uniformLocation(const Program& p, const char* name) {
    return glGetUniformLocation(p.id(), name);
}

namespace {
struct DebugProblems {
    std::mutex mutex;
    std::vector<std::pair<std::string, DebugProblem>> groups; // key: text with digits masked
};
DebugProblems& debugStore() {
    static DebugProblems store;
    return store;
}

void recordProblem(const std::string& text) {
    std::string key = text;
    for (char& c : key)
        if (c >= '0' && c <= '9') c = '#';
    DebugProblems& st = debugStore();
    std::lock_guard<std::mutex> lock(st.mutex);
    const double now = core::secondsSinceStart();
    for (auto& [k, p] : st.groups)
        if (k == key) {
            ++p.count;
            p.lastSeconds = now;
            return;
        }
    if (st.groups.size() < 64) st.groups.push_back({key, DebugProblem{text, 1, now}});
}

std::atomic<DebugObserver> g_observer{nullptr};

void onDebugMessage(GLenum source, GLenum type, GLuint id, GLenum severity, const char* message) {
    if (const DebugObserver o = g_observer.load()) o(source, type, severity, message);
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    core::LogLevel level = core::LogLevel::Debug;
    // shader compiler messages are reported through ProgramError, mapped to the user's file
    if (source == GL_DEBUG_SOURCE_SHADER_COMPILER)
        level = core::LogLevel::Debug;
    else if (type == GL_DEBUG_TYPE_ERROR || severity == GL_DEBUG_SEVERITY_HIGH)
        level = core::LogLevel::Error;
    else if (severity == GL_DEBUG_SEVERITY_MEDIUM)
        level = core::LogLevel::Warn;
    core::log(level, "GL debug [" + std::to_string(id) + "]: " + message);
    if (level == core::LogLevel::Error || level == core::LogLevel::Warn) recordProblem(message);
}

void GLAPIENTRY debugCallback(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei,
                              const GLchar* message, const void*) {
    onDebugMessage(source, type, id, severity, message);
}
} // namespace

void detail::reportDebugMessage(GLenum source, GLenum type, GLenum severity,
                                const std::string& message) {
    onDebugMessage(source, type, 0, severity, message.c_str());
}

std::vector<DebugProblem> debugProblems() {
    DebugProblems& st = debugStore();
    std::lock_guard<std::mutex> lock(st.mutex);
    std::vector<DebugProblem> out;
    for (const auto& [k, p] : st.groups)
        out.push_back(p);
    return out;
}

void clearDebugProblems() {
    DebugProblems& st = debugStore();
    std::lock_guard<std::mutex> lock(st.mutex);
    st.groups.clear();
}

void expireDebugProblems(double seconds) {
    const double now = core::secondsSinceStart();
    DebugProblems& st = debugStore();
    std::lock_guard<std::mutex> lock(st.mutex);
    std::erase_if(st.groups, [&](const auto& g) { return now - g.second.lastSeconds > seconds; });
}

void setDebugObserver(DebugObserver observer) {
    g_observer = observer;
}

void installDebugOutput() {
    if (!epoxy_has_gl_extension("GL_KHR_debug") && epoxy_gl_version() < 43) return;
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, nullptr);
}

} // namespace gl
