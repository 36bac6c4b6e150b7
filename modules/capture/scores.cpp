// scores.json read back (scores.h).
#include "capture/scores.h"

#include "core/core.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace capture {
using nlohmann::json;

std::vector<ScoreRow> readScores(const std::string& file) {
    json j;
    try {
        j = json::parse(core::readFile(file));
    } catch (const json::exception& e) {
        throw core::Error(file, 0, std::string("not JSON: ") + core::printableText(e.what()));
    }
    if (!j.is_object() || !j.contains("schema") || !j["schema"].is_string() ||
        j["schema"].get<std::string>() != kScoresSchema)
        throw core::Error(file, 0,
                          std::string("not a scores file (expected \"schema\": \"") +
                              kScoresSchema + "\")");
    if (!j.contains("version") || !j["version"].is_number_integer())
        throw core::Error(file, 0, "version: expected an integer");
    if (const int v = j["version"].get<int>(); v == 1)
        throw core::Error(file, 0,
                          "scores of schema version 1, which ranked by rel_l2; this version (" +
                              std::to_string(kScoresVersion) +
                              ") ranks by rel_err, a different measure: run `compare` again to "
                              "make the baseline");
    else if (v != kScoresVersion)
        throw core::Error(file, 0,
                          "scores of schema version " + std::to_string(v) + " (expected " +
                              std::to_string(kScoresVersion) + ")");
    if (!j.contains("rows") || !j["rows"].is_array())
        throw core::Error(file, 0, "rows: expected an array");
    std::vector<ScoreRow> rows;
    for (size_t i = 0; i < j["rows"].size(); ++i) {
        const json& r = j["rows"][i];
        const std::string at = "rows[" + std::to_string(i) + "]";
        auto str = [&](const char* k) {
            if (!r.is_object() || !r.contains(k) || !r[k].is_string())
                throw core::Error(file, 0, at + "." + k + ": expected a string");
            return r[k].get<std::string>();
        };
        auto num = [&](const char* k) {
            if (!r.contains(k) || !r[k].is_number())
                throw core::Error(file, 0, at + "." + k + ": expected a number");
            return r[k].get<double>();
        };
        ScoreRow s;
        s.model = str("model");
        s.preset = str("preset");
        s.channel = str("channel");
        s.thetaI = num("theta_i");
        s.relErr = num("rel_err");
        s.relErrSe = num("rel_err_se");
        if (!(std::isfinite(s.thetaI) && s.relErr >= 0 && std::isfinite(s.relErr) &&
              s.relErrSe >= 0 && std::isfinite(s.relErrSe)))
            throw core::Error(file, 0,
                              at + ": theta_i, rel_err and rel_err_se must be finite, "
                                   "rel_err and rel_err_se >= 0");
        rows.push_back(s);
    }
    return rows;
}

} // namespace capture
