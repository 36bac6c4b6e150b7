// Arguments shared by the commands: R,G,B triples, model files, materials, shards.
#include "cli/args.h"

#include "core/core.h"
#include "material/material.h"
#include "pipeline/workbench.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

namespace app {
namespace fs = std::filesystem;

glm::dvec3 parseRgb(const std::string& text, const std::string& argName) {
    std::vector<double> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        double d = std::strtod(item.c_str(), &end);
        if (item.empty() || end == item.c_str() || *end != '\0')
            throw core::Error(argName, 0, "'" + item + "' is not a number (expected R,G,B)");
        v.push_back(d);
    }
    if (v.size() == 1) return glm::dvec3(v[0]);
    if (v.size() != 3)
        throw core::Error(argName, 0,
                          "expected 3 comma-separated values R,G,B (or one for all), got " +
                              std::to_string(v.size()));
    return {v[0], v[1], v[2]};
}

namespace {
// "; the models in ROOT/materials: a, b, c": what a misspelt model name could have been
std::string modelsThere(const fs::path& root) {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(root / "materials", ec))
        if (e.path().extension() == ".bssrdf") names.push_back(e.path().stem().string());
    if (names.empty()) return "; no models in " + (root / "materials").string();
    std::sort(names.begin(), names.end());
    std::string out = "; the models in " + (root / "materials").string() + ": ";
    for (size_t i = 0; i < names.size(); ++i)
        out += (i ? ", " : "") + names[i];
    return out;
}
} // namespace

fs::path resolveModel(const fs::path& root, const std::string& model, const std::string& flag) {
    const bool isModel = flag == "--model" || flag == "--from";
    fs::path p = model;
    if (!fs::exists(p) && fs::exists(root / p)) p = root / p;
    // a bare name, as the Models panel lists a model and `new-model` makes one: NAME stands for
    // materials/NAME.bssrdf
    if (!fs::exists(p) && isModel && !model.empty() && p.parent_path().empty())
        for (const fs::path& c :
             {root / "materials" / model, root / "materials" / (model + ".bssrdf")})
            if (fs::is_regular_file(c)) {
                p = c;
                break;
            }
    if (!fs::exists(p))
        throw core::Error(model, 0, flag + ": no such file" + (isModel ? modelsThere(root) : ""));
    if (fs::is_directory(p))
        throw core::Error(fs::absolute(p).lexically_normal().string(), 0,
                          flag + ": a folder, expected " +
                              (flag == "--model" ? "a .bssrdf file" : "a file"));
    return p;
}

MaterialSettings settingsFromArgs(Workbench& wb, const std::string& preset,
                                  const std::string& sigmaA, const std::string& sigmaS,
                                  std::optional<double> g, std::optional<double> eta) {
    MaterialSettings s;
    if (g) s.params.g = *g;
    if (!preset.empty()) {
        if (!sigmaA.empty() || !sigmaS.empty())
            throw core::Error("--preset", 0, "give either --preset or --sigma-a/--sigma-s");
        if (!material::findPreset(wb.presets(), preset)) // named by the argument
            throw core::Error("--preset", 0, material::unknownPresetMessage(wb.presets(), preset));
        wb.applyPreset(s, preset); // σs = σ′s/(1−g), η from the preset
    } else {
        if (sigmaA.empty() || sigmaS.empty())
            throw core::Error("--sigma-a", 0, "give --preset NAME or both --sigma-a and --sigma-s");
        s.params.sigmaA = parseRgb(sigmaA, "--sigma-a");
        s.params.sigmaS = parseRgb(sigmaS, "--sigma-s");
        s.preset.clear();
    }
    if (eta) s.params.eta = *eta;
    material::validate(s.params, "arguments");
    return s;
}

bool parseSize(const std::string& s, int& w, int& h, int minSide) {
    char tail = 0;
    return std::sscanf(s.c_str(), "%dx%d%c", &w, &h, &tail) == 2 && w >= minSide && h >= minSide &&
           w <= 8192 && h <= 8192;
}

std::pair<uint64_t, uint64_t> parseShard(const std::string& text, const std::string& flag) {
    const size_t slash = text.find('/');
    unsigned long long k = 0, n = 0;
    char tail = 0;
    if (slash == std::string::npos ||
        std::sscanf(text.c_str(), "%llu/%llu%c", &k, &n, &tail) != 2 || n < 1 || k < 1 || k > n ||
        n > 1000000)
        throw core::Error(
            flag, 0, "expected K/N with 1 <= K <= N <= 1000000 (shard K of N), got '" + text + "'");
    return {k - 1, n};
}

std::vector<fs::path> modelFiles(const fs::path& root, const std::vector<std::string>& models) {
    std::vector<fs::path> files;
    std::error_code ec;
    if (models.empty()) {
        for (const auto& e : fs::directory_iterator(root / "materials", ec))
            if (e.path().extension() == ".bssrdf") files.push_back(e.path());
        std::sort(files.begin(), files.end());
    } else {
        for (const auto& m : models)
            files.push_back(resolveModel(root, m));
    }
    if (files.empty()) throw core::Error("--models", 0, "no model files");
    return files;
}

void ShardSet::add(size_t k, size_t n, const std::string& file, const std::string& folder) {
    m_n = n;
    if (const auto it = m_folders.find(k); it != m_folders.end())
        throw core::Error(file, 0,
                          "shard " + std::to_string(k) + "/" + std::to_string(n) + " is also in " +
                              it->second);
    m_folders.emplace(k, folder);
}

void ShardSet::complete() const {
    if (m_folders.size() == m_n) return;
    std::string missing;
    for (size_t k = 1; k <= m_n; ++k)
        if (!m_folders.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
    throw core::Error("merge", 0, "missing shards of " + std::to_string(m_n) + ": " + missing);
}

} // namespace app
