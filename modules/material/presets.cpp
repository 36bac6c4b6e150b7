// material presets: Jensen et al. 2001 measured σ′s, σa (1/mm) from materials/presets.json.
#include "material.h"

#include "core/core.h"
#include "core/text.h"

#include <nlohmann/json.hpp>

namespace material {

std::vector<Preset> loadPresets(const std::filesystem::path& file) {
    const std::string text = core::readFile(file);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        int line = core::lineOfOffset(text, e.byte > 0 ? e.byte - 1 : 0);
        throw core::Error(file.string(), line, std::string("invalid JSON: ") + e.what());
    } catch (const nlohmann::json::exception& e) {
        // e.g. out_of_range 406: a number too large for a double ("1e999")
        throw core::Error(file.string(), 0, std::string("invalid JSON: ") + e.what());
    }
    std::vector<Preset> out;
    if (!j.contains("presets") || !j["presets"].is_array())
        throw core::Error(file.string(), 0, "expected an array \"presets\"");
    for (const auto& p : j["presets"]) {
        Preset pr;
        try {
            pr.name = p.at("name").get<std::string>();
            auto s = p.at("sigma_s_prime").get<std::vector<double>>();
            auto a = p.at("sigma_a").get<std::vector<double>>();
            if (s.size() != 3 || a.size() != 3)
                throw core::Error(file.string(), 0,
                                  "preset " + pr.name + ": sigma arrays need 3 values");
            pr.sigmaSPrime = {s[0], s[1], s[2]};
            pr.sigmaA = {a[0], a[1], a[2]};
            pr.eta = p.value("eta", 1.3);
        } catch (const nlohmann::json::exception& e) {
            throw core::Error(file.string(), 0, std::string("bad preset entry: ") + e.what());
        }
        out.push_back(pr);
    }
    return out;
}

const Preset* findPreset(const std::vector<Preset>& presets, const std::string& name) {
    for (const auto& p : presets)
        if (p.name == name) return &p;
    return nullptr;
}

std::string unknownPresetMessage(const std::vector<Preset>& presets, const std::string& name) {
    std::vector<std::string> names;
    std::string known;
    for (const auto& p : presets) {
        names.push_back(p.name);
        known += (known.empty() ? "" : ", ") + p.name;
    }
    const std::string nearest = core::nearestName(name, names);
    return "unknown preset '" + name + "' (" +
           (nearest.empty() ? "" : "did you mean '" + nearest + "'? ") + "known: " + known + ")";
}

MaterialParams applyPreset(const Preset& preset, MaterialParams base) {
    base.sigmaA = preset.sigmaA;
    base.sigmaS = preset.sigmaSPrime / (1.0 - base.g);
    base.eta = preset.eta;
    return base;
}

} // namespace material
