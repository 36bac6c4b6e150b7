// The workbench settings as JSON (settings_json.h).
#include "captures/settings_json.h"

#include "core/core.h"
#include "core/fields.h"

#include <cmath>

namespace app {
using nlohmann::json;

json settingsJson(Workbench& wb, int traceX, int traceY) {
    json scene = core::toJson(wb.scene().settings());
    scene["trace_pixel"] = {traceX, traceY};
    return {{"plot", core::toJson(wb.plotSettings())},
            {"r_max_mm", wb.rMaxMm()},
            {"reference", core::toJson(wb.referenceSettings())},
            {"lit_spheres", core::toJson(wb.litSphereSettings())},
            {"slice", core::toJson(wb.sliceSettings())},
            {"monte_carlo", core::toJson(wb.monteCarloSettings())},
            {"texture_space", core::toJson(wb.textureSpaceSettings())},
            {"scene", scene}};
}

void applySettingsJson(Workbench& wb, const json& settings, const std::string& file, int& traceX,
                       int& traceY) {
    traceX = traceY = -1;
    if (!settings.is_object()) throw core::Error(file, 0, "settings: expected an object");
    for (auto it = settings.begin(); it != settings.end(); ++it) {
        const std::string& key = it.key();
        const std::string path = "settings." + key;
        if (key == "plot") {
            PlotSettings p = core::fromJson(*it, file, path, PlotSettings{});
            wb.plotSettings() = p;
        } else if (key == "reference") {
            wb.referenceSettings() = core::fromJson(*it, file, path, ReferenceSettings{});
        } else if (key == "slice") {
            wb.sliceSettings() = core::fromJson(*it, file, path, SliceSettings{});
        } else if (key == "monte_carlo") {
            wb.monteCarloSettings() = core::fromJson(*it, file, path, MonteCarloSettings{});
        } else if (key == "texture_space") {
            wb.textureSpaceSettings() = core::fromJson(*it, file, path, TextureSpaceSettings{});
            texspace::validateSettings(wb.textureSpaceSettings().sampling);
        } else if (key == "lit_spheres") {
            wb.litSphereSettings() = core::fromJson(*it, file, path, LitSphereSettings{});
        } else if (key == "scene") {
            json scene = *it;
            if (scene.is_object() && scene.contains("trace_pixel")) {
                const json& t = scene["trace_pixel"];
                if (!t.is_array() || t.size() != 2 || !t[0].is_number_integer() ||
                    !t[1].is_number_integer())
                    throw core::Error(file, 0, path + ".trace_pixel: expected two integers");
                traceX = t[0].get<int>();
                traceY = t[1].get<int>();
                scene.erase("trace_pixel");
            }
            core::fromJson(scene, wb.scene().settings(), file, path);
            wb.scene().settings().useCache = false; // replays regenerate: no cache hides a change
            wb.scene().keepCamera();                // the recorded camera, not one fitted on load
        } else if (key != "r_max_mm" && key != "seed") {
            // r_max_mm is derived; "seed" (format 1) repeated the reference seed
            throw core::Error(file, 0, path + ": unknown key");
        }
    }
}

} // namespace app
