// `bssrdf-workbench slab`: runs pathtrace::runSlab and writes R_d(r) as CSV (see slab_command.h).
#include "cli/slab_command.h"
#include "cli/args.h"
#include "cli/command.h"
#include "pathtrace/mco.h"

#include "cli/interrupt.h"
#include "core/text.h"

#include "cli/options.h"
#include "cli/output.h"

#include "core/core.h"
#include "gl/gl.h"
#include "pathtrace/bssrdf_table.h"
#include "pathtrace/gpu_slab.h"
#include "pathtrace/pathtrace.h"

#include <chrono>
#include <cstdio>
#include <functional>
#include <memory>
#include <sstream>

namespace app {
double defaultSlabRMax(const pathtrace::Medium& m) {
    const double sigmaSReduced = m.sigmaS * (1 - m.g);
    const double sigmaTr = std::sqrt(3 * m.sigmaA * (m.sigmaA + sigmaSReduced));
    if (sigmaTr > 0 && std::isfinite(sigmaTr)) return 10 / sigmaTr;
    return 100 / sigmaSReduced;
}

namespace {
struct SlabSetup {
    pathtrace::Medium m;
    pathtrace::SlabSettings s;
};

SlabSetup prepare(const SlabArgs& a) {
    SlabSetup k;
    k.m = a.medium;
    k.s = a.settings;
    pathtrace::validate(k.m, "slab");
    if (a.out.empty()) throw core::Error("--out", 0, "give the CSV file to write");
    if (!std::isnan(a.rMax) && !(a.rMax > 0 && std::isfinite(a.rMax)))
        throw core::Error(
            "--rmax", 0, "rMax must be a positive length in mm, got " + core::formatNumber(a.rMax));
    k.s.rMaxMm = std::isnan(a.rMax) ? defaultSlabRMax(k.m) : a.rMax;
    if (a.analog) k.s.estimator = pathtrace::Estimator::Analog;
    pathtrace::validate(k.s);
    return k;
}

std::function<void(uint64_t)> progressLine(const pathtrace::SlabSettings& s,
                                           core::Stopwatch& clock) {
    return [&s, &clock](uint64_t done) {
        printPathProgress("slab", done, s.paths, clock.ms() / 1000.0);
    };
}

// What radial splitting did (pathtrace.h, Splitting): off for the GL tracer.
std::string splittingText(const pathtrace::SlabSettings& s) {
    const pathtrace::Splitting& p = s.splitting;
    if (p.levels == 0) return "off";
    return "levels " + std::to_string(p.levels) + ", start " + core::formatNumber(p.startLd) +
           " l_d, step " + core::formatNumber(p.stepLd) + " l_d, depth " +
           core::formatNumber(p.depth);
}

// How exits were tallied (pathtrace.h, ExpectedExits): actual for the GL tracer and the
// connections estimator.
std::string exitsText(const pathtrace::SlabSettings& s) {
    const pathtrace::ExpectedExits& e = s.exits;
    if (e.samples == 0 || s.estimator == pathtrace::Estimator::Connections) return "actual";
    return "expected, " + std::to_string(e.samples) + " samples within " +
           core::formatNumber(e.depthMfp) + " mfp";
}

} // namespace

int writeSlabCsv(const std::string& path, const pathtrace::Medium& m,
                 const pathtrace::SlabSettings& s, const pathtrace::SlabResult& r,
                 const std::string& device, bool partial) {
    const std::string problem = pathtrace::energyProblem(r);
    const double perSecond = r.seconds > 0 ? double(r.paths) / r.seconds : 0;
    std::ostringstream out;
    out << "# bssrdf-workbench slab " << BW_VERSION << "\n"
        << "# " << device
        << " path-traced pencil beam at normal incidence on the semi-infinite "
           "slab z < 0 (thesis 3.2, Algorithm 1)\n"
        << "# R_d(r): diffuse reflectance per unit area per incident photon, 1/mm^2, MCML "
           "convention (specular reflection excluded)\n"
        << "# sigma_a " << core::formatNumber(m.sigmaA) << " 1/mm\n"
        << "# sigma_s " << core::formatNumber(m.sigmaS) << " 1/mm\n"
        << "# g " << core::formatNumber(m.g) << "\n"
        << "# eta " << core::formatNumber(m.eta) << "\n"
        << "# r_max_mm " << core::formatNumber(s.rMaxMm) << "\n"
        << "# bins " << s.bins << "\n"
        << "# bin_width_mm " << core::formatNumber(s.rMaxMm / s.bins) << "\n"
        << "# seed " << s.seed << "\n"
        << "# threads " << s.threads << "\n"
        << "# estimator " << core::nameOf(s.estimator) << "\n"
        << "# roulette_weight " << core::formatNumber(s.termination.rouletteWeight) << "\n"
        << "# roulette_survival " << core::formatNumber(s.termination.rouletteSurvival) << "\n"
        << "# max_events " << s.termination.maxEvents << "\n"
        << "# splitting " << splittingText(s) << "\n"
        << "# exits " << exitsText(s) << "\n"
        << "# paths " << r.paths << "\n"
        << (partial ? "# partial: interrupted after " + std::to_string(r.paths) + " of " +
                          std::to_string(s.paths) + " paths\n"
                    : std::string())
        << "# total_Rd " << core::formatNumber(r.totalRd) << " +- "
        << core::formatNumber(r.totalRdStderr) << "\n"
        << "# specular " << core::formatNumber(r.specular) << "\n"
        << "# absorbed " << core::formatNumber(r.absorbed) << " +- "
        << core::formatNumber(r.absorbedStderr) << "\n"
        << "# roulette_net " << core::formatNumber(r.rouletteNet) << " +- "
        << core::formatNumber(r.rouletteNetStderr) << " (expected 0)\n"
        << "# truncated " << core::formatNumber(r.truncated) << " +- "
        << core::formatNumber(r.truncatedStderr) << " (" << r.truncatedPaths
        << " paths; R_d may be low by up to this much)\n"
        << "# energy_check " << (problem.empty() ? "ok" : "FAILED: " + problem) << "\n"
        << "# events_per_path "
        << core::formatNumber(r.paths ? double(r.events) / double(r.paths) : 0) << "\n"
        << "# wall_s " << core::formatNumber(r.seconds) << "\n"
        << "# paths_per_s " << core::formatNumber(perSecond) << "\n"
        << "r_mm,Rd_per_mm2,stderr\n";
    for (size_t i = 0; i < r.rd.size(); ++i)
        out << core::formatNumber(r.rMid[i]) << ',' << core::formatNumber(r.rd[i]) << ','
            << core::formatNumber(r.rdStderr[i]) << '\n';
    if (std::filesystem::path(path).extension() == ".mco") // MCML's format (pathtrace/mco.h)
        core::writeFile(path, pathtrace::formatMco(pathtrace::mcoFromSlab(
                                  m, s, r, std::filesystem::path(path).filename().string())));
    else
        core::writeFile(path, out.str());
    std::fprintf(stderr, "wrote %s (%llu paths, R_d %s +- %s, %.1f s, %.0f paths/s)\n",
                 path.c_str(), static_cast<unsigned long long>(r.paths),
                 core::formatNumber(r.totalRd).c_str(), core::formatNumber(r.totalRdStderr).c_str(),
                 r.seconds, perSecond);
    if (problem.empty()) return 0;
    std::fprintf(stderr, "error: slab: %s\n", problem.c_str());
    return kEnergyCheckFailed;
}

void addMediumOptions(CLI::App* cmd, pathtrace::Medium& m) {
    addSettingOptions(
        cmd, m,
        {{"sigma_a", "--sigma-a"}, {"sigma_s", "--sigma-s"}, {"g", "--g"}, {"eta", "--eta"}});
}

void addSlabOptions(CLI::App* cmd, SlabArgs& a) {
    addMediumOptions(cmd, a.medium);
    cmd->add_option("--rmax", a.rMax, "histogram radius in mm (default 10 l_d)");
    addSettingOptions(cmd, a.settings,
                      {{"bins", "--bins"},
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
    addCountOption(cmd, "--threads", a.settings.threads,
                   "worker threads, 0 … 1024 (default 0: all cores)", kThreadLimits);
    cmd->add_flag("--analog", a.analog, "same as --estimator analog (thesis Algorithm 1)");
    cmd->add_flag("--gpu", a.gpu, "trace on the GL compute tracer instead of the CPU");
    cmd->add_option("--shard", a.shard,
                    "run shard K of N (1 <= K <= N) and write its table (raw sums) to --out; "
                    "`merge --slab-csv` combines the shards into this command's CSV");
    cmd->add_option("--out", a.out,
                    "CSV file: # header, then r_mm,Rd_per_mm2,stderr; FILE.mco: MCML 1.2.2's "
                    "output format (R_d(r) in 1/cm2); with --shard: the table")
        ->required();
    refuseWithGlTracer(cmd, a.gpu);
}

void refuseWithGlTracer(CLI::App* cmd, const bool& gpu) {
    // the GL tracers neither split paths nor score sampled exits (gpu_slab.h, gpu_bssrdf.h)
    refuseIgnoredOptions(cmd, {{{"--split-levels", "--split-start", "--split-step", "--split-depth",
                                 "--exit-samples", "--exit-depth"},
                                [&gpu] { return gpu; },
                                "the GL tracer neither splits nor samples exits: leave out --gpu"},
                               {{"--threads"},
                                [&gpu] { return gpu; },
                                "the GL tracer runs on the GPU: leave out --threads"}});
}

int runSlabCli(const SlabArgs& a) {
    const SlabSetup k = prepare(a);
    checkWritable(a.out, "--out");
    if (!a.shard.empty()) {
        if (std::filesystem::path(a.out).extension() == ".mco")
            throw core::Error("--out", 0,
                              "a shard writes its table of raw sums, not an MCML file: give "
                              "`merge --slab-csv` the .mco name instead");
        const auto [shard, n] = parseShard(a.shard, "--shard");
        const pathtrace::EstimateSettings e = pathtrace::slabTableSettings(k.s);
        const auto [first, last] = pathtrace::shardChunks(e, shard, n);
        core::Stopwatch clock;
        const auto table = pathtrace::estimateTable(k.m, e, first, last, progressLine(k.s, clock));
        core::progressEnd();
        pathtrace::writeTable(a.out, table);
        std::fprintf(stderr, "wrote %s (shard %s, %llu paths)\n", a.out.c_str(), a.shard.c_str(),
                     static_cast<unsigned long long>(table.tallies[0].paths));
        return 0;
    }
    core::Stopwatch clock;
    const pathtrace::SlabResult r =
        pathtrace::runSlab(k.m, k.s, progressLine(k.s, clock), interruptFlag());
    core::progressEnd();
    if (interrupted()) {
        // what is done so far: the completed prefix of chunks, marked partial in the header
        writeSlabCsv(a.out, k.m, k.s, r, "CPU", true);
        std::fprintf(stderr, "error: slab: interrupted: %s holds %llu of %llu paths (partial)\n",
                     a.out.c_str(), static_cast<unsigned long long>(r.paths),
                     static_cast<unsigned long long>(k.s.paths));
        return kInterrupted;
    }
    return writeSlabCsv(a.out, k.m, k.s, r, "CPU");
}

int runSlabGpuCli(const std::filesystem::path& root, const SlabArgs& a) {
    const SlabSetup k = prepare(a);
    checkWritable(a.out, "--out");
    if (!a.shard.empty())
        throw core::Error("--shard", 0, "shards run on the CPU tracer (leave out --gpu)");
    auto ctx = gl::createHeadlessContext(false);
    pathtrace::GpuSlabTracer tracer(root / "shaders" / "pathtrace_slab.comp");
    tracer.reset(k.m, k.s);
    core::Stopwatch clock;
    auto progress = progressLine(k.s, clock);
    while (!tracer.finished())
        progress(tracer.step(pathtrace::GpuSlabTracer::kMaxPathsPerRound));
    core::progressEnd();
    pathtrace::SlabResult r = pathtrace::finalize(tracer.tally(), k.s);
    r.seconds = tracer.seconds();
    pathtrace::SlabSettings traced = k.s;
    traced.splitting.levels = 0; // the GL tracer does not split (same expectation)
    traced.exits.samples = 0;    // and tallies the actual exits
    return writeSlabCsv(a.out, k.m, traced, r, std::string("GPU (") + ctx->renderer() + ")");
}

Command slabCommand() {
    return {"slab", "path-traced pencil beam on a semi-infinite slab: R_d(r) with standard errors",
            false, [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<SlabArgs>();
                addSlabOptions(&cmd, *a);
                return [a](CommandContext& ctx) {
                    return a->gpu ? runSlabGpuCli(ctx.root(), *a) : runSlabCli(*a);
                };
            }};
}

} // namespace app
