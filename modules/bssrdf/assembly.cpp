// GLSL assembly of a model's sections into a template (see assembly.h).
#include "bssrdf/assembly.h"

#include "bssrdf/loop_budget.h"
#include "core/core.h"

#include <algorithm>

namespace bssrdf {

namespace {

void emitDefines(shader::Emitter& out, const Model& m) {
    if (m.attrs.radial) out.text("#define BSSRDF_RADIAL 1\n");
    if (m.attrs.noWi) out.text("#define BSSRDF_NO_WI 1\n");
    if (m.attrs.noWo) out.text("#define BSSRDF_NO_WO 1\n");
    if (!m.diffuseReflectance) out.text("#define BSSRDF_NO_DIFFUSE_REFLECTANCE 1\n");
    if (m.sample) out.text("#define BSSRDF_HAS_SAMPLE 1\n");
    if (m.lobesLine > 0) out.text("#define BSSRDF_HAS_LOBES 1\n");
    out.line(2, 0);
}

void emitModel(shader::Emitter& out, const Model& m, int lineNo, int source) {
    if (std::count(m.source.begin(), m.source.end(), '\n') >= shader::kLineStride - 1)
        throw core::Error(m.path, 0, "too long for the #line source map");
    const int ms = out.source(m.path);
    // the loop budget (loop_budget.h): the guard before the model's code, its loops rewritten
    const bool loops = !guardedLoopLines(m).empty();
    if (loops) {
        out.line(lineNo, source);
        out.text(loopGuardPrelude());
    }
    unsigned site = 0;
    std::vector<int> lines;
    for (const Param& p : m.params) {
        out.line(p.line, ms);
        out.text(std::string("uniform ") + glslType(p.type) + " " + p.name + ";\n");
    }
    auto emitSection = [&](const std::optional<Section>& s) {
        if (!s) return;
        out.line(s->firstLine, ms);
        out.text(loops ? guardLoops(s->code, s->firstLine, site, lines) : s->code);
    };
    if (m.initializer) {
        emitSection(m.initializer);
    } else {
        out.line(lineNo, source);
        out.text("void init() {}\n");
    }
    emitSection(m.diffuseReflectance);
    emitSection(m.shader);
    if (m.sample) { // only templates that evaluate the sampler compile it
        out.text("#if defined(BSSRDF_WANT_SAMPLE)\n");
        emitSection(m.sample);
        out.text("#endif\n");
    }
    if (loops) {
        out.line(lineNo, source);
        out.text(loopGuardEpilogue(m));
    }
    out.line(lineNo + 1, source);
}

} // namespace

shader::Extension modelExtension(const Model* model) {
    shader::Extension ext;
    if (model) ext.afterVersion = [model](shader::Emitter& out) { emitDefines(out, *model); };
    ext.pragma = "bssrdf_model";
    ext.onPragma = [model](shader::Emitter& out, const std::string& path, int lineNo, int source) {
        if (!model)
            throw core::Error(path, lineNo,
                              "'#pragma bssrdf_model' in a shader assembled without a model");
        emitModel(out, *model, lineNo, source);
    };
    return ext;
}

const char* glslType(ParamType t) {
    switch (t) {
    case ParamType::Float:
        return "float";
    case ParamType::Bool:
        return "bool";
    case ParamType::Color:
        return "vec3";
    }
    return "float";
}

std::string uniformDeclarations(const Model& m) {
    std::string out;
    for (const Param& p : m.params)
        out += std::string("uniform ") + glslType(p.type) + " " + p.name + ";\n";
    return out;
}

shader::AssembledShader assemble(std::string_view templateText,
                                 const std::string& templateDisplayPath, const Model* model,
                                 const shader::IncludeResolver& resolveInclude) {
    return shader::assemble(templateText, templateDisplayPath, resolveInclude,
                            modelExtension(model));
}

} // namespace bssrdf
