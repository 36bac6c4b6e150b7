// `bssrdf-workbench fit`: a model's declared parameters fitted to the path-traced reference
// (pipeline/fitting.h), with uncertainties from refitting on two independent half references.
// Outputs in --out: fit.json (schema "bssrdf-workbench-fit", version 1), report.md with the
// profiles before and after against the reference (plots/, as `compare` draws them) and the
// model file with the fitted values as its defaults (<stem>_fit.bssrdf, loadable like any model).
#include "cli/args.h"
#include "cli/command.h"
#include "cli/compare_command.h"
#include "cli/interrupt.h"
#include "cli/options.h"
#include "cli/output.h"

#include "common/exit_codes.h"
#include "core/core.h"
#include "core/relative_error.h"
#include "core/text.h"
#include "gl/gl.h"
#include "material/material.h"
#include "pipeline/fitting.h"
#include "pipeline/model_stages.h"
#include "pipeline/scoring.h"
#include "pipeline/scoring_oblique.h"
#include "pipeline/workbench.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct FitArgs {
    std::string model, out;
    std::vector<std::string> params, presets{"Marble"}, channels{"R", "G", "B"};
    std::vector<double> thetaI{0.0}; // 0: the radial profile; > 0: the whole BSSRDF's slice
    uint64_t paths = 1000000;
    int maxEvaluations = FitSettings{}.maxEvaluations;
    double xtolRel = FitSettings{}.xtolRel;
    bool uncertainty = true;
    bool plots = true; // before/after pictures in the report
};

// The targets of every preset × channel against references of `paths` paths with `seed`.
std::vector<FitTarget> makeTargets(Workbench& wb, const bssrdf::ModelEntry& e, const FitArgs& a,
                                   uint64_t paths, uint64_t seed, const std::string& what) {
    std::vector<FitTarget> targets;
    for (const std::string& preset : a.presets) {
        MaterialSettings s;
        wb.applyPreset(s, preset);
        const material::MaterialParams eff = effectiveParams(e, s);
        for (const std::string& ch : a.channels) {
            const int c = ch == "R" ? 0 : ch == "G" ? 1 : 2;
            const pathtrace::Medium m{eff.sigmaA[c], eff.sigmaS[c], eff.g, eff.eta};
            const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
            if (!(std::isfinite(ld) && ld > 0))
                throw core::Error("--presets", 0,
                                  preset + " " + ch +
                                      ": sigma_a = 0, no diffuse mean free path to fit over "
                                      "(leave the channel out with --channels)");
            for (double theta : a.thetaI) {
                FitTarget t;
                t.preset = preset;
                t.channel = c;
                t.ldMm = ld;
                t.params = eff;
                t.thetaI = theta;
                bool cached = false;
                if (theta > 0) { // the whole BSSRDF on compare's oblique bins
                    pathtrace::EstimateSettings es = obliqueSettings(ld, theta, paths);
                    es.seed = seed;
                    t.bins = es.bins;
                    t.slice = obliqueReference(m, es,
                                               preset + " " + ch + " at " +
                                                   core::formatNumber(theta, 3) + " deg" + what,
                                               cached);
                    targets.push_back(std::move(t));
                    continue;
                }
                pathtrace::SlabSettings ss = scoringSlabSettings(ld, paths);
                ss.seed = seed;
                const pathtrace::SlabResult ref =
                    slabReference(m, ss, "fit: reference " + preset + " " + ch + what, cached);
                t.edges = binEdges(ref.rMid);
                for (size_t i = 0; i < ref.rd.size(); ++i) {
                    t.ref.push_back(ref.rd[i] / (1 - ref.specular));
                    t.refSe.push_back(ref.rdStderr[i] / (1 - ref.specular));
                }
                targets.push_back(std::move(t));
            }
        }
    }
    return targets;
}

std::string pct(double v) {
    return std::isfinite(v) ? core::formatNumber(100 * v, 3) + " %" : std::string("-");
}

