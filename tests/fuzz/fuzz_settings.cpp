// Fuzzes the workbench settings JSON (the "settings" object of capture manifests): the input
// parsed as JSON, then each section read with core::fromJson into its settings struct (plot,
// reference, slice, monte_carlo, texture_space, lit_spheres, scene), as applySettingsJson does
// without a
// workbench, and the struct written back with core::toJson.
#include "fuzz_common.h"

#include "core/fields.h"
#include "pipeline/workbench.h"

#include <nlohmann/json.hpp>

namespace {
template <class T> void section(const nlohmann::json& j, const std::string& key) {
    T s = core::fromJson(j, "settings.json", "settings." + key, T{});
    (void)core::toJson(s).dump();
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(fuzz::asText(data, size));
    } catch (const nlohmann::json::exception&) {
        return 0; // JSON syntax is the JSON library's; the readers above catch it
    }
    if (!j.is_object()) return 0;
    fuzz::expectCleanError([&] {
        for (auto it = j.begin(); it != j.end(); ++it) {
            if (it.key() == "plot") section<app::PlotSettings>(*it, it.key());
            if (it.key() == "reference") section<app::ReferenceSettings>(*it, it.key());
            if (it.key() == "slice") section<app::SliceSettings>(*it, it.key());
            if (it.key() == "monte_carlo") section<app::MonteCarloSettings>(*it, it.key());
            if (it.key() == "texture_space") {
                const auto ts = core::fromJson(*it, "settings.json", "settings.texture_space",
                                               app::TextureSpaceSettings{});
                texspace::validateSettings(ts.sampling); // as applySettingsJson does
                (void)core::toJson(ts).dump();
            }
            if (it.key() == "lit_spheres") section<app::LitSphereSettings>(*it, it.key());
            if (it.key() == "scene") {
                nlohmann::json scene = *it;
                if (scene.is_object()) scene.erase("trace_pixel");
                section<app::SceneSettings>(scene, it.key());
            }
        }
    });
    return 0;
}
