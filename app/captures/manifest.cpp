// The manifest's models, params and GL strings (manifest.h).
#include "captures/manifest.h"

#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"
#include "pipeline/param_json.h"

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string gpuString(GLenum e) {
    const GLubyte* s = glGetString(e);
    return s ? reinterpret_cast<const char*>(s) : "";
}

} // namespace

std::string glRendererString() {
    return gpuString(GL_RENDERER);
}

std::string glVersionString() {
    return gpuString(GL_VERSION);
}

std::string capturePathOf(const bssrdf::ModelEntry& e) {
    if (!fs::path(e.displayPath).is_absolute()) return e.displayPath;
    return std::string(kExternalPrefix) + e.file.filename().string();
}

json paramsJson(Workbench& wb) {
    json models = json::object();
    for (auto& e : wb.library().entries()) {
        auto& v = wb.view(e.displayPath);
        models[capturePathOf(e)] = {{"visible", v.visible},
                                    {"override", v.override},
                                    {"own", core::toJson(v.own)},
                                    {"values", toJson(e.values)}};
    }
    return {{"shared", core::toJson(wb.shared())}, {"models", models}};
}

void applyParams(Workbench& wb, const json& params, const std::string& where) {
    // Every JSON type is checked here, so a hostile manifest gets a message with its JSON
    // path, never the JSON library's own exception text.
    if (!params.is_object() || !params.contains("shared") || !params.contains("models"))
        throw core::Error(where, 0, "params needs 'shared' and 'models'");
    wb.shared() = core::fromJson(params["shared"], where, "params.shared", MaterialSettings{});
    if (!params["models"].is_object())
        throw core::Error(where, 0, "params.models: expected an object");
    for (auto it = params["models"].begin(); it != params["models"].end(); ++it) {
        auto* e = wb.library().find(it.key());
        // an external model was loaded from a copy of its recorded text: find it by its file
        if (!e && it.key().rfind(kExternalPrefix, 0) == 0)
            for (auto& cand : wb.library().entries())
                if (capturePathOf(cand) == it.key()) e = &cand;
        if (!e) continue; // reported as an input problem / missing stage
        const std::string path = "params.models." + it.key();
        const std::string w = where + " (" + path + ")";
        if (!it->is_object() || !it->contains("own") || !it->contains("values"))
            throw core::Error(where, 0, path + ": needs 'own' and 'values'");
        auto flag = [&](const char* key, bool otherwise) {
            if (!it->contains(key)) return otherwise;
            if (!it->at(key).is_boolean())
                throw core::Error(where, 0, path + "." + key + ": expected true or false");
            return it->at(key).get<bool>();
        };
        auto& v = wb.view(e->displayPath);
        v.visible = flag("visible", true);
        v.override = flag("override", false);
        v.own = core::fromJson(it->at("own"), where, path + ".own", MaterialSettings{});
        auto values = valuesFromJson(it->at("values"), w);
        for (auto& [k, val] : values)
            if (e->values.count(k)) e->values[k] = val;
    }
}

} // namespace app
