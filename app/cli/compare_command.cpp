// `bssrdf-workbench compare`: the scoreboard (pipeline/scoring.h has the definitions of every
// number).
#include "cli/compare_command.h"
#include "cli/args.h"
#include "cli/command.h"
#include "cli/compare_geometry.h"
#include "cli/options.h"
#include "pathtrace/mco.h"

#include "capture/scores.h"
#include "cli/capture_commands.h"
#include "cli/output.h"
#include "core/core.h"
#include "core/fields.h"
#include "core/relative_error.h"
#include "core/text.h"
#include "gl/gl.h"
#include "material/material.h"
#include "mesh/suite.h"
#include "pathtrace/pathtrace.h"
#include "pipeline/model_stages.h"
#include "pipeline/scoring_oblique.h"
#include "pipeline/workbench.h"

#include <memory>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <numbers>
#include <sstream>

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kSchema = capture::kScoresSchema;
constexpr int kSchemaVersion = capture::kScoresVersion;

} // namespace

json scoreRowJson(const ScoreRow& r) {
    return {{"model", r.model},
            {"preset", r.preset},
            {"channel", r.channel},
            {"theta_i", r.thetaI},
            {"ld_mm", r.ldMm},
            {"rel_err", r.relErr},
            {"rel_err_se", r.relErrSe},
            {"ratio_1ld", r.ratio1},
            {"ratio_1ld_se", r.ratio1Se},
            {"ratio_4ld", r.ratio4},
            {"ratio_4ld_se", r.ratio4Se},
            {"total_ratio", r.totalRatio},
            {"total_ratio_se", r.totalRatioSe},
            {"r_err5_ld", r.rErr5Ld ? json(*r.rErr5Ld) : json(nullptr)},
            {"rel_err_dir", r.relErrDir ? json(*r.relErrDir) : json(nullptr)},
            {"rel_err_dir_se", r.relErrDirSe ? json(*r.relErrDirSe) : json(nullptr)},
            {"rank", r.rank},
            {"tie", r.tie}};
}

