// gl limits: what the workbench needs of a driver beyond "OpenGL 4.5 core", checked when a
// context is created (gl.h, requiredLimits / limitsProblem / requireLimits). Every figure here
// is within the OpenGL 4.5 core minima (spec table 23.x), so a conforming driver passes; the
// check turns a driver that claims 4.5 but falls short into one message at start naming what
// is missing and what needs it, instead of a failed link or a wrong result later.
#include "gl.h"

#include "core/core.h"

#include <string>

namespace gl {

const std::vector<RequiredLimit>& requiredLimits() {
    static const std::vector<RequiredLimit> limits = {
        {"GL_MAX_COMPUTE_SHARED_MEMORY_SIZE", GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, -1, 8192,
         "the slab tracer's workgroup-shared tallies (512 slots of 16 bytes)"},
        {"GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS", GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, -1, 64,
         "workgroups of 64 invocations (every compute shader)"},
        {"GL_MAX_COMPUTE_WORK_GROUP_COUNT[x]", GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, 65535,
         "dispatches of up to 65535 groups (tracers, traversal, point cloud)"},
        {"GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, -1, 8,
         "up to 8 storage buffers per compute program (octree_render.comp, bssrdf_walk.comp)"},
        {"GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS", GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, -1, 8,
         "storage buffer bindings 0..7"},
        {"GL_MAX_COMPUTE_ATOMIC_COUNTERS", GL_MAX_COMPUTE_ATOMIC_COUNTERS, -1, 8,
         "the loop budget's counters in every model program"},
        {"GL_MAX_COMPUTE_ATOMIC_COUNTER_BUFFERS", GL_MAX_COMPUTE_ATOMIC_COUNTER_BUFFERS, -1, 1,
         "the loop budget's counter buffer"},
        {"GL_MAX_TEXTURE_SIZE", GL_MAX_TEXTURE_SIZE, -1, 4096,
         "render targets and exported images up to 4096 pixels a side"},
        {"GL_MAX_SHADER_STORAGE_BLOCK_SIZE", GL_MAX_SHADER_STORAGE_BLOCK_SIZE, -1, 1 << 27,
         "storage buffers up to 128 MiB (GL tracer tallies, point clouds)"},
    };
    return limits;
}

std::string limitsProblem(const std::function<int64_t(const RequiredLimit&)>& query) {
    std::string out;
    for (const RequiredLimit& l : requiredLimits()) {
        const int64_t have = query(l);
        if (have >= l.needed) continue;
        if (!out.empty()) out += "; ";
        out += std::string(l.name) + " is " + std::to_string(have) + ", needs " +
               std::to_string(l.needed) + " (" + l.use + ")";
    }
    return out.empty() ? out : "the OpenGL driver falls short of what the workbench needs: " + out;
}

void requireLimits() {
    const std::string problem = limitsProblem([](const RequiredLimit& l) {
        GLint64 v = 0;
        if (l.index >= 0)
            glGetInteger64i_v(l.pname, static_cast<GLuint>(l.index), &v);
        else
            glGetInteger64v(l.pname, &v);
        return static_cast<int64_t>(v);
    });
    if (!problem.empty()) {
        const GLubyte* r = glGetString(GL_RENDERER);
        throw core::Error(std::string(r ? reinterpret_cast<const char*>(r) : "unknown GPU") + ": " +
                          problem);
    }
}

int64_t maxStorageBlockBytes() {
    GLint64 v = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &v);
    return static_cast<int64_t>(v);
}

void requireStorageBlock(uint64_t bytes, const std::string& what, const std::string& unit,
                         uint64_t bytesPerUnit) {
    const int64_t limit = maxStorageBlockBytes();
    if (limit <= 0 || bytes <= static_cast<uint64_t>(limit)) return;
    throw core::Error(what, 0,
                      "needs " + std::to_string(bytes) +
                          " bytes in one storage buffer, more than "
                          "this driver's GL_MAX_SHADER_STORAGE_BLOCK_SIZE (" +
                          std::to_string(limit) + " bytes: at most " +
                          std::to_string(static_cast<uint64_t>(limit) / bytesPerUnit) + " " + unit +
                          ")");
}

} // namespace gl
