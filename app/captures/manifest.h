// What a capture's manifest holds of the workbench besides its outputs (format v1:
// captures/README.md): the models by their path in the capture, their parameters ("params"),
// and the GL driver that recorded it. The settings ("settings"): settings_json.h.
#pragma once

#include "pipeline/workbench.h"

#include <nlohmann/json.hpp>

#include <string>

namespace app {

// A model opened from outside the project is recorded as "external/FILE" with its text in the
// manifest; replay loads it from that text.
inline constexpr const char* kExternalPrefix = "external/";
// A model's path in a capture: its path under the root, or "external/FILE".
std::string capturePathOf(const bssrdf::ModelEntry& e);

// The manifest's "params": the shared material settings and, per model, its visibility, own
// settings and parameter values.
nlohmann::json paramsJson(Workbench& wb);
// Applies "params" (every JSON type checked: core::Error naming `where` and the JSON path).
void applyParams(Workbench& wb, const nlohmann::json& params, const std::string& where);

// The current GL context's renderer and version, as the manifest records them.
std::string glRendererString();
std::string glVersionString();

} // namespace app