int runCompareCli(const fs::path& root, const CompareArgs& a) {
    if (a.out.empty()) throw core::Error("--out", 0, "give the folder to write");
    if (a.failIfWorse && a.baseline.empty())
        throw core::Error("--fail-if-worse", 0, "needs --baseline FILE");
    if (a.failIfWorse && !(*a.failIfWorse >= 0))
        throw core::Error("--fail-if-worse", 0, "must be a percentage >= 0");
    size_t shardK = 0, shardN = 1;
    if (!a.shard.empty()) {
        if (!a.mco.empty()) throw core::Error("--shard", 0, "an MCML run is one unit: no shards");
        if (!a.baseline.empty())
            throw core::Error("--baseline", 0, "compare the merged run (leave out --shard)");
        const auto [k, n] = parseShard(a.shard, "--shard");
        shardK = size_t(k);
        shardN = size_t(n);
    }
    for (double t : a.thetaI)
        if (!(std::isfinite(t) && t >= 0 && t < 90))
            throw core::Error("--theta-i", 0,
                              "incidence angles must be degrees in [0, 90), got " + formatScore(t));
    if (a.thetaI.empty()) throw core::Error("--theta-i", 0, "give at least one angle");
    const std::vector<ScoreRow> baseline =
        a.baseline.empty() ? std::vector<ScoreRow>{} : capture::readScores(a.baseline);
    // the output folder must be writable before any work is done
    std::error_code ec;
    fs::create_directories(a.out, ec);
    if (ec || !fs::is_directory(a.out))
        throw core::Error("--out", 0,
                          "cannot create the folder '" + a.out + "'" +
                              (ec ? ": " + ec.message() : std::string()));
    checkWritable((fs::path(a.out) / "scores.json").string(), "--out");

    const std::vector<fs::path> models = modelFiles(root, a.models);

    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, models);
    for (const auto& e : wb.library().entries())
        if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    // The media scored: presets, or the one medium of the MCML runs given with --mco (their
    // R_d(r) is the reference, pathtrace/mco.h)
    std::optional<pathtrace::SlabResult> mcoReference;
    std::string mcoName;
    pathtrace::Medium mcoMedium;
    if (!a.mco.empty()) {
        if (a.mco.size() > 2)
            throw core::Error("--mco", 0, "give one MCML output, or two independent runs");
        if (!a.presets.empty())
            throw core::Error("--mco", 0, "scores the MCML run's own medium: leave out --presets");
        if (a.thetaI != std::vector<double>{0.0})
            throw core::Error("--mco", 0,
                              "an MCML run is a pencil beam at normal incidence: "
                              "leave out --theta-i");
        std::vector<pathtrace::McoFile> runs;
        for (const std::string& f : a.mco)
            runs.push_back(pathtrace::readMco(f));
        mcoMedium = pathtrace::mediumOfMco(runs[0], a.mco[0]);
        if (runs.size() == 2) {
            const pathtrace::Medium other = pathtrace::mediumOfMco(runs[1], a.mco[1]);
            if (other.sigmaA != mcoMedium.sigmaA || other.sigmaS != mcoMedium.sigmaS ||
                other.g != mcoMedium.g || other.eta != mcoMedium.eta || runs[0].dr != runs[1].dr ||
                runs[0].nr != runs[1].nr)
                throw core::Error(a.mco[1], 0,
                                  "not a run of the same input as " + a.mco[0] +
                                      " (medium or grid differ)");
        }
        mcoReference = pathtrace::slabFromMco(runs[0], runs.size() == 2 ? &runs[1] : nullptr);
        mcoName = fs::path(a.mco[0]).stem().string();
    }
    std::vector<std::string> presets = a.presets;
    if (mcoReference) presets = {mcoName};
    if (presets.empty()) // the first table's (Jensen et al. 2001: the scoreboard's media)
        for (const auto& p : wb.presets())
            if (p.table == wb.presets().front().table && p.unusable.empty())
                presets.push_back(p.name);
    for (const auto& name : presets)
        if (!mcoReference && !material::findPreset(wb.presets(), name))
            throw core::Error("--presets", 0, material::unknownPresetMessage(wb.presets(), name));

    CompareReport report;
    report.paths = a.paths;
    report.thetaI = a.thetaI;
    std::vector<ScoreRow>& rows = report.rows;
    json skipped = json::array();
    size_t cached = 0, traced = 0, units = 0;
    std::vector<size_t> unitOfRow, unitOfProfile, unitOfSlice;
    auto stem = [](const std::string& displayPath) {
        std::string m = displayPath.substr(displayPath.rfind('/') + 1);
        return m.substr(0, m.rfind('.'));
    };
    for (const std::string& preset : presets) {
        MaterialSettings s;
        if (mcoReference) {
            s.preset.clear();
            s.params.sigmaA = glm::dvec3(mcoMedium.sigmaA);
            s.params.sigmaS = glm::dvec3(mcoMedium.sigmaS);
            s.params.g = mcoMedium.g;
            s.params.eta = mcoMedium.eta;
        } else {
            wb.applyPreset(s, preset);
        }
        const material::MaterialParams& p = s.params;
        for (int c = 0; c < (mcoReference ? 1 : 3); ++c) {
            const std::string ch(1, "RGB"[c]);
            const pathtrace::Medium m{p.sigmaA[c], p.sigmaS[c], p.g, p.eta};
            const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
            if (!(std::isfinite(ld) && ld > 0)) { // σa = 0 (Spectralon): no l_d to score over
                skipped.push_back({{"preset", preset},
                                   {"channel", ch},
                                   {"reason", "sigma_a = 0: no diffuse mean free path l_d"}});
                std::fprintf(stderr, "compare: %s %c not scored (sigma_a = 0: no l_d)\n",
                             preset.c_str(), "RGB"[c]);
                continue;
            }
            for (double thetaI : a.thetaI) {
                // a unit of work: one medium and angle (--shard runs every N-th)
                const size_t unit = units++;
                if (unit % shardN != shardK) continue;
                if (thetaI == 0) {
                    const pathtrace::SlabSettings ss = scoringSlabSettings(ld, a.paths);
                    bool fromCache = false;
                    const pathtrace::SlabResult ref =
                        mcoReference
                            ? *mcoReference
                            : slabReference(m, ss, "compare: reference " + preset + " " + ch,
                                            fromCache);
                    if (!mcoReference) (fromCache ? cached : traced)++;
                    ProfileCurves curves{preset, c, ld, ref.rMid, {}, {}, {}};
                    for (size_t i = 0; i < ref.rMid.size(); ++i) {
                        curves.ref.push_back(ref.rd[i] / (1 - ref.specular));
                        curves.refSe.push_back(ref.rdStderr[i] / (1 - ref.specular));
                    }
                    const std::vector<double> edges = binEdges(ref.rMid);
                    for (auto& e : wb.library().entries()) {
                        if (!e.usable()) continue;
                        const material::MaterialParams eff = effectiveParams(e, s);
                        const bssrdf::Builtins b = builtinsOf(eff);
                        const GLuint program = e.programs.at("pencil_profile.comp").id();
                        std::string bad;
                        const bssrdf::Profile prof = binAverageProfile(program, e, b, edges, bad);
                        if (!bad.empty()) throw core::Error(e.displayPath, 0, preset + ": " + bad);
                        std::vector<double> mv = channelOf(prof, c);
                        ScoreRow row = scoreAgainstReference(
                            edges, ref.rd, ref.rdStderr, ref.specular, ref.totalRd,
                            ref.totalRdStderr, ld, mv, modelTotalRd(program, e, b, ld, c),
                            ref.rdBatches);
                        row.model = stem(e.displayPath);
                        row.preset = preset;
                        row.channel = ch;
                        rows.push_back(row);
                        unitOfRow.push_back(unit);
                        curves.models.emplace_back(row.model, std::move(mv));
                    }
                    report.profiles.push_back(std::move(curves));
                    unitOfProfile.push_back(unit);
                    continue;
                }
                const pathtrace::EstimateSettings es = obliqueSettings(ld, thetaI, a.paths);
                bool fromCache = false;
                const pathtrace::BssrdfSlice ref = obliqueReference(
                    m, es, preset + " " + ch + " at " + formatScore(thetaI, 3) + " deg", fromCache);
                (fromCache ? cached : traced)++;
                SliceMaps maps{preset, c, thetaI, ld, es.bins, ref.R, ref.RStderr, {}};
                for (auto& e : wb.library().entries()) {
                    if (!e.usable()) continue;
                    const material::MaterialParams eff = effectiveParams(e, s);
                    const bool readsWo = !e.model->attrs.noWo;
                    const SliceSampling n = sliceSampling(es.bins, readsWo);
                    const std::vector<bssrdf::Query> q = sliceQueries(es.bins, thetaI, readsWo, n);
                    const std::vector<glm::dvec3> rgb =
                        bssrdf::evaluateQueries(e.programs.at("pencil_profile.comp").id(), *e.model,
                                                e.values, builtinsOf(eff), q);
                    std::vector<double> values(rgb.size());
                    for (size_t i = 0; i < rgb.size(); ++i)
                        values[i] = rgb[i][c];
                    const ModelSlice ms = modelSlice(es.bins, thetaI, eff.eta, readsWo, n, values);
                    for (size_t i = 0; i < ms.R.size(); ++i)
                        if (!std::isfinite(ms.R[i]) || ms.R[i] < 0)
                            throw core::Error(
                                e.displayPath, 0,
                                preset +
                                    ": Bssrdf() is negative or not finite on "
                                    "the slice at theta_i " +
                                    formatScore(thetaI, 3) + " deg, r = " +
                                    formatScore(es.bins.rEdges()[i / size_t(es.bins.thetaSBins)],
                                                4) +
                                    " mm");
                    ScoreRow row = scoreSlice(es.bins, ref, ms, ld);
                    row.model = stem(e.displayPath);
                    row.preset = preset;
                    row.channel = ch;
                    rows.push_back(row);
                    unitOfRow.push_back(unit);
                    maps.models.emplace_back(row.model, ms.R);
                }
                report.slices.push_back(std::move(maps));
                unitOfSlice.push_back(unit);
            }
        }
    }
    for (const ScoreRow& r : rows) // JSON has no infinity: say what is missing instead
        if (!std::isfinite(r.relErr) || (r.relErrDir && !std::isfinite(*r.relErrDir)))
            throw core::Error("--paths", 0,
                              r.preset + " " + r.channel + " at " + formatScore(r.thetaI, 3) +
                                  " deg: the reference has a bin without paths in [0.1, 4] l_d "
                                  "(give more --paths)");
    std::fprintf(stderr, "%zu references traced, %zu from the cache\n", traced, cached);
    CompareRun run{report, skipped, unitOfRow, unitOfProfile, unitOfSlice, units, presets, {}};
    for (const auto& e : wb.library().entries())
        run.models.push_back(stem(e.displayPath));
    if (!a.shard.empty()) {
        writeCompareShard(a.out, run, shardK + 1, shardN);
        return 0;
    }
    return finishCompare(a.out, run.report, run.skipped, a.plots, baseline, a.failIfWorse);
}

