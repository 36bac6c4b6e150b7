// `bssrdf-workbench fit`: a model's declared parameters fitted to the path-traced reference
// (pipeline/fitting.h), with uncertainties from refitting on two independent half references.
// Outputs in --out: fit.json (schema "bssrdf-workbench-fit", version 1), report.md with the
// profiles before and after against the reference (plots/, as `compare` draws them) and the
// model file with the fitted values as its defaults (<stem>_fit.bssrdf, loadable like any model).
#include "cli/fit_command.h"
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

std::vector<FitTarget> makeTargets(const std::vector<FitMedium>& media,
                                   const std::vector<double>& thetaI, uint64_t paths, uint64_t seed,
                                   const std::string& what) {
    std::vector<FitTarget> targets;
    for (const FitMedium& medium : media) {
        const material::MaterialParams& eff = medium.params;
        for (int c : medium.channels) {
            const std::string name = medium.name + " " + "RGB"[c];
            const pathtrace::Medium m{eff.sigmaA[c], eff.sigmaS[c], eff.g, eff.eta};
            const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
            if (!(std::isfinite(ld) && ld > 0))
                throw core::Error("--presets", 0,
                                  name + ": sigma_a = 0, no diffuse mean free path to fit over "
                                         "(leave the channel out with --channels)");
            for (double theta : thetaI) {
                FitTarget t;
                t.preset = medium.name;
                t.channel = c;
                t.ldMm = ld;
                t.params = eff;
                t.thetaI = theta;
                bool cached = false;
                if (theta > 0) { // the whole BSSRDF on compare's oblique bins
                    pathtrace::EstimateSettings es = obliqueSettings(ld, theta, paths);
                    es.seed = seed;
                    t.bins = es.bins;
                    t.slice = obliqueReference(
                        m, es, name + " at " + core::formatNumber(theta, 3) + " deg" + what,
                        cached);
                    targets.push_back(std::move(t));
                    continue;
                }
                pathtrace::SlabSettings ss = scoringSlabSettings(ld, paths);
                ss.seed = seed;
                const pathtrace::SlabResult ref =
                    slabReference(m, ss, "fit: reference " + name + what, cached);
                t.edges = binEdges(ref.rMid);
                for (size_t i = 0; i < ref.rd.size(); ++i) {
                    t.ref.push_back(ref.rd[i] / (1 - ref.specular));
                    t.refSe.push_back(ref.rdStderr[i] / (1 - ref.specular));
                }
                t.refBatches = ref.rdBatches.scaled(1 / (1 - ref.specular)); // as ref
                t.totalRd = ref.totalRd / (1 - ref.specular);
                t.totalRdSe = ref.totalRdStderr / (1 - ref.specular);
                targets.push_back(std::move(t));
            }
        }
    }
    return targets;
}

std::function<void(int, double)> fitProgress(const std::string& what) {
    auto clock = std::make_shared<core::Stopwatch>();
    auto last = std::make_shared<double>(-1e9);
    return [what, clock, last](int n, double best) {
        if (clock->ms() - *last < 250) return;
        *last = clock->ms();
        core::progress("fit%s: %d evaluations, best mean rel_err^2 %s", what.c_str(), n,
                       core::formatNumber(best, 4).c_str());
    };
}

namespace {
// Ends the fit's progress line with where the fit ended: the last line drawn (at most four a
// second) may be from before its last evaluations.
void endFitProgress(const std::string& what, const SearchResult& r) {
    core::progress("fit%s: %d evaluations, best mean rel_err^2 %s", what.c_str(), r.evaluations,
                   core::formatNumber(r.bestObjective, 4).c_str());
    core::progressEnd();
}
} // namespace

FitOutcome fitWithUncertainty(const bssrdf::ModelEntry& e, const std::vector<FitVariable>& vars,
                              const std::vector<FitMedium>& media, const FitArgs& a,
                              const FitSettings& s, const std::string& what) {
    const std::atomic<bool>* cancel = interruptFlag();
    FitOutcome out;
    out.targets = makeTargets(media, a.thetaI, a.paths, 1, what);
    out.result = fitModel(e, vars, out.targets, s, fitProgress(what), cancel);
    endFitProgress(what, out.result);
    out.sigma.assign(vars.size(), std::nan(""));
    if (!a.uncertainty || interrupted()) return out;
    const std::vector<FitTarget> halfA =
        makeTargets(media, a.thetaI, a.paths / 2, 2, what + " (half A)");
    const std::vector<FitTarget> halfB =
        makeTargets(media, a.thetaI, a.paths / 2, 3, what + " (half B)");
    const FitResult ra = fitModel(e, vars, halfA, s, fitProgress(what + " (half A)"), cancel);
    endFitProgress(what + " (half A)", ra);
    const FitResult rb = fitModel(e, vars, halfB, s, fitProgress(what + " (half B)"), cancel);
    endFitProgress(what + " (half B)", rb);
    for (size_t i = 0; i < vars.size(); ++i) {
        const double stat = std::abs(ra.best[i] - rb.best[i]) / 2;
        const double bias = out.result.best[i] - (ra.best[i] + rb.best[i]) / 2;
        out.sigma[i] = std::hypot(stat, bias);
    }
    out.halfA = ra.best;
    out.halfB = rb.best;
    return out;
}

