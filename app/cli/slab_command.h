// `bssrdf-workbench slab`: the CPU path-traced pencil-beam reference (pathtrace::runSlab, thesis
// Section 3.2 / Algorithm 1) written as CSV — R_d(r) with per-bin standard errors in the MCML
// convention (1/mm² per incident photon, specular reflection excluded), every parameter and the
// totals in '#' header lines. No display or GL needed. The result's energy check
// (pathtrace::energyProblem) is written into the header; when it fails the CSV is still
// written and the command exits with kEnergyCheckFailed, the problem on stderr.
#pragma once

#include "common/exit_codes.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include "pathtrace/pathtrace.h"

namespace CLI {
class App;
}

namespace app {

struct SlabArgs {
    pathtrace::Medium medium;         // its defaults are the CLI's
    pathtrace::SlabSettings settings; // bins, paths, seed, threads, termination, estimator
    double rMax = NAN;                // mm; NaN: defaultSlabRMax (replaces settings.rMaxMm)
    bool analog = false;              // --analog: settings.estimator = Analog
    bool gpu = false;                 // the GL compute tracer instead of the CPU
    std::string shard;                // --shard K/N: write shard K's table to `out`
    std::string out;                  // CSV path (required); the table with --shard
};
// --sigma-a --sigma-s --g --eta, generated from pathtrace::Medium's description (its defaults).
void addMediumOptions(CLI::App* cmd, pathtrace::Medium& m);
// The options of `slab`: medium and settings options generated from their descriptions
// (options.h), so their flags' defaults are the structs' own.
void addSlabOptions(CLI::App* cmd, SlabArgs& a);
// With --gpu (`gpu` as parsed), the options of what the GL tracers do not do (--split-*,
// --exit-*, --threads) are refused by name: slab's and estimate's (options.h).
void refuseWithGlTracer(CLI::App* cmd, const bool& gpu);

// 10 diffuse mean free paths l_d = 1/σtr, σtr = √(3σa(σa + σs(1 − g))); with σa = 0 (no
// l_d), 100 transport mean free paths 1/(σs(1 − g)).
double defaultSlabRMax(const pathtrace::Medium& m);

// Writes a slab result as the CSV `slab` writes (device: "CPU", "GPU (…)", "merged shards");
// returns 0, or kEnergyCheckFailed (problem on stderr) when it fails its energy check.
int writeSlabCsv(const std::string& path, const pathtrace::Medium& m,
                 const pathtrace::SlabSettings& s, const pathtrace::SlabResult& r,
                 const std::string& device, bool partial = false);

// Validates (core::Error naming the argument; the output must be writable), runs with a
// progress line on stderr, writes the CSV — or with --shard the shard's table. Returns 0, or
// kEnergyCheckFailed.
int runSlabCli(const SlabArgs& a);
// The same on the GL compute tracer (shaders/pathtrace_slab.comp under `root`), headless.
int runSlabGpuCli(const std::filesystem::path& root, const SlabArgs& a);

} // namespace app
