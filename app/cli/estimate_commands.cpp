// `bssrdf-workbench estimate` / `merge` (see estimate_commands.h).
#include "cli/estimate_commands.h"
#include "cli/args.h"
#include "cli/command.h"
#include "cli/compare_command.h"
#include "cli/compare_geometry.h"

#include "cli/interrupt.h"

#include "cli/options.h"
#include "cli/output.h"
#include "cli/slab_command.h"

#include "core/core.h"
#include "core/text.h"
#include "gl/gl.h"
#include "pathtrace/bssrdf_table.h"
#include "pathtrace/gpu_bssrdf.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

namespace app {
namespace fs = std::filesystem;

namespace {

// A number list "0,45,75" (core::Error naming the flag).
std::vector<double> parseList(const std::string& text, const std::string& flag) {
    std::vector<double> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        size_t used = 0;
        double v = 0;
        try {
            v = std::stod(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != item.size())
            throw core::Error(flag, 0, "expected numbers separated by commas, got '" + text + "'");
        out.push_back(v);
    }
    if (out.empty()) throw core::Error(flag, 0, "give at least one value");
    return out;
}

int parseCount(const std::string& s, const std::string& flag, const std::string& text) {
    size_t used = 0;
    long v = 0;
    try {
        v = std::stol(s, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != s.size() || v < 1 || v > 1000)
        throw core::Error(flag, 0,
                          "expected K or RxS with counts in [1, 1000], got '" + text + "'");
    return int(v);
}

void writeOutputs(const pathtrace::BssrdfTable& t, const std::string& out, const std::string& csv,
                  const std::string& csvDir) {
    pathtrace::writeTable(out, t);
    std::fprintf(stderr, "wrote %s\n", out.c_str());
    if (!csv.empty()) {
        core::writeFile(csv, pathtrace::tableCsv(t));
        std::fprintf(stderr, "wrote %s\n", csv.c_str());
    }
    if (!csvDir.empty()) {
        core::writeFile(csvDir, pathtrace::tableDirCsv(t));
        std::fprintf(stderr, "wrote %s\n", csvDir.c_str());
    }
}

// Prints each slice's totals and energy check; returns kEnergyCheckFailed if one fails.
int report(const pathtrace::BssrdfTable& t) {
    int rc = 0;
    for (size_t a = 0; a < t.tallies.size(); ++a) {
        const auto s = t.slice(a);
        const std::string problem = pathtrace::energyProblem(s, t.settings.orders);
        std::fprintf(
            stderr, "theta_i %s: %llu paths, R %s +- %s, energy check %s\n",
            core::formatNumber(s.thetaIDeg).c_str(), static_cast<unsigned long long>(s.paths),
            core::formatNumber(s.totalRd).c_str(), core::formatNumber(s.totalRdStderr).c_str(),
            problem.empty() ? "ok" : problem.c_str());
        if (!problem.empty()) rc = kEnergyCheckFailed;
    }
    return rc;
}

} // namespace

void addEstimateOptions(CLI::App* cmd, EstimateArgs& a) {
    addMediumOptions(cmd, a.medium);
    cmd->add_option("--theta-i", a.thetaI, "incidence angles in degrees, [0, 90): DEG[,DEG...]")
        ->capture_default_str();
    addSettingOptions(cmd, a.settings,
                      {{"bins.r_bins", "--r-bins"},
                       {"bins.r_max_mm", "--rmax"},
                       {"bins.r_start_mm", "--r-start"},
                       {"bins.r_min_mm", "--r-min"},
                       {"bins.theta_s_bins", "--theta-s-bins"},
                       {"paths", "--paths"},
                       {"seed", "--seed"},
                       {"estimator", "--estimator"},
                       {"termination.max_events", "--max-events"},
                       {"termination.roulette_weight", "--roulette-weight"},
                       {"termination.roulette_survival", "--roulette-survival"},
                       {"splitting.levels", "--split-levels"},
                       {"splitting.start_ld", "--split-start"},
                       {"splitting.step_ld", "--split-step"},
                       {"splitting.depth", "--split-depth"},
                       {"exits.samples", "--exit-samples"},
                       {"exits.depth_mfp", "--exit-depth"}});
    cmd->add_flag("--log-r", a.logR, "logarithmic radial bins (first bin [0, r-min))");
    cmd->add_option("--dir-bins", a.dirBins,
                    "exit-direction cells of equal solid angle: K (K rings x K sectors) or RxS")
        ->capture_default_str();
    cmd->add_flag("--multiple-only", a.multipleOnly, "skip the first scattering event");
    cmd->add_flag("--single-only", a.singleOnly, "the first scattering event only");
    addCountOption(cmd, "--threads", a.settings.threads,
                   "worker threads, 0 … 1024 (default 0: all cores; CPU only)", kThreadLimits);
    cmd->add_option("--shard", a.shard,
                    "run shard K of N (1 <= K <= N): a disjoint range of the same paths; combine "
                    "with `merge` (CPU only)");
    cmd->add_flag("--gpu", a.gpu, "trace on the GL compute walk (headless context)");
    cmd->add_option("--out", a.out, "table file to write (.bwtable)")->required();
    cmd->add_option("--csv", a.csv,
                    "CSV per spatial bin: theta_i_deg,r_lo_mm,r_hi_mm,theta_s_lo_deg,"
                    "theta_s_hi_deg,R,stderr");
    cmd->add_option("--csv-dir", a.csvDir,
                    "CSV per direction cell: ...,theta_o_deg,phi_o_deg,solid_angle_sr,S,stderr");
    refuseWithGlTracer(cmd, a.gpu);
}

int runEstimateCli(EstimateArgs a, const std::filesystem::path& root) {
    pathtrace::validate(a.medium, "estimate");
    a.settings.thetaIDeg = parseList(a.thetaI, "--theta-i");
    for (double t : a.settings.thetaIDeg)
        if (!(std::isfinite(t) && t >= 0 && t < 90))
            throw core::Error("--theta-i", 0,
                              "incidence angles must lie in [0, 90) degrees, got " +
                                  core::formatNumber(t));
    const size_t x = a.dirBins.find('x');
    if (x == std::string::npos) {
        a.settings.bins.dirCosBins = a.settings.bins.dirPhiBins =
            parseCount(a.dirBins, "--dir-bins", a.dirBins);
    } else {
        a.settings.bins.dirCosBins = parseCount(a.dirBins.substr(0, x), "--dir-bins", a.dirBins);
        a.settings.bins.dirPhiBins = parseCount(a.dirBins.substr(x + 1), "--dir-bins", a.dirBins);
    }
    if (a.logR) a.settings.bins.spacing = pathtrace::RadialSpacing::Log;
    if (a.multipleOnly && a.singleOnly)
        throw core::Error("--single-only", 0, "cannot be combined with --multiple-only");
    if (a.multipleOnly) a.settings.orders = pathtrace::ScatterOrders::MultipleOnly;
    if (a.singleOnly) a.settings.orders = pathtrace::ScatterOrders::SingleOnly;
    pathtrace::validate(a.settings);
    if (a.gpu && !a.shard.empty())
        throw core::Error("--shard", 0,
                          "shards run on the CPU walk (leave out --gpu): the GL walk's error bars "
                          "come from batch means over its whole run, so its tables would not "
                          "merge into exactly the table of one run");
    uint64_t first = 0, last = pathtrace::chunkCount(a.settings);
    if (!a.shard.empty()) {
        const auto [k, n] = parseShard(a.shard, "--shard");
        std::tie(first, last) = pathtrace::shardChunks(a.settings, k, n);
    }
    checkWritable(a.out, "--out");
    checkWritable(a.csv, "--csv");
    checkWritable(a.csvDir, "--csv-dir");
    core::Stopwatch clock;
    const uint64_t total = [&] {
        const uint64_t paths = std::min(last * pathtrace::kChunkPaths, a.settings.paths) -
                               std::min(first * pathtrace::kChunkPaths, a.settings.paths);
        return paths * a.settings.thetaIDeg.size();
    }();
    const auto progress = [&](uint64_t done) {
        printPathProgress("estimate", done, total, clock.ms() / 1000.0);
    };
    std::string device = "CPU";
    const auto table = [&] {
        if (!a.gpu)
            return pathtrace::estimateTable(a.medium, a.settings, first, last, progress,
                                            interruptFlag());
        auto ctx = gl::createHeadlessContext(false);
        device = std::string("GPU (") + ctx->renderer() + ")";
        pathtrace::GpuBssrdfEstimator gpu(root / "shaders" / "bssrdf_walk.comp");
        return pathtrace::estimateTableGpu(gpu, a.medium, a.settings, progress, interruptFlag());
    }();
    core::progressEnd();
    std::fprintf(stderr, "traced on %s\n", device.c_str());
    writeOutputs(table, a.out, a.csv, a.csvDir);
    if (interrupted()) {
        // The table holds the paths traced so far (its tallies count them) and merges like
        // any shard; the run is incomplete, so the exit status says so.
        std::fprintf(stderr,
                     "error: estimate: interrupted: %s holds %llu of %llu paths per angle "
                     "(partial)\n",
                     a.out.c_str(), static_cast<unsigned long long>(table.tallies[0].paths),
                     static_cast<unsigned long long>(total / a.settings.thetaIDeg.size()));
        return kInterrupted;
    }
    return report(table);
}

void addMergeOptions(CLI::App* cmd, MergeArgs& a) {
    cmd->add_option("files", a.inputs,
                    "table files (shards of one estimate run), or with --geometry the folders of "
                    "`compare --geometry --shard` runs")
        ->required();
    cmd->add_option("--out", a.out, "merged table file (--geometry: the output folder)")
        ->required();
    cmd->add_flag("!--no-plots", a.plots, "compare shards: reports without the PNG plots");
    cmd->add_flag("--geometry", a.geometry,
                  "merge `compare --geometry --shard K/N` folders into one run's scores and "
                  "reports");
    cmd->add_option("--csv", a.csv, "CSV per spatial bin (as estimate --csv)");
    cmd->add_option("--csv-dir", a.csvDir, "CSV per direction cell (as estimate --csv-dir)");
    cmd->add_option("--slab-csv", a.slabCsv,
                    "for shards of `slab --shard`: the CSV `slab` writes for the whole run");
}

int runMergeCli(const MergeArgs& a) {
    // folders of `compare --shard` or `compare --geometry --shard`: told apart by their shard.json
    std::error_code ec;
    const bool folders = !a.inputs.empty() && fs::is_directory(a.inputs.front(), ec);
    if (a.geometry || folders) {
        if (!a.csv.empty() || !a.csvDir.empty() || !a.slabCsv.empty())
            throw core::Error(!a.csv.empty()      ? "--csv"
                              : !a.csvDir.empty() ? "--csv-dir"
                                                  : "--slab-csv",
                              0, "compare shards merge into --out only");
        const std::string kind =
            a.geometry ? "" : core::readFile(fs::path(a.inputs.front()) / "shard.json");
        if (a.geometry || kind.find("bssrdf-workbench-geometry-shard") != std::string::npos) {
            if (!a.plots)
                throw core::Error("--no-plots", 0,
                                  "geometry shards bring their own pictures: run them with "
                                  "--no-plots instead");
            return runMergeGeometryCli(a.inputs, a.out);
        }
        return runMergeCompareCli(a.inputs, a.out, a.plots);
    }
    if (!a.plots)
        throw core::Error("--no-plots", 0,
                          "only for folders of `compare --shard` (tables have no plots)");
    checkWritable(a.out, "--out");
    checkWritable(a.csv, "--csv");
    checkWritable(a.csvDir, "--csv-dir");
    checkWritable(a.slabCsv, "--slab-csv");
    std::vector<pathtrace::BssrdfTable> tables;
    for (const auto& f : a.inputs)
        tables.push_back(pathtrace::readTable(f));
    const auto merged = pathtrace::mergeTables(tables, a.inputs);
    writeOutputs(merged, a.out, a.csv, a.csvDir);
    int slabRc = 0;
    if (!a.slabCsv.empty()) {
        pathtrace::SlabSettings s;
        const pathtrace::SlabResult r = pathtrace::slabResultOf(merged, s, "--slab-csv");
        slabRc = writeSlabCsv(a.slabCsv, merged.medium, s, r, "CPU (merged shards)");
    }
    if (!merged.complete()) {
        uint64_t have = 0;
        for (const auto& [f, l] : merged.chunks)
            have += l - f;
        std::fprintf(stderr,
                     "note: the merged table covers %llu of the run's %llu chunks (a partial "
                     "run: still unbiased, with fewer paths)\n",
                     static_cast<unsigned long long>(have),
                     static_cast<unsigned long long>(pathtrace::chunkCount(merged.settings)));
    }
    const int rc = report(merged);
    return rc != 0 ? rc : slabRc;
}

Command estimateCommand() {
    return {"estimate", "the whole BSSRDF of the slab at oblique incidence (seed 001) as a table",
            false, [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<EstimateArgs>();
                addEstimateOptions(&cmd, *a);
                return [a](CommandContext& ctx) {
                    return a->gpu ? runEstimateCli(*a, ctx.root()) : runEstimateCli(*a);
                };
            }};
}

Command mergeCommand() {
    return {"merge", "merge shards (estimate, slab or compare --geometry --shard) into one result",
            false, [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<MergeArgs>();
                addMergeOptions(&cmd, *a);
                return [a](CommandContext&) { return runMergeCli(*a); };
            }};
}

} // namespace app
