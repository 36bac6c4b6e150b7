// Command-line subcommands that never need a display: profile, invert, record, replay.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace app {

// "R,G,B" or a single number for all three channels; throws core::Error naming `argName`.
glm::dvec3 parseRgb(const std::string& text, const std::string& argName);

struct ProfileArgs {
    std::string model, preset, sigmaA, sigmaS, out;
    std::optional<double> g, eta, rMax;
    int samples = 512;
};
int runProfile(const std::filesystem::path& root, const ProfileArgs& a);

struct InvertArgs {
    std::string model, rdr, ld;
    std::optional<double> g, eta;
};
int runInvert(const std::filesystem::path& root, const InvertArgs& a);

struct RecordArgs {
    std::string name, preset, outDir;
    std::vector<std::string> models;
    uint64_t referencePaths = 0; // > 0: also record the path-traced reference (per channel)
    int referenceBins = 200;
    int litSphereSize = 0; // > 0: also record the lit-sphere images at this size
    std::string litMesh;   // with litSphereSize: path trace this OBJ instead of the sphere
};
int runRecord(const std::filesystem::path& root, const RecordArgs& a);

int runReplay(const std::filesystem::path& root, const std::string& dir, bool update);

} // namespace app