namespace {

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
    bssrdf::ModelEntry* e = wb.library().entries().empty() ? nullptr : &wb.library().entries()[0];
    if (!e) throw core::Error("--model", 0, "no model loaded");
    if (e->problem) throw core::Error(e->problem->file, e->problem->line, e->problem->message);
    setParameters(*e->model, a.set, e->values);
    const std::vector<FitVariable> vars = fitVariables(*e->model, a.params);
    FitSettings settings;
    settings.maxEvaluations = a.maxEvaluations;
    settings.xtolRel = a.xtolRel;
    if (!a.albedoSweep.empty()) {
        FitArgs sweep = a; // published curves, like models, are also looked up in the project
        for (std::string& p : sweep.published)
            if (!fs::exists(p) && fs::exists(root / p)) p = (root / p).string();
        return runFitSweep(*e, vars, sweep, settings);
    }

    std::vector<FitMedium> media;
    for (const std::string& p : a.presets) {
        if (!material::findPreset(wb.presets(), p))
            throw core::Error("--presets", 0, material::unknownPresetMessage(wb.presets(), p));
        MaterialSettings s;
        wb.applyPreset(s, p);
        FitMedium m{p, effectiveParams(*e, s), {}};
        for (const std::string& ch : a.channels)
            m.channels.push_back(ch == "R" ? 0 : ch == "G" ? 1 : 2);
        media.push_back(std::move(m));
    }
    const FitOutcome outcome = fitWithUncertainty(*e, vars, media, a, settings, "");
    const FitResult& r = outcome.result;
    const std::vector<double>& sigma = outcome.sigma;
    const std::vector<FitTarget>& targets = outcome.targets;
    const std::string uncertaintyNote =
        a.uncertainty
            ? std::string(kUncertaintyNote) + ", " + std::to_string(a.paths / 2) + " paths each"
            : "not computed (--no-uncertainty)";

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
        j["parameters"].push_back(
            {{"name", vars[i].label},
             {"lo", vars[i].lo},
             {"hi", vars[i].hi},
             {"start", r.start[i]},
             {"fitted", r.best[i]},
             {"sigma", std::isfinite(sigma[i]) ? json(sigma[i]) : json()},
             {"halves",
              outcome.halfA.empty() ? json() : json::array({outcome.halfA[i], outcome.halfB[i]})}});
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
                cmd.add_option("--set", a->set,
                               "fixed parameter values: NAME=V or NAME=R,G,B (e.g. "
                               "Configuration=3)");
                auto* presets =
                    cmd.add_option("--presets", a->presets, "presets to fit over (default Marble)");
                auto* channels =
                    cmd.add_option("--channels", a->channels, "channels R G B (default all)")
                        ->delimiter(',');
                auto* sweep =
                    cmd.add_option("--albedo-sweep", a->albedoSweep,
                                   "fit at each reduced albedo a' in (0, 1) of a medium with "
                                   "sigma'_t = 1/mm instead of presets: A[,A...]; writes the "
                                   "fitted values as a table over albedo (sweep.csv)")
                        ->delimiter(',')
                        ->excludes(presets)
                        ->excludes(channels);
                addNumberOption(&cmd, "--eta", a->sweepEta,
                                "the sweep's relative index of refraction (default " +
                                    core::formatNumber(a->sweepEta) + ")",
                                core::Limits{1.0, 3.0})
                    ->needs(sweep);
                addNumberOption(&cmd, "--g", a->sweepG,
                                "the sweep's Henyey-Greenstein g (default " +
                                    core::formatNumber(a->sweepG) + ")",
                                core::Limits{-0.95, 0.95})
                    ->needs(sweep);
                cmd.add_option("--published", a->published,
                               "CSV of a published curve to draw beside the sweep's fitted "
                               "values: a header 'A,PARAM' then rows of A and the value")
                    ->needs(sweep);
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
