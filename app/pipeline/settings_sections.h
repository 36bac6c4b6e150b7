// The workbench's settings as named sections, one per settings struct: "material", "plot",
// "reference", "slice", "lit_spheres", "scene", "monte_carlo", "fit", "texture_space". A capture
// manifest's "settings" (captures/settings_json.cpp) and the `defaults` table
// (cli/defaults_command.cpp) loop over them, so a stage's settings are registered once, here
// (settings_sections.cpp), and JSON, defaults and their documentation follow from the struct's
// description (core/fields.h).
#pragma once

#include "core/fields.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace app {

class Workbench;

struct SettingsSection {
    std::string key;        // the JSON key, and the defaults table's prefix
    bool inCaptures = true; // false: the manifest keeps it elsewhere (material: in "params")
    // The current values, and replacing them from JSON (core::Error naming file and path; a
    // missing key keeps the default, an unknown key or a wrong type is refused).
    std::function<nlohmann::json()> toJson;
    std::function<void(const nlohmann::json&, const std::string& file, const std::string& path)>
        fromJson;
    // Every member of a default-constructed struct: its path, its value as text, its doc.
    using DefaultRow =
        std::function<void(const std::string& path, const std::string& value, const char* doc)>;
    std::function<void(const DefaultRow&)> forEachDefault;
};

// Every section in the defaults table's order, reading and writing wb's settings (wb null:
// only key, inCaptures and forEachDefault are usable).
std::vector<SettingsSection> settingsSections(Workbench* wb);

} // namespace app
