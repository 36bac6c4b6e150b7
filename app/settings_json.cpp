// JSON forms of MaterialSettings, PlotSettings and model parameter values.
#include "settings_json.h"

#include "core/core.h"

namespace app {
using nlohmann::json;

namespace {
json vec(const glm::dvec3& v) {
    return json::array({v.x, v.y, v.z});
}
glm::dvec3 vecFrom(const json& j, const char* key, const std::string& where) {
    if (!j.contains(key) || !j[key].is_array() || j[key].size() != 3)
        throw core::Error(where, 0, std::string("'") + key + "' must be an array of 3 numbers");
    return {j[key][0].get<double>(), j[key][1].get<double>(), j[key][2].get<double>()};
}
template <class T> T get(const json& j, const char* key, const std::string& where) {
    if (!j.contains(key)) throw core::Error(where, 0, std::string("missing '") + key + "'");
    try {
        return j[key].get<T>();
    } catch (const json::exception&) {
        throw core::Error(where, 0, std::string("'") + key + "' has the wrong type");
    }
}
} // namespace

json toJson(const MaterialSettings& s) {
    return {{"mode", s.mode == ParamMode::Sigma ? "sigma" : "rdr_ld"},
            {"sigma_a", vec(s.params.sigmaA)},
            {"sigma_s", vec(s.params.sigmaS)},
            {"g", s.params.g},
            {"eta", s.params.eta},
            {"scale", s.params.scale},
            {"rdr", vec(s.rdr)},
            {"ld_mm", vec(s.ld)},
            {"preset", s.preset}};
}

MaterialSettings materialFromJson(const json& j, const std::string& where) {
    MaterialSettings s;
    std::string mode = get<std::string>(j, "mode", where);
    if (mode != "sigma" && mode != "rdr_ld")
        throw core::Error(where, 0, "mode must be 'sigma' or 'rdr_ld', got '" + mode + "'");
    s.mode = mode == "sigma" ? ParamMode::Sigma : ParamMode::RdrLd;
    s.params.sigmaA = vecFrom(j, "sigma_a", where);
    s.params.sigmaS = vecFrom(j, "sigma_s", where);
    s.params.g = get<double>(j, "g", where);
    s.params.eta = get<double>(j, "eta", where);
    s.params.scale = get<double>(j, "scale", where);
    s.rdr = vecFrom(j, "rdr", where);
    s.ld = vecFrom(j, "ld_mm", where);
    s.preset = get<std::string>(j, "preset", where);
    return s;
}

json toJson(const PlotSettings& s) {
    return {{"y_scale", plot::scaleName(s.yScale)},
            {"r_times_r", s.rTimesR},
            {"channel", s.channel},
            {"solo", s.solo},
            {"samples", s.samples},
            {"fixed_range", s.fixedRange},
            {"r_max_mm", s.rMaxMm},
            {"range_ld", s.rangeLd}};
}

PlotSettings plotFromJson(const json& j, const std::string& where) {
    PlotSettings s;
    std::string scale = get<std::string>(j, "y_scale", where);
    if (scale == "linear")
        s.yScale = plot::Scale::Linear;
    else if (scale == "log")
        s.yScale = plot::Scale::Log;
    else if (scale == "sqrt")
        s.yScale = plot::Scale::Sqrt;
    else
        throw core::Error(where, 0, "y_scale must be linear, log or sqrt");
    s.rTimesR = get<bool>(j, "r_times_r", where);
    s.channel = get<int>(j, "channel", where);
    s.solo = get<std::string>(j, "solo", where);
    s.samples = get<int>(j, "samples", where);
    s.fixedRange = get<bool>(j, "fixed_range", where);
    s.rMaxMm = get<double>(j, "r_max_mm", where);
    s.rangeLd = get<double>(j, "range_ld", where);
    if (s.samples < 2) throw core::Error(where, 0, "samples must be >= 2");
    return s;
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
        if (!it->is_array() || it->size() != 3)
            throw core::Error(where, 0, "value of '" + it.key() + "' must be 3 numbers");
        v[it.key()] = {(*it)[0].get<float>(), (*it)[1].get<float>(), (*it)[2].get<float>()};
    }
    return v;
}

} // namespace app
