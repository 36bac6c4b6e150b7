// gl hazards: storage made without data is undefined (OpenGL 4.5 §6.2, §8.19): Mesa hands out
// zeros, other drivers whatever the memory held. With the barrier checks on, new storage is filled
// with a pattern instead (a quiet NaN in each 32-bit float, 0xAB in each byte of a normalized
// texel, 0xDEADBEEF in each integer), so code that reads it before writing it fails here as it
// would elsewhere. Depth textures are left as they are (every use clears them first).
#include "detail/hazard_state.h"

namespace gl::barriers {
namespace {
constexpr GLuint kPoisonWord = 0x7FC0DEADu; // a quiet NaN as a float
} // namespace

void poisonBuffer(GLuint buffer, GLsizeiptr size, decltype(epoxy_glClearNamedBufferData) clear) {
    if (!clear || size <= 0) return;
    if (size % 4 == 0) {
        clear(buffer, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &kPoisonWord);
    } else {
        const GLubyte b = 0xAB;
        clear(buffer, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &b);
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

} // namespace gl::barriers
