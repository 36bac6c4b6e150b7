// Symmetric JSON forms of the workbench settings (captures and the CLI use them).
#pragma once

#include "workbench.h"

#include <nlohmann/json.hpp>

namespace app {

nlohmann::json toJson(const MaterialSettings& s);
MaterialSettings materialFromJson(const nlohmann::json& j, const std::string& where);
nlohmann::json toJson(const PlotSettings& s);
PlotSettings plotFromJson(const nlohmann::json& j, const std::string& where);
nlohmann::json toJson(const bssrdf::ParamValues& v);
bssrdf::ParamValues valuesFromJson(const nlohmann::json& j, const std::string& where);

} // namespace app
