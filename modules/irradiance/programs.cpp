// irradiance/programs: the sampler deleter (see programs.h).
#include "irradiance/programs.h"

namespace irradiance::detail {

void deleteSampler(GLuint id) {
    glDeleteSamplers(1, &id);
}

} // namespace irradiance::detail