int finishCompare(const fs::path& out, CompareReport& report, const json& skipped, bool plots,
                  const std::vector<ScoreRow>& baseline, std::optional<double> failIfWorse) {
    std::vector<ScoreRow>& rows = report.rows;
    rankRows(rows);
    json angles = json::array();
    for (double t : report.thetaI)
        angles.push_back(t);
    json j = {{"schema", kSchema},
              {"version", kSchemaVersion},
              {"theta_i", angles},
              {"paths", report.paths},
              {"rel_err", "RMS relative error over ln r in [0.1, 4] l_d, the reference's noise "
                          "removed (modules/core/relative_error.h)"},
              {"rel_err_range_ld", {core::kRelErrFromLd, core::kRelErrToLd}},
              {"rows", json::array()},
              {"skipped", skipped}};
    for (const ScoreRow& r : rows)
        j["rows"].push_back(scoreRowJson(r));
    writeReports(out, report, plots);
    core::writeFile(out / "scores.json", j.dump(2) + "\n");
    std::fputs(modelSummaryText(rows).c_str(), stdout);
    std::printf("%zu rows: %s; reports: %s, %s\n", rows.size(), (out / "scores.json").c_str(),
                (out / "report.md").c_str(), (out / "report.html").c_str());

    if (!failIfWorse) return 0;
    int worse = 0;
    for (const ScoreRow& r : rows)
        for (const ScoreRow& b : baseline) {
            if (b.model != r.model || b.preset != r.preset || b.channel != r.channel ||
                b.thetaI != r.thetaI)
                continue;
            const double noise = 3 * std::sqrt(r.relErrSe * r.relErrSe + b.relErrSe * b.relErrSe);
            if (r.relErr > b.relErr * (1 + *failIfWorse / 100) && r.relErr - b.relErr > noise) {
                std::fprintf(stderr, "worse: %s %s %s rel_err %s -> %s\n", r.model.c_str(),
                             r.preset.c_str(), r.channel.c_str(), formatScore(b.relErr).c_str(),
                             formatScore(r.relErr).c_str());
                ++worse;
            }
        }
    if (worse) {
        std::fprintf(stderr, "error: %d rows worse than the baseline by more than %s %%\n", worse,
                     formatScore(*failIfWorse).c_str());
        return 1;
    }
    return 0;
}

