// Arguments shared by the commands: R,G,B triples, model files, materials from --preset or σ,
// shards. Each parser throws core::Error naming the argument.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace app {

// "R,G,B" or a single number for all three channels; throws core::Error naming `argName`.
glm::dvec3 parseRgb(const std::string& text, const std::string& argName);

class Workbench;
struct MaterialSettings;
// A model file (or another file the option `flag` names) as given or relative to the root; for
// a model (--model, --from) a bare NAME is also materials/NAME.bssrdf of the root. Throws
// core::Error naming the flag when missing (for a model, listing the root's models) or a folder
// (naming its full path).
std::filesystem::path resolveModel(const std::filesystem::path& root, const std::string& model,
                                   const std::string& flag = "--model");
// Material settings from --preset or --sigma-a/--sigma-s (+ --g, --eta), validated.
MaterialSettings settingsFromArgs(Workbench& wb, const std::string& preset,
                                  const std::string& sigmaA, const std::string& sigmaS,
                                  std::optional<double> g, std::optional<double> eta);

// "WxH" with both sides in [minSide, 8192]: false when malformed or out of range.
bool parseSize(const std::string& text, int& w, int& h, int minSide = 64);

// "K/N" → (K − 1, N); core::Error naming `flag` when malformed or K not in [1, N].
// The model files of a command: `models` resolved (resolveModel), or every materials/*.bssrdf
// in name order; throws core::Error("--models", …) when there are none.
std::vector<std::filesystem::path> modelFiles(const std::filesystem::path& root,
                                              const std::vector<std::string>& models);

// The shard folders given to `merge` for one run: add() refuses a shard K given twice (naming
// both files), complete() names the missing ones.
class ShardSet {
  public:
    void add(size_t k, size_t n, const std::string& file, const std::string& folder);
    void complete() const;

  private:
    size_t m_n = 0;
    std::map<size_t, std::string> m_folders;
};

std::pair<uint64_t, uint64_t> parseShard(const std::string& text, const std::string& flag);

} // namespace app
