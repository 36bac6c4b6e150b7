// The workbench settings as JSON (settings_json.h).
#include "captures/settings_json.h"

#include "core/core.h"
#include "core/fields.h"
#include "pipeline/settings_sections.h"

#include <algorithm>

namespace app {
using nlohmann::json;

json settingsJson(Workbench& wb, int traceX, int traceY) {
    json out = json::object();
    for (const SettingsSection& s : settingsSections(&wb))
        if (s.inCaptures) out[s.key] = s.toJson();
    out["r_max_mm"] = wb.rMaxMm();
    out["scene"]["trace_pixel"] = {traceX, traceY};
    return out;
}

void applySettingsJson(Workbench& wb, const json& settings, const std::string& file, int& traceX,
                       int& traceY) {
    traceX = traceY = -1;
    if (!settings.is_object()) throw core::Error(file, 0, "settings: expected an object");
    const std::vector<SettingsSection> sections = settingsSections(&wb);
    for (auto it = settings.begin(); it != settings.end(); ++it) {
        const std::string& key = it.key();
        const std::string path = "settings." + key;
        if (key == "r_max_mm" || key == "seed")
            continue; // r_max_mm is derived; "seed" (format 1) repeated the reference seed
        auto s = std::find_if(sections.begin(), sections.end(), [&](const SettingsSection& s) {
            return s.inCaptures && s.key == key;
        });
        if (s == sections.end()) throw core::Error(file, 0, path + ": unknown key");
        json value = *it;
        if (key == "scene" && value.is_object() && value.contains("trace_pixel")) {
            // the capture's traced pixel, kept beside the scene's settings
            const json& t = value["trace_pixel"];
            if (!t.is_array() || t.size() != 2 || !t[0].is_number_integer() ||
                !t[1].is_number_integer())
                throw core::Error(file, 0, path + ".trace_pixel: expected two integers");
            traceX = t[0].get<int>();
            traceY = t[1].get<int>();
            value.erase("trace_pixel");
        }
        if (key == "reference" && value.is_object() && value.contains("gpu") &&
            !value.contains("device")) {
            // format 1 before `device`: "gpu": true/false chose the GL or the CPU tracer
            const json& g = value["gpu"];
            if (!g.is_boolean()) throw core::Error(file, 0, path + ".gpu: expected true or false");
            value["device"] = g.get<bool>() ? "gpu" : "cpu";
            value.erase("gpu");
        }
        if ((key == "reference" || key == "slice") && value.is_object() &&
            !value.contains("device") && !value.contains("gpu"))
            value["device"] = "cpu"; // recorded before the GL tracers: the CPU walk traced it
        if ((key == "reference" || key == "slice") && value.is_object() &&
            !value.contains("exit_samples"))
            value["exit_samples"] = 0; // recorded before the setting: the actual exits
        s->fromJson(value, file, path);
    }
}

} // namespace app
