// The workbench's settings sections (settings_sections.h): one line per settings struct.
#include "pipeline/settings_sections.h"

#include "pipeline/workbench.h"
#include "texspace/pipeline.h"

namespace app {
using nlohmann::json;

namespace {

// A section over settings struct S at `s` (null: defaults only). afterRead runs after the
// values were replaced from JSON (validation, or what a replay needs besides the values).
template <class S>
SettingsSection section(std::string key, S* s, std::function<void()> afterRead = {}) {
    SettingsSection out;
    out.key = key;
    if (s) {
        out.toJson = [s] { return core::toJson(*s); };
        out.fromJson = [s, afterRead](const json& j, const std::string& file,
                                      const std::string& path) {
            *s = core::fromJson(j, file, path, S{});
            if (afterRead) afterRead();
        };
    }
    out.forEachDefault = [key](const SettingsSection::DefaultRow& row) {
        S defaults{};
        core::forEachField(
            defaults,
            [&](const std::string& path, const auto& m, const char* doc) {
                row(path, core::defaultText(m), doc);
            },
            key + ".");
    };
    return out;
}

} // namespace

std::vector<SettingsSection> settingsSections(Workbench* wb) {
    SettingsSection material = section<MaterialSettings>("material", wb ? &wb->shared() : nullptr);
    material.inCaptures = false; // the manifest's "params" hold the shared material
    SettingsSection scene = section<SceneSettings>("scene", wb ? &wb->scene().settings() : nullptr);
    if (wb) {
        // read from a capture or a session: the members it does not name keep their values
        // (not the defaults), and the scene keeps the recorded camera instead of fitting one to
        // the mesh
        scene.fromJson = [wb](const json& j, const std::string& file, const std::string& path) {
            core::fromJson(j, wb->scene().settings(), file, path);
            wb->scene().keepCamera();
        };
    }
    return {
        material,
        section<PlotSettings>("plot", wb ? &wb->plotSettings() : nullptr),
        section<ReferenceSettings>("reference", wb ? &wb->referenceSettings() : nullptr),
        section<SliceSettings>("slice", wb ? &wb->sliceSettings() : nullptr),
        section<LitSphereSettings>("lit_spheres", wb ? &wb->litSphereSettings() : nullptr),
        scene,
        section<MonteCarloSettings>("monte_carlo", wb ? &wb->monteCarloSettings() : nullptr),
        section<FitRequestSettings>("fit", wb ? &wb->fitRequest() : nullptr),
        section<TextureSpaceSettings>(
            "texture_space", wb ? &wb->textureSpaceSettings() : nullptr,
            [wb] { texspace::validateSettings(wb->textureSpaceSettings().sampling); }),
    };
}

} // namespace app
