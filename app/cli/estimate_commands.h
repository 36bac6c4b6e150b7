// `bssrdf-workbench estimate` and `merge`: the whole BSSRDF of the slab at oblique incidence
// (pathtrace/bssrdf_estimate.h, seed 001) written as a table file (pathtrace/bssrdf_table.h)
// and optionally as CSV; `--shard K/N` runs the K-th of N disjoint chunk ranges, and `merge`
// adds shards into exactly the table one run of all paths gives. `--gpu` traces on the GL
// compute walk (pathtrace/gpu_bssrdf.h) on a headless context, without shards. Bad arguments are
// core::Error naming the flag, checked (including that the outputs can be written) before any work.
#pragma once

#include "pathtrace/bssrdf_estimate.h"
#include "pathtrace/pathtrace.h"

#include <filesystem>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace app {

struct EstimateArgs {
    pathtrace::Medium medium;
    pathtrace::EstimateSettings settings;
    std::string thetaI = "0";  // --theta-i DEG[,DEG…]
    std::string dirBins = "1"; // --dir-bins K (K rings × K sectors) or RxS
    std::string shard;         // --shard K/N (1 ≤ K ≤ N)
    bool logR = false, multipleOnly = false, singleOnly = false, gpu = false;
    std::string out, csv, csvDir;
};
void addEstimateOptions(CLI::App* cmd, EstimateArgs& a);
// Returns 0, or kEnergyCheckFailed (common/exit_codes.h) when a slice fails its energy check (the
// files are still written). `root` (the project root, for shaders/) is needed with --gpu only.
int runEstimateCli(EstimateArgs a, const std::filesystem::path& root = {});

struct MergeArgs {
    std::vector<std::string> inputs;
    std::string out, csv, csvDir;
    std::string slabCsv;   // slab-shaped tables (slab --shard): the CSV `slab` writes
    bool geometry = false; // the inputs are folders of `compare --geometry --shard`
    bool plots = true;     // folders of `compare --shard`: the reports' plots
};
void addMergeOptions(CLI::App* cmd, MergeArgs& a);
int runMergeCli(const MergeArgs& a);

} // namespace app
