// gl hazards: a program's interface as the barrier checks read it (detail/hazard_state.h): which
// storage blocks, uniform blocks, samplers and images it uses, from glGetProgramResource*, and
// which storage blocks its sources declare readonly or writeonly, from the GLSL text (the
// interface queries do not say: OpenGL 4.5 §7.3.1 has no memory-qualifier property).
#include "detail/hazard_state.h"

#include <cctype>

namespace gl::barriers {
namespace {

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

} // namespace

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

BlockQualifiers blockQualifiers(const std::vector<ShaderStage>& stages) {
    // `layout(...) readonly buffer Name {`: memory qualifiers stand between the declaration's
    // start (after `)`, `;`, `{` or `}`) and `buffer`
    const auto word = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    };
    BlockQualifiers q;
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
                q.readonly.insert(t.substr(name, end - name));
            if (qualifiers.find("writeonly") != std::string::npos)
                q.writeonly.insert(t.substr(name, end - name));
        }
    }
    return q;
}

} // namespace gl::barriers
