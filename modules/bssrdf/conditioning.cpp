// The spread of a model's pencil profile under the errors GLSL allows its transcendental functions
// (conditioning.h).
#include "bssrdf/conditioning.h"

#include "bssrdf/detail/run_batch.h"

#include <algorithm>
#include <cmath>

namespace bssrdf {

std::vector<glm::dvec3> profileSpread(const Model& m, const shader::Sources& src,
                                      const ParamValues& values, const Builtins& b,
                                      const std::vector<double>& radii, int patterns) {
    const gl::Program program = buildModelProgram(m, "pencil_perturbed.comp", src);
    setUniforms(program.id(), m, values, b);
    std::vector<float> in(radii.size() * 4, 0.0f);
    for (size_t i = 0; i < radii.size(); ++i)
        in[4 * i] = static_cast<float>(radii[i]);
    const GLint seed = glGetUniformLocation(program.id(), "PerturbSeed");
    const auto run = [&](GLuint s) {
        if (seed >= 0) glProgramUniform1ui(program.id(), seed, s);
        return detail::runBatch(m, program.id(), in, radii.size());
    };
    const std::vector<float> exact = run(0);
    std::vector<glm::dvec3> spread(radii.size(), glm::dvec3(0.0));
    // without the uniform (a model that calls none of the functions) every seed gives `exact`
    for (int k = 1; k <= patterns && seed >= 0; ++k) {
        const std::vector<float> moved = run(GLuint(k));
        for (size_t i = 0; i < radii.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const double d = std::fabs(double(moved[4 * i + c]) - double(exact[4 * i + c]));
                // NaN or inf where the model is not finite: no spread to speak of
                if (std::isfinite(d)) spread[i][c] = std::max(spread[i][c], d);
            }
    }
    glUseProgram(0);
    return spread;
}

} // namespace bssrdf