int runFit(const fs::path& root, const FitArgs& a) {
    if (a.out.empty()) throw core::Error("--out", 0, "give the folder to write");
    for (const std::string& ch : a.channels)
        if (ch != "R" && ch != "G" && ch != "B")
            throw core::Error("--channels", 0, "'" + ch + "' is not a channel (R, G or B)");
    if (a.channels.empty()) throw core::Error("--channels", 0, "give at least one channel");
    if (a.presets.empty()) throw core::Error("--presets", 0, "give at least one preset");
    if (a.thetaI.empty()) throw core::Error("--theta-i", 0, "give at least one angle");
    for (double t : a.thetaI)
        if (!(std::isfinite(t) && t >= 0 && t < 90))
            throw core::Error("--theta-i", 0,
                              "incidence angles must be degrees in [0, 90), got " +
                                  core::formatNumber(t, 6));
    std::error_code ec;
    fs::create_directories(a.out, ec);
    if (ec || !fs::is_directory(a.out))
        throw core::Error("--out", 0, "cannot create the folder '" + a.out + "'");
    checkWritable((fs::path(a.out) / "fit.json").string(), "--out");

    auto ctx = gl::createHeadlessContext(false);
    const fs::path file = resolveModel(root, a.model);
    Workbench wb(root, false, {file});
    const bssrdf::ModelEntry* e =
        wb.library().entries().empty() ? nullptr : &wb.library().entries()[0];
    if (!e) throw core::Error("--model", 0, "no model loaded");
    if (e->problem) throw core::Error(e->problem->file, e->problem->line, e->problem->message);
    for (const std::string& p : a.presets)
        if (!material::findPreset(wb.presets(), p))
            throw core::Error("--presets", 0, material::unknownPresetMessage(wb.presets(), p));
    const std::vector<FitVariable> vars = fitVariables(*e->model, a.params);

    FitSettings fs;
    fs.maxEvaluations = a.maxEvaluations;
    fs.xtolRel = a.xtolRel;
    const std::atomic<bool>* cancel = interruptFlag();
    // one progress line, rewritten at most four times a second
    auto progress = [](const char* what) {
        auto clock = std::make_shared<core::Stopwatch>();
        auto last = std::make_shared<double>(-1e9);
        return [what, clock, last](int n, double best) {
            if (clock->ms() - *last < 250) return;
            *last = clock->ms();
            std::fprintf(stderr, "\rfit%s: %d evaluations, best mean rel_err^2 %s   ", what, n,
                         core::formatNumber(best, 4).c_str());
            std::fflush(stderr);
        };
    };
    const std::vector<FitTarget> targets = makeTargets(wb, *e, a, a.paths, 1, "");
    const FitResult r = fitModel(*e, vars, targets, fs, progress(""), cancel);
    std::fprintf(stderr, "\n");
    // uncertainties: refits on two independent half references (seeds 2 and 3); each half fit
    // scatters √2 times the full one, their difference 2 times: σ ≈ |x_A − x_B| / 2
    std::vector<double> sigma(vars.size(), std::nan(""));
    std::string uncertaintyNote = "not computed (--no-uncertainty)";
    if (a.uncertainty && !interrupted()) {
        const std::vector<FitTarget> halfA = makeTargets(wb, *e, a, a.paths / 2, 2, " (half A)");
        const std::vector<FitTarget> halfB = makeTargets(wb, *e, a, a.paths / 2, 3, " (half B)");
        const FitResult ra = fitModel(*e, vars, halfA, fs, progress(" (half A)"), cancel);
        std::fprintf(stderr, "\n");
        const FitResult rb = fitModel(*e, vars, halfB, fs, progress(" (half B)"), cancel);
        std::fprintf(stderr, "\n");
        for (size_t i = 0; i < vars.size(); ++i)
            sigma[i] = std::abs(ra.best[i] - rb.best[i]) / 2;
        uncertaintyNote = "|x_A - x_B| / 2 from fits to two independent references of " +
                          std::to_string(a.paths / 2) + " paths (seeds 2 and 3)";
    }

    json j = {{"schema", "bssrdf-workbench-fit"},
              {"version", 1},
              {"model", e->displayPath},
              {"objective", "mean over the targets of rel_err^2 (modules/core/relative_error.h)"},
              {"optimizer", "NLopt BOBYQA"},
              {"paths", a.paths},
              {"evaluations", r.evaluations},
              {"status", r.status},
              {"converged", r.converged},
              {"objective_start", r.startObjective},
              {"objective_fitted", r.bestObjective},
              {"uncertainty", uncertaintyNote},
              {"problems", r.problems},
              {"parameters", json::array()},
              {"targets", json::array()}};
    for (size_t i = 0; i < vars.size(); ++i)
        j["parameters"].push_back({{"name", vars[i].label},
                                   {"lo", vars[i].lo},
                                   {"hi", vars[i].hi},
                                   {"start", r.start[i]},
                                   {"fitted", r.best[i]},
                                   {"sigma", std::isfinite(sigma[i]) ? json(sigma[i]) : json()}});
    for (size_t t = 0; t < targets.size(); ++t)
        j["targets"].push_back({{"preset", targets[t].preset},
                                {"channel", std::string(1, "RGB"[targets[t].channel])},
                                {"theta_i", targets[t].thetaI},
                                {"ld_mm", targets[t].ldMm},
                                {"rel_err_start", r.relErrStart[t]},
                                {"rel_err_fitted", r.relErrBest[t]}});
    core::writeFile(fs::path(a.out) / "fit.json", j.dump(2) + "\n");

    bssrdf::ParamValues fitted = e->values;
    applyFit(vars, r.best, fitted);
    const std::string stem = fs::path(e->displayPath).stem().string();
    const fs::path modelOut = fs::path(a.out) / (stem + "_fit.bssrdf");
    core::writeFile(modelOut, withDefaults(*e->model, fitted,
                                           "defaults fitted by `bssrdf-workbench fit` to the "
                                           "path-traced reference (fit.json beside this file)"));

    std::ostringstream md;
    md << "# Fit of " << e->displayPath << "\n\n"
       << "Free parameters fitted to the path-traced slab reference (" << a.paths
       << " paths per preset and channel) by NLopt's BOBYQA, minimising the mean rel_err² over "
          "the targets. "
       << r.evaluations << " evaluations: " << r.status << ". Uncertainty: " << uncertaintyNote
       << ".\n\n| parameter | range | start | fitted | ± |\n|---|---|---|---|---|\n";
    for (size_t i = 0; i < vars.size(); ++i)
        md << "| " << vars[i].label << " | [" << core::formatNumber(vars[i].lo, 4) << ", "
           << core::formatNumber(vars[i].hi, 4) << "] | " << core::formatNumber(r.start[i], 5)
           << " | " << core::formatNumber(r.best[i], 5) << " | "
           << (std::isfinite(sigma[i]) ? core::formatNumber(sigma[i], 2) : "—") << " |\n";
    md << "\n| preset | ch | θi | l_d (mm) | rel_err before | rel_err after |\n"
          "|---|---|---|---|---|---|\n";
    for (size_t t = 0; t < targets.size(); ++t)
        md << "| " << targets[t].preset << " | "
           << "RGB"[targets[t].channel] << " | " << core::formatNumber(targets[t].thetaI, 3)
           << " | " << core::formatNumber(targets[t].ldMm, 4) << " | " << pct(r.relErrStart[t])
           << " | " << pct(r.relErrBest[t]) << " |\n";
    // before and after against the reference, per radial target (the pencil plot's drawing)
    if (a.plots) {
        bssrdf::ParamValues startValues = e->values;
        applyFit(vars, r.start, startValues);
        for (const FitTarget& t : targets) {
            if (t.thetaI > 0) continue;
            ProfileCurves curves{t.preset, t.channel, t.ldMm, {}, t.ref, t.refSe, {}};
            for (size_t i = 0; i + 1 < t.edges.size(); ++i)
                curves.r.push_back(0.5 * (t.edges[i] + t.edges[i + 1]));
            FitTarget atStart = t, atBest = t; // with the medium the model was evaluated with
            applyMedium(vars, r.start, t.params, atStart.params);
            applyMedium(vars, r.best, t.params, atBest.params);
            const std::vector<double> before = modelOnTarget(*e, startValues, atStart);
            const std::vector<double> after = modelOnTarget(*e, fitted, atBest);
            if (before.empty() || after.empty()) continue;
            curves.models = {{stem + " start", before}, {stem + " fitted", after}};
            md << "\n";
            for (const auto& [file, caption] :
                 writeProfilePictures(fs::path(a.out) / "plots", curves))
                md << "![" << caption << "](plots/" << file << ")\n";
        }
    }
    if (!r.problems.empty()) {
        md << "\nWhere the model was not finite during the search:\n\n";
        for (const std::string& p : r.problems)
            md << "- " << p << "\n";
    }
    md << "\nThe model with the fitted values as its defaults: [" << modelOut.filename().string()
       << "](" << modelOut.filename().string() << ").\n";
    core::writeFile(fs::path(a.out) / "report.md", md.str());

    for (size_t i = 0; i < vars.size(); ++i)
        std::printf("%s = %s +- %s (start %s)\n", vars[i].label.c_str(),
                    core::formatNumber(r.best[i], 6).c_str(),
                    std::isfinite(sigma[i]) ? core::formatNumber(sigma[i], 2).c_str() : "-",
                    core::formatNumber(r.start[i], 6).c_str());
    for (size_t t = 0; t < targets.size(); ++t)
        std::printf("%s %c%s: rel_err %s -> %s\n", targets[t].preset.c_str(),
                    "RGB"[targets[t].channel],
                    targets[t].thetaI > 0
                        ? (" at " + core::formatNumber(targets[t].thetaI, 3) + " deg").c_str()
                        : "",
                    pct(r.relErrStart[t]).c_str(), pct(r.relErrBest[t]).c_str());
    std::printf("wrote %s, %s, %s\n", (fs::path(a.out) / "fit.json").c_str(),
                (fs::path(a.out) / "report.md").c_str(), modelOut.c_str());
    for (const std::string& p : r.problems)
        core::logWarn("fit: the model is not finite at " + p);
    if (interrupted()) {
        std::fprintf(stderr, "fit: interrupted: wrote the best point so far\n");
        return kInterrupted;
    }
    if (!r.converged) {
        std::fprintf(stderr,
                     "error: the fit did not converge (%s after %d evaluations; the best point "
                     "so far is written): raise --max-evaluations or narrow the ranges\n",
                     r.status.c_str(), r.evaluations);
        return kNotConverged;
    }
    return 0;
}

} // namespace

