// irradiance/programs: the sampler deleter (see programs.h).
#include "irradiance/programs.h"

namespace irradiance::detail {

void deleteSampler(GLuint id) {
    if (!gl::contextLost()) glDeleteSamplers(1, &id);
}

} // namespace irradiance::detail
