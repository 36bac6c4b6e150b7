// gl hazards: the state bound at a dispatch or draw, checked against the rules a GPU enforces and
// llvmpipe does not: a shadow sampler meets a depth texture with comparison on, a plain sampler
// one with it off (OpenGL 4.5 §8.23.1 and §11.1.3.5: otherwise the results are undefined; NVIDIA
// reports it), and no storage block is bound over more bytes than GL_MAX_SHADER_STORAGE_BLOCK_SIZE
// (llvmpipe: 2^27, and it addresses more anyway; NVIDIA's is 2^31 - 1).
#include "detail/hazard_state.h"

namespace gl::barriers {
namespace {

// The comparison mode comes from the sampler object bound to the unit, else from the texture.
void checkComparison(State& st, const std::string& by, bool shadow, GLuint texture,
                     GLuint samplerObject, GLint unit) {
    if (texture == 0) {
        if (!shadow) return;
        reportOnce(st, "sampler state: " + by + " has a shadow sampler on unit " +
                           std::to_string(unit) + ", which has no texture bound");
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
    reportOnce(st, message);
}

} // namespace

GLuint indexedBinding(GLenum target, GLuint index) {
    GLint id = 0;
    glGetIntegeri_v(target, index, &id);
    return static_cast<GLuint>(id);
}

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

// A binding is a range, or the whole buffer from its start: a larger binding addresses storage
// the driver does not promise to reach (gl::requireStorageBlock is the program's own check).
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
        reportOnce(st, message);
    }
}

} // namespace gl::barriers
