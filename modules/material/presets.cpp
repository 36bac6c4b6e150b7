// material presets: measured media from materials/presets.json, one table per publication
// (Jensen et al. 2001: reduced σ′s and σa; Narasimhan et al. 2006: σs, σa and g per channel,
// applied as σ′s = σs (1 − g)), in 1/mm, each table with its source and the copies it was read
// from, each entry with its notes and disputes (materials/README.md, section Presets).
#include "material.h"

#include "core/core.h"
#include "core/text.h"
#include "detail/messages.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <set>

namespace material {

namespace {

using nlohmann::json;

// Where an entry is written, for its messages: file, line and "preset 'X': ".
struct Where {
    std::string file;
    int line = 0;
    std::string prefix;
};
[[noreturn]] void fail(const Where& w, const std::string& message) {
    throw core::Error(w.file, w.line, w.prefix + message);
}

// Three finite values >= 0 (g: in (-1, 1)) from entry[key]; errors name the preset and line.
glm::dvec3 triple(const json& entry, const char* key, const Where& where, bool isG = false) {
    if (!entry.contains(key)) fail(where, "missing \"" + std::string(key) + "\"");
    const json& v = entry[key];
    if (!v.is_array() || v.size() != 3)
        fail(where, "\"" + std::string(key) + "\" needs 3 values (R, G, B)");
    glm::dvec3 out;
    for (int c = 0; c < 3; ++c) {
        if (!v[c].is_number())
            fail(where, "\"" + std::string(key) +
                            "\" holds a value that is not a "
                            "number");
        out[c] = v[c].get<double>();
        const bool ok = std::isfinite(out[c]) && (isG ? std::abs(out[c]) < 1 : out[c] >= 0);
        if (!ok)
            fail(where, "\"" + std::string(key) + "\" channel " + detail::channelName(c) + " is " +
                            core::formatNumber(out[c], 6) +
                            (isG ? ", outside (-1, 1)" : ", not a value >= 0"));
    }
    return out;
}

std::string text(const json& j, const char* key, const Where& where) {
    if (!j.contains(key) || !j[key].is_string())
        fail(where, "missing the text \"" + std::string(key) + "\"");
    return j[key].get<std::string>();
}

} // namespace

std::vector<Preset> loadPresets(const std::filesystem::path& file) {
    const std::string content = core::readFile(file);
    json j;
    try {
        j = json::parse(content);
    } catch (const json::parse_error& e) {
        int line = core::lineOfOffset(content, e.byte > 0 ? e.byte - 1 : 0);
        throw core::Error(file.string(), line, std::string("invalid JSON: ") + e.what());
    } catch (const json::exception& e) {
        // e.g. out_of_range 406: a number too large for a double ("1e999")
        throw core::Error(file.string(), 0, std::string("invalid JSON: ") + e.what());
    }
    // the line of an entry: where its name is written
    auto lineOf = [&](const std::string& name) {
        const size_t at = content.find("\"" + name + "\"");
        return at == std::string::npos ? 0 : core::lineOfOffset(content, at);
    };
    auto where = [&](const std::string& name) {
        return Where{file.string(), lineOf(name), "preset '" + name + "': "};
    };
    if (!j.is_object()) throw core::Error(file.string(), 0, "expected a JSON object");
    json tables;
    if (j.contains("tables")) {
        if (j.value("version", 0) != 2)
            throw core::Error(file.string(), 0, "\"tables\" needs \"version\": 2");
        tables = j["tables"];
    } else if (j.contains("presets")) { // version 1: one table of σ′s and σa
        tables = json::array({{{"id", "presets"},
                               {"name", "presets"},
                               {"source", j.value("source", std::string("(no source given)"))},
                               {"form", "sigma_s_prime"},
                               {"presets", j["presets"]}}});
    } else {
        throw core::Error(file.string(), 0, "expected an array \"tables\" (or \"presets\")");
    }
    if (!tables.is_array()) throw core::Error(file.string(), 0, "\"tables\" must be an array");
    std::vector<Preset> out;
    std::set<std::string> names;
    for (const json& t : tables) {
        if (!t.is_object()) throw core::Error(file.string(), 0, "a table must be an object");
        const Where tw{file.string(), lineOf(t.value("id", std::string())),
                       "table '" + t.value("id", std::string("?")) + "': "};
        const std::string id = text(t, "id", tw), tableName = text(t, "name", tw);
        const std::string source = text(t, "source", tw), form = text(t, "form", tw);
        if (form != "sigma_s_prime" && form != "sigma_s_and_g")
            fail(tw, "\"form\" must be \"sigma_s_prime\" or \"sigma_s_and_g\", got '" + form + "'");
        const double eta = t.value("eta", 1.3);
        if (!t.contains("presets") || !t["presets"].is_array())
            fail(tw, "expected an array \"presets\"");
        for (const json& p : t["presets"]) {
            if (!p.is_object() || !p.contains("name") || !p["name"].is_string())
                fail(tw, "a preset without a \"name\"");
            Preset pr;
            pr.name = p["name"].get<std::string>();
            const Where w = where(pr.name);
            if (!names.insert(pr.name).second) fail(w, "the name is used twice");
            pr.table = id;
            pr.tableName = tableName;
            pr.source = source;
            pr.sigmaA = triple(p, "sigma_a", w);
            if (form == "sigma_s_prime") {
                pr.sigmaSPrime = triple(p, "sigma_s_prime", w);
            } else {
                const glm::dvec3 s = triple(p, "sigma_s", w);
                pr.publishedG = triple(p, "g", w, true);
                pr.sigmaSPrime = s * (glm::dvec3(1.0) - pr.publishedG);
                pr.hasG = true;
            }
            pr.eta = p.value("eta", eta);
            if (!(std::isfinite(pr.eta) && pr.eta > 0)) fail(w, "eta must be > 0");
            pr.note = p.value("note", std::string());
            if (p.contains("disputed")) {
                const json& d = p["disputed"];
                const glm::dvec3 alt = triple(d, "sigma_a", w);
                pr.disputed = true;
                pr.note += std::string(pr.note.empty() ? "" : "; ") + "disputed: sigma_a (" +
                           core::formatNumber(alt.x, 4) + ", " + core::formatNumber(alt.y, 4) +
                           ", " + core::formatNumber(alt.z, 4) + ") in " + text(d, "in", w) + ": " +
                           text(d, "note", w);
            }
            for (int c = 0; c < 3 && pr.unusable.empty(); ++c)
                if (!(pr.sigmaSPrime[c] > 0))
                    pr.unusable = std::string("sigma_s = 0 in channel ") + detail::channelName(c) +
                                  " (the measured medium does not scatter there): the models "
                                  "need sigma_s > 0";
            out.push_back(std::move(pr));
        }
    }
    if (out.empty()) throw core::Error(file.string(), 0, "no presets");
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
    if (!preset.unusable.empty())
        throw core::Error("preset", 0, preset.name + ": " + preset.unusable);
    base.sigmaA = preset.sigmaA;
    base.sigmaS = preset.sigmaSPrime / (1.0 - base.g);
    base.eta = preset.eta;
    return base;
}

} // namespace material
