// A model's analytic sampler functions (`::begin sample`) and Gaussian lobes (QdLobeCount,
// QdLobe) evaluated through the query modes 2 and 3 of shaders/pencil_profile.comp (program.h).
#include "bssrdf/detail/run_batch.h"
#include "bssrdf/program.h"

#include "core/core.h"
#include "core/text.h"

#include <algorithm>
#include <cmath>

namespace bssrdf {

namespace {
constexpr GLuint kSamplerMode = 2, kLobeMode = 3;
// Batches keep one dispatch short on a software rasteriser.
constexpr size_t kBatch = size_t(1) << 16;

// (x, y) per entry through query mode `mode`: the .xyzw of each result.
std::vector<float> runQueries(const Model& m, GLuint program, GLuint mode,
                              const std::vector<float>& in) {
    const size_t count = in.size() / 4;
    std::vector<float> out(in.size());
    for (size_t first = 0; first < count; first += kBatch) {
        const size_t n = std::min(kBatch, count - first);
        std::vector<float> part(in.begin() + std::ptrdiff_t(4 * first),
                                in.begin() + std::ptrdiff_t(4 * (first + n)));
        const std::vector<float> r = detail::runBatch(m, program, part, n, 1, mode);
        std::copy(r.begin(), r.end(), out.begin() + std::ptrdiff_t(4 * first));
    }
    return out;
}
} // namespace

std::vector<double> evaluateSampler(GLuint pencilProgram, const Model& m, const ParamValues& values,
                                    const Builtins& b, const std::vector<SamplerQuery>& queries) {
    if (!m.sample) throw core::Error(m.path, 0, "the model has no 'sample' section");
    if (queries.empty()) return {};
    setUniforms(pencilProgram, m, values, b);
    std::vector<float> in(4 * queries.size(), 0.0f);
    for (size_t i = 0; i < queries.size(); ++i) {
        in[4 * i] = float(queries[i].x);
        in[4 * i + 1] = float(queries[i].channel);
        in[4 * i + 2] = float(int(queries[i].function));
    }
    const std::vector<float> out = runQueries(m, pencilProgram, kSamplerMode, in);
    std::vector<double> v(queries.size());
    for (size_t i = 0; i < v.size(); ++i)
        v[i] = out[4 * i];
    return v;
}

std::array<std::vector<glm::dvec2>, 3> evaluateLobes(GLuint pencilProgram, const Model& m,
                                                     const ParamValues& values, const Builtins& b) {
    if (m.lobesLine <= 0)
        throw core::Error(m.path, 0, "the model does not define QdLobeCount() and QdLobe()");
    setUniforms(pencilProgram, m, values, b);
    const std::vector<float> first = runQueries(m, pencilProgram, kLobeMode, {0, 0, 0, 0});
    const float count = first[2];
    if (!(count >= 1 && count <= float(kMaxLobes)))
        throw core::Error(m.path, m.lobesLine,
                          "QdLobeCount() must return 1 … " + std::to_string(kMaxLobes) +
                              " (it returns " + core::formatNumber(count, 9) + ")");
    const size_t n = size_t(count);
    std::vector<float> in(4 * 3 * n, 0.0f);
    for (size_t c = 0; c < 3; ++c)
        for (size_t k = 0; k < n; ++k) {
            in[4 * (c * n + k)] = float(k);
            in[4 * (c * n + k) + 1] = float(c);
        }
    const std::vector<float> out = runQueries(m, pencilProgram, kLobeMode, in);
    std::array<std::vector<glm::dvec2>, 3> lobes;
    for (size_t c = 0; c < 3; ++c)
        for (size_t k = 0; k < n; ++k) {
            const size_t i = 4 * (c * n + k);
            lobes[c].push_back({out[i], out[i + 1]});
        }
    return lobes;
}

} // namespace bssrdf
