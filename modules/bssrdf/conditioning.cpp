// The spread of a model's values under the errors GLSL allows its transcendental functions
// (conditioning.h).
#include "bssrdf/conditioning.h"

#include "bssrdf/detail/run_batch.h"

#include <algorithm>
#include <cmath>

namespace bssrdf {

namespace {

// The batch `in` (`inVec4` vec4 per entry; `queries` the template's mode) through
// pencil_perturbed.comp unperturbed and under seeds 1 … patterns: one RGB vector per seed.
std::vector<std::vector<glm::dvec3>> perturbed(const Model& m, const shader::Sources& src,
                                               const ParamValues& values, const Builtins& b,
                                               const std::vector<float>& in, size_t count,
                                               size_t inVec4, GLuint queries, int patterns) {
    const gl::Program program = buildModelProgram(m, "pencil_perturbed.comp", src);
    setUniforms(program.id(), m, values, b);
    const GLint seed = glGetUniformLocation(program.id(), "PerturbSeed");
    std::vector<std::vector<glm::dvec3>> out;
    // without the uniform (a model that calls none of the functions) every seed gives [0]
    for (int k = 0; k <= (seed >= 0 ? patterns : 0); ++k) {
        if (seed >= 0) glProgramUniform1ui(program.id(), seed, GLuint(k));
        // batches keep one dispatch short on a software rasteriser
        constexpr size_t kBatch = size_t(1) << 16;
        std::vector<glm::dvec3> v(count);
        for (size_t first = 0; first < count; first += kBatch) {
            const size_t n = std::min(kBatch, count - first);
            const std::vector<float> part(in.begin() + std::ptrdiff_t(4 * inVec4 * first),
                                          in.begin() + std::ptrdiff_t(4 * inVec4 * (first + n)));
            const std::vector<float> r =
                detail::runBatch(m, program.id(), part, n, inVec4, queries);
            for (size_t i = 0; i < n; ++i)
                v[first + i] = {r[4 * i], r[4 * i + 1], r[4 * i + 2]};
        }
        out.push_back(std::move(v));
    }
    glUseProgram(0);
    while (int(out.size()) <= patterns)
        out.push_back(out.front());
    return out;
}

} // namespace

std::vector<glm::dvec3> profileSpread(const Model& m, const shader::Sources& src,
                                      const ParamValues& values, const Builtins& b,
                                      const std::vector<double>& radii, int patterns) {
    std::vector<float> in(radii.size() * 4, 0.0f);
    for (size_t i = 0; i < radii.size(); ++i)
        in[4 * i] = static_cast<float>(radii[i]);
    const auto v = perturbed(m, src, values, b, in, radii.size(), 1, 0, patterns);
    std::vector<glm::dvec3> spread(radii.size(), glm::dvec3(0.0));
    for (size_t k = 1; k < v.size(); ++k)
        for (size_t i = 0; i < radii.size(); ++i)
            for (int c = 0; c < 3; ++c) {
                const double d = std::fabs(v[k][i][c] - v[0][i][c]);
                // NaN or inf where the model is not finite: no spread to speak of
                if (std::isfinite(d)) spread[i][c] = std::max(spread[i][c], d);
            }
    return spread;
}

std::vector<std::vector<glm::dvec3>> perturbedQueries(const Model& m, const shader::Sources& src,
                                                      const ParamValues& values, const Builtins& b,
                                                      const std::vector<Query>& queries,
                                                      int patterns) {
    return perturbed(m, src, values, b, detail::queryInputs(queries), queries.size(), 3, 1,
                     patterns);
}

} // namespace bssrdf