namespace {

void addGeometryOptions(CLI::App& cmd, bool& geometry, GeometryArgs& g) {
    const GeometrySettings d;
    CLI::Option* geo =
        cmd.add_flag("--geometry", geometry,
                     "score images of the geometry suite's shapes against the volumetric path "
                     "tracer instead of radial profiles (default presets Marble and Skin1)");
    std::string kinds;
    for (const mesh::SuiteKind& k : mesh::suiteKinds()) {
        kinds += std::string(kinds.empty() ? "" : "; ") + k.name + " (";
        for (size_t i = 0; i < k.params.size(); ++i)
            kinds += std::string(i ? ", " : "") + k.params[i].name;
        kinds += std::string(k.name) == "slab" ? ", view)" : ")";
    }
    cmd.add_option("--shapes", g.shapes,
                   "--geometry: shape specs KIND[:NAME=VALUE,...] in units of l_d, e.g. "
                   "slab:t=0.3,view=back sphere:r=2; kinds: " +
                       kinds + " (default: the whole suite, " +
                       std::to_string(mesh::defaultSuite().size()) + " shapes)")
        ->needs(geo);
    addCountOption(&cmd, "--size", g.settings.size,
                   "--geometry: image side in pixels (default " + std::to_string(d.size) + ")",
                   core::Limits{8, 1024})
        ->needs(geo);
    addCountOption(&cmd, "--reference-spp", g.settings.referenceSpp,
                   "--geometry: reference paths per covered pixel, x3 estimates (default " +
                       std::to_string(d.referenceSpp) + ")",
                   core::Limits{1, 1e6})
        ->needs(geo);
    addCountOption(&cmd, "--model-spp", g.settings.modelSpp,
                   "--geometry: BSSRDF samples per pixel (default " + std::to_string(d.modelSpp) +
                       ")",
                   core::Limits{1, 1e6})
        ->needs(geo);
    cmd.add_option("--sampling", g.sampling,
                   std::string("--geometry: BSSRDF integration, uniform or disk (default ") +
                       core::nameOf(d.sampling) + ")")
        ->needs(geo);
    cmd.add_option("--pictures", g.pictures,
                   "--geometry: the channels whose cases get a picture in the report, e.g. G "
                   "(default RGB; --no-plots: none)")
        ->needs(geo);
    cmd.add_option("--shard", g.shard,
                   "run shard K of N (1 <= K <= N): every N-th medium and angle (--geometry: "
                   "case) from the K-th, into DIR/shard.json; `merge DIR... --out D` combines "
                   "them");
}

} // namespace

