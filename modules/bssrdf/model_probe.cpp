// The check of a new model (model_probe.h): its key, the warm-up and the sentinel evaluation.
#include "bssrdf/model_probe.h"

#include "bssrdf/assembly.h"
#include "bssrdf/loop_sites.h"
#include "core/core.h"
#include "detail/run_batch.h"

#include <algorithm>

namespace bssrdf {
namespace {
// .w of an output the invocation did not write (the templates write r ≥ 0, 0 or -1).
constexpr float kNotWritten = -2.0f;
} // namespace

std::string probeKey(const Model& m, const shader::Sources& src) {
    shader::Dependencies deps;
    std::string text = src.assemble("pencil_profile.comp", deps, modelExtension(&m)).glsl;
    if (m.diffuseReflectance)
        text += src.assemble("invert_rdr.comp", deps, modelExtension(&m)).glsl;
    return core::hashHex(text);
}

namespace {
// A `#define` in the model's code: a macro may hide a loop from the scan of loop_sites.h (which
// skips preprocessor lines), even one whose keyword is pasted together (`f##or`).
bool definesMacros(const Model& m) {
    bool found = false;
    for (const std::optional<Section>* s :
         {&m.initializer, &m.diffuseReflectance, &m.shader, &m.sample, &m.table})
        if (*s)
            forEachDefine((*s)->code, (*s)->firstLine,
                          [&](const std::string&, int) { found = true; });
    return found;
}
} // namespace

bool inversionMayLoop(const Model& m) {
    if (!m.diffuseReflectance) return false;
    for (const std::optional<Section>* s : {&m.initializer, &m.diffuseReflectance}) {
        if (!*s) continue;
        bool loops = false;
        forEachWord((*s)->code, (*s)->firstLine, [&](const std::string& w, size_t, int, char) {
            loops = loops || w == "for" || w == "while" || w == "do";
        });
        if (loops || loopInMacro((*s)->code, (*s)->firstLine)) return true;
        // `)` then `;` outside braces: a prototype (or a global initialised by a call; either
        // way the check runs)
        const std::string& c = (*s)->code;
        int depth = 0;
        for (size_t i = 0; i < c.size(); ++i) {
            if (c.compare(i, 2, "//") == 0) {
                i = std::min(c.find('\n', i), c.size());
                continue;
            }
            if (c.compare(i, 2, "/*") == 0) {
                i = std::min(c.find("*/", i + 2), c.size()) + 1;
                continue;
            }
            if (c[i] == '{') ++depth;
            if (c[i] == '}') --depth;
            if (c[i] == ')' && depth == 0) {
                const size_t next = c.find_first_not_of(" \t\r\n", i + 1);
                if (next != std::string::npos && c[next] == ';') return true;
            }
        }
    }
    return false;
}

std::string probeFrameKey(const Model& m, const shader::Sources& src) {
    if (!loopSites(m).empty() || definesMacros(m)) return "";
    Model frame = m;
    for (std::optional<Section>* s : {&frame.initializer, &frame.diffuseReflectance, &frame.shader,
                                      &frame.sample, &frame.table})
        if (*s) **s = Section{(*s)->name, "", 0, 0};
    frame.source.clear();
    frame.hash.clear();
    return "frame " + probeKey(frame, src);
}

std::vector<std::string> programsToWarmDuringCheck(const Model& m, bool inversionInUse,
                                                   bool driverCacheOff) {
    std::vector<std::string> out;
    if (driverCacheOff) out.push_back("pencil_profile.comp");
    if (m.diffuseReflectance && inversionInUse && (driverCacheOff || !inversionMayLoop(m)))
        out.push_back("invert_rdr.comp");
    return out;
}

void warmUp(GLuint program) {
    // Count = 0: every invocation of the one work group returns at its first line.
    const std::vector<float> zeros(64 * 4, 0.0f);
    gl::Buffer in = gl::createBuffer(zeros.size() * sizeof(float), zeros.data());
    gl::Buffer out = gl::createBuffer(zeros.size() * sizeof(float), nullptr);
    glUseProgram(program);
    glUniform1ui(glGetUniformLocation(program, "Count"), 0u);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glDispatchCompute(1, 1, 1);
    glFinish();
}

ProbeResult evaluateProbe(GLuint pencilProgram, GLuint inversionProgram, const Model& m,
                          const ParamValues& values, const Builtins& b,
                          const std::vector<double>& radii) {
    ProbeResult res;
    setUniforms(pencilProgram, m, values, b);
    std::vector<float> in(radii.size() * 4, 0.0f);
    for (size_t i = 0; i < radii.size(); ++i)
        in[4 * i] = static_cast<float>(radii[i]);
    const std::vector<float> unwritten(radii.size() * 4, kNotWritten);
    const auto out =
        detail::runBatch(m, pencilProgram, in, radii.size(), 1, 0, kProbeSentinel, &unwritten);
    res.profile.r = radii;
    for (size_t i = 0; i < radii.size(); ++i) {
        res.profile.value.push_back({out[4 * i], out[4 * i + 1], out[4 * i + 2]});
        res.loopsCut += out[4 * i + 3] == -1.0f;
        res.notWritten += out[4 * i + 3] == kNotWritten;
    }
    res.evaluated = radii.size();
    if (inversionProgram == 0) return res;
    // α′ across (0, 1], as the bisection of the inversion visits them
    std::vector<float> alpha;
    for (float a : {0.01f, 0.3f, 0.6f, 0.9f, 0.99f, 0.9999f, 1.0f})
        alpha.insert(alpha.end(), {a, a, a, 0.0f});
    setUniforms(inversionProgram, m, values, b);
    const size_t n = alpha.size() / 4;
    const std::vector<float> unwrittenRdr(n * 4, kNotWritten);
    const auto rdr =
        detail::runBatch(m, inversionProgram, alpha, n, 1, 0, kProbeSentinel, &unwrittenRdr);
    for (size_t i = 0; i < n; ++i) {
        res.loopsCut += rdr[4 * i + 3] == -1.0f;
        res.notWritten += rdr[4 * i + 3] == kNotWritten;
    }
    res.evaluated += n;
    return res;
}

} // namespace bssrdf
