// A model's parameter values as JSON: {"NAME": [R, G, B], ...} (capture manifests, cache keys).
#include "pipeline/param_json.h"

#include "core/core.h"

#include <cmath>

namespace app {
using nlohmann::json;

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
