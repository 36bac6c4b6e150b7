// irradiance/programs: an RAII sampler object. (The module's shaders are built by the project's
// one shader builder, shader/program.h; see Stage.)
#pragma once

#include "gl/gl.h"

namespace irradiance::detail {

void deleteSampler(GLuint id);
using Sampler = gl::Handle<deleteSampler>;

} // namespace irradiance::detail
