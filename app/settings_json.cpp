// The workbench settings as JSON (settings_json.h).
#include "settings_json.h"

#include "cli_options.h"
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

std::string defaultsTable() {
    std::string out = "| setting | default | meaning |\n|---|---|---|\n";
    auto rows = [&](auto s, const std::string& prefix) {
        core::forEachField(
            s,
            [&](const std::string& path, const auto& m, const char* doc) {
                out += "| `" + path + "` | " + defaultText(m) + " | " + doc + " |\n";
            },
            prefix);
    };
    rows(MaterialSettings{}, "material.");
    rows(PlotSettings{}, "plot.");
    rows(ReferenceSettings{}, "reference.");
    rows(SliceSettings{}, "slice.");
    rows(LitSphereSettings{}, "lit_spheres.");
    rows(SceneSettings{}, "scene.");
    rows(MonteCarloSettings{}, "monte_carlo.");
    rows(TextureSpaceSettings{}, "texture_space.");
    return out;
}

json toJson(const bssrdf::ParamValues& v) {
    json j = json::object();
    for (const auto& [k, val] : v)
        j[k] = json::array({val[0], val[1], val[2]});
    return j;
}

bssrdf::ParamValues valuesFromJson(const json& j, const std::string& where) {
    bssrdf::ParamValues v;
    if (!j.is_object()) throw core::Error(where, 0, "parameter values must be an object");
    for (auto it = j.begin(); it != j.end(); ++it) {
        if (!it->is_array() || it->size() != 3 || !(*it)[0].is_number() || !(*it)[1].is_number() ||
            !(*it)[2].is_number())
            throw core::Error(where, 0, "value of '" + it.key() + "' must be 3 numbers");
        v[it.key()] = {(*it)[0].get<float>(), (*it)[1].get<float>(), (*it)[2].get<float>()};
        for (int c = 0; c < 3; ++c)
            if (!std::isfinite(v[it.key()][c]))
                throw core::Error(where, 0,
                                  "value of '" + it.key() + "' out of range: " + it->dump());
    }
    return v;
}

} // namespace app
