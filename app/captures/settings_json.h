// The workbench settings as JSON (capture manifests: "settings" and "params"), generated from
// each settings struct's description (core/fields.h): symmetric by construction, enums by name,
// a missing key keeps the default (older manifests read as they were recorded), an unknown key
// or a wrong type throws core::Error(file, 0, "settings.scene.render.eps: expected a number").
#pragma once

#include "pipeline/param_json.h"
#include "pipeline/workbench.h"

#include <nlohmann/json.hpp>

namespace app {

// The manifest's "settings": plot, reference, slice, lit_spheres and scene (with the traced pixel
// (traceX, traceY) as scene.trace_pixel), and r_max_mm (informational: it is derived).
nlohmann::json settingsJson(Workbench& wb, int traceX, int traceY);
// Applies a manifest's "settings"; sections that are absent keep the workbench's settings.
// Returns the traced pixel through traceX, traceY (-1 when none).
void applySettingsJson(Workbench& wb, const nlohmann::json& settings, const std::string& file,
                       int& traceX, int& traceY);

} // namespace app
