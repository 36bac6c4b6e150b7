// A model's parameter values as JSON: {"NAME": [R, G, B], ...}, used by the stages' cache keys
// and by capture manifests ("params").
#pragma once

#include "bssrdf/program_library.h"

#include <nlohmann/json.hpp>

#include <string>

namespace app {

nlohmann::json toJson(const bssrdf::ParamValues& v);
// Throws core::Error(where, 0, ...) for anything but an object of three finite numbers each.
bssrdf::ParamValues valuesFromJson(const nlohmann::json& j, const std::string& where);

} // namespace app