Command compareCommand() {
    return {"compare", "score every model against the path-traced reference (scoreboard)", false,
            [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<CompareArgs>();
                auto g = std::make_shared<GeometryArgs>();
                auto geometry = std::make_shared<bool>(false);
                cmd.add_option("--models", a->models,
                               "model files (default: every materials/*.bssrdf)");
                cmd.add_option("--presets", a->presets,
                               "preset names (default: the Jensen et al. 2001 table's)");
                cmd.add_option("--mco", a->mco,
                               "score against MCML output instead of presets: FILE.mco, or two "
                               "independent runs for per-bin standard errors (one semi-infinite "
                               "layer)");
                addCountOption(&cmd, "--paths", a->paths,
                               "reference paths per preset and channel (default " +
                                   std::to_string(a->paths) + ")",
                               core::Limits{1000, 1e12});
                cmd.add_option(
                       "--theta-i", a->thetaI,
                       "incidence angles in degrees, [0, 90): DEG[,DEG...]; 0 scores the radial "
                       "profile, others the whole BSSRDF (default 0)")
                    ->delimiter(',');
                cmd.add_flag("!--no-plots", a->plots, "reports without the PNG plots");
                cmd.add_option("--baseline", a->baseline, "an earlier scores.json to compare with");
                addNumberOption(&cmd, "--fail-if-worse", a->failIfWorse,
                                "with --baseline: exit 1 when a rel_err grew by more than PCT %",
                                core::Limits{0, 1e6});
                cmd.add_option("--out", a->out,
                               "output folder: scores.json, report.md, report.html")
                    ->required();
                addGeometryOptions(cmd, *geometry, *g);
                // the radial scoreboard's options, which the geometry suite would ignore
                const auto suite = [geometry] { return *geometry; };
                refuseIgnoredOptions(
                    &cmd,
                    {{{"--mco"}, suite, "an MCML run scores radial profiles: leave out --geometry"},
                     {{"--paths"},
                      suite,
                      "the geometry suite's reference takes --reference-spp: leave out "
                      "--paths"},
                     {{"--theta-i"},
                      suite,
                      "the geometry suite has its own lights: leave out --theta-i"}});
                return [a, g, geometry](CommandContext& ctx) {
                    if (!*geometry) {
                        a->shard = g->shard;
                        return runCompareCli(ctx.root(), *a);
                    }
                    g->models = a->models;
                    g->presets = a->presets;
                    g->plots = a->plots;
                    g->baseline = a->baseline;
                    g->failIfWorse = a->failIfWorse;
                    g->out = a->out;
                    return runCompareGeometryCli(ctx.root(), *g);
                };
            }};
}

} // namespace app