Command fitCommand() {
    return {"fit", "fit a model's parameters to the path-traced reference", false,
            [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<FitArgs>();
                cmd.add_option("--model", a->model, "the model file")->required();
                cmd.add_option("--params", a->params,
                               "parameters to fit: NAME (its declared range) or NAME=LO,HI; also "
                               "the medium's medium.sigma_scale (sigma_a and sigma_s times it, "
                               "[0.1, 10]) and medium.g ([-0.95, 0.95])")
                    ->required();
                cmd.add_option("--presets", a->presets, "presets to fit over (default Marble)");
                cmd.add_option("--channels", a->channels, "channels R G B (default all)")
                    ->delimiter(',');
                cmd.add_option("--theta-i", a->thetaI,
                               "incidence angles in degrees, [0, 90): DEG[,DEG...]; 0 fits the "
                               "radial profile, others the whole BSSRDF over the plane (default 0)")
                    ->delimiter(',');
                addCountOption(&cmd, "--paths", a->paths,
                               "reference paths per preset and channel (default " +
                                   std::to_string(a->paths) + ")",
                               core::Limits{1000, 1e12});
                cmd.add_option("--max-evaluations", a->maxEvaluations,
                               "evaluation budget of the optimizer (default " +
                                   std::to_string(a->maxEvaluations) + ")")
                    ->check(CLI::Range(1, 1000000));
                addNumberOption(&cmd, "--xtol", a->xtolRel,
                                "relative parameter tolerance of convergence (default " +
                                    core::formatNumber(a->xtolRel) + ")",
                                core::Limits{1e-12, 1});
                cmd.add_flag("!--no-uncertainty", a->uncertainty,
                             "skip the refits on two half references");
                cmd.add_flag("!--no-plots", a->plots, "the report without its PNG plots");
                cmd.add_option("--out", a->out, "output folder: fit.json, report.md, the model")
                    ->required();
                return [a](CommandContext& ctx) { return runFit(ctx.root(), *a); };
            }};
}

} // namespace app
