// gl shader cache: whether the driver's on-disk shader cache is turned off by the environment
// (gl.h, driverShaderCacheOff). Mesa reads MESA_SHADER_CACHE_DISABLE (and the older
// MESA_GLSL_CACHE_DISABLE) as a boolean; NVIDIA's driver reads __GL_SHADER_DISK_CACHE=0. Both
// caches are on by default.
#include "gl.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <string>

namespace gl {

namespace {
// Mesa's reading of a boolean variable: 1, true, y, yes (any case).
bool truthy(const char* name) {
    const char* v = std::getenv(name);
    if (!v) return false;
    std::string s(v);
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s == "1" || s == "true" || s == "y" || s == "yes";
}
} // namespace

bool driverShaderCacheOff() {
    const char* nvidia = std::getenv("__GL_SHADER_DISK_CACHE");
    return truthy("MESA_SHADER_CACHE_DISABLE") || truthy("MESA_GLSL_CACHE_DISABLE") ||
           (nvidia && std::string(nvidia) == "0");
}

} // namespace gl
