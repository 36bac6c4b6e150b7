// gl/detail/hazard_state.h: what the barrier checks' files share (hazards.cpp is the tracker and
// its hooks; hazards_program.cpp reads a program's interface; hazards_bindings.cpp checks the
// state bound at a dispatch or draw; hazards_poison.cpp fills new storage). Every function here
// runs with the tracker's lock held (hazards.cpp's hooks take it), on the thread whose context is
// current.
#pragma once

#include "gl/gl.h"

#include <map>
#include <set>
#include <string>
#include <vector>

namespace gl::barriers {

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

// One context's: the bits owed per buffer and texture, each program's interface, the storage
// blocks its sources declare readonly / writeonly, the messages already reported.
struct State {
    std::map<GLuint, Pending> buffers, textures;
    std::map<GLuint, ProgramIo> programs;
    std::map<GLuint, std::set<std::string>> readonlyBlocks; // by program, from its sources
    std::map<GLuint, std::set<std::string>> writeonlyBlocks;
    std::set<std::string> reported;
};

// hazards.cpp
State& state(); // the current context's
// Reports a read of `id` (a `what`) by `call` as UNDEFINED_BEHAVIOR when it still owes `bit`.
void need(State& st, std::map<GLuint, Pending>& objects, GLuint id, GLbitfield bit,
          const std::string& call, const char* what);
// Sends `message` as a GL debug message of type UNDEFINED_BEHAVIOR, once per context and `key`
// (default: the message).
void reportOnce(State& st, const std::string& message, const std::string& key = "");

// hazards_program.cpp
ProgramIo& programIo(State& st, GLuint program);
struct BlockQualifiers {
    std::set<std::string> readonly, writeonly; // storage block names
};
// The storage blocks the sources declare `readonly` or `writeonly`.
BlockQualifiers blockQualifiers(const std::vector<ShaderStage>& stages);

// hazards_bindings.cpp
GLuint indexedBinding(GLenum target, GLuint index);
// The texture and sampler on each of the program's sampler units: their comparison mode, and
// with `fetch` (a dispatch or draw, which reads them) the texture-fetch barrier owed.
void samplerState(State& st, GLuint program, const ProgramIo& io, const std::string& by,
                  bool fetch);
// Every storage block of the program bound within GL_MAX_SHADER_STORAGE_BLOCK_SIZE bytes.
void storageBlockSizes(State& st, const ProgramIo& io, const std::string& by);

// hazards_poison.cpp: storage made without data filled with a pattern. `clear` is the driver's
// glClearNamedBufferData (the hooked one would take the tracker's lock again).
void poisonBuffer(GLuint buffer, GLsizeiptr size, decltype(epoxy_glClearNamedBufferData) clear);
void poisonTexture(GLuint texture, GLenum internalFormat);

} // namespace gl::barriers
