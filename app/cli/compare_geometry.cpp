// `bssrdf-workbench compare --geometry` and `merge --geometry` (compare_geometry.h).
#include "cli/compare_geometry.h"
#include "cli/args.h"
#include "cli/interrupt.h"
#include "cli/output.h"

#include "core/core.h"
#include "core/text.h"
#include "gl/gl.h"
#include "mesh/suite.h"
#include "pipeline/geometry_images.h"
#include "pipeline/scoring.h"
#include "pipeline/workbench.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kGeometrySchema = "bssrdf-workbench-geometry-scores";
constexpr const char* kShardSchema = "bssrdf-workbench-geometry-shard";
constexpr int kGeometryVersion = 1;

json numberOrNull(double v, bool valid) {
    return valid && std::isfinite(v) ? json(v) : json();
}

json settingsJson(const GeometrySettings& s) {
    return {{"size", s.size},
            {"reference_spp", s.referenceSpp},
            {"model_spp", s.modelSpp},
            {"sampling", core::nameOf(s.sampling)},
            {"seed", s.seed}};
}

json rowJson(const GeometryRow& r, size_t caseIndex) {
    const bool ok = r.score.problem.empty();
    return {{"case", caseIndex},
            {"model", r.model},
            {"shape", r.shape},
            {"preset", r.preset},
            {"channel", r.channel},
            {"ld_mm", r.ldMm},
            {"radius_mm", r.radiusMm},
            {"rel_l2", numberOrNull(r.score.relL2, ok)},
            {"rel_l2_se", numberOrNull(r.score.relL2Se, ok)},
            {"mean_ratio", numberOrNull(r.score.meanRatio, ok)},
            {"mean_ratio_se", numberOrNull(r.score.meanRatioSe, ok)},
            {"pixels", r.score.pixels},
            {"rank", r.rank},
            {"tie", r.tie},
            {"problem", ok ? json() : json(r.score.problem)}};
}

double numberIn(const json& j, const char* key) {
    return j.at(key).is_null() ? std::nan("") : j.at(key).get<double>();
}

GeometryRow rowOf(const json& j) {
    GeometryRow r;
    r.model = j.at("model").get<std::string>();
    r.shape = j.at("shape").get<std::string>();
    r.preset = j.at("preset").get<std::string>();
    r.channel = j.at("channel").get<std::string>();
    r.ldMm = j.at("ld_mm").get<double>();
    r.radiusMm = j.at("radius_mm").get<double>();
    r.score.relL2 = numberIn(j, "rel_l2");
    r.score.relL2Se = numberIn(j, "rel_l2_se");
    r.score.meanRatio = numberIn(j, "mean_ratio");
    r.score.meanRatioSe = numberIn(j, "mean_ratio_se");
    r.score.pixels = j.at("pixels").get<size_t>();
    r.rank = j.at("rank").get<int>();
    r.tie = j.at("tie").get<bool>();
    if (!j.at("problem").is_null()) r.score.problem = j.at("problem").get<std::string>();
    return r;
}

// What identifies a run: every shard of it has the same.
json runJson(const GeometryReport& r, const json& skipped, size_t cases) {
    json shapes = json::array();
    for (const std::string& spec : r.shapes) {
        const mesh::SuiteShape s = mesh::makeSuiteShape(spec, "--shapes");
        shapes.push_back({{"spec", s.spec},
                          {"kind", s.kind},
                          {"light", s.light},
                          {"longest_axis_ld", s.longestAxis}});
    }
    return {{"settings", settingsJson(r.settings)},
            {"rel_l2", "relative L2 error of the model image over the pixels showing the object, "
                       "both images' noise removed (app/pipeline/geometry_scoring.h)"},
            {"shapes", shapes},
            {"presets", r.presets},
            {"models", r.models},
            {"cases", cases},
            {"skipped", skipped}};
}

// A --baseline file's rows, read before any image is traced: a missing, foreign or malformed
// file fails at once, naming it.
std::vector<GeometryRow> readBaseline(const std::string& file) {
    const json b = json::parse(core::readFile(file), nullptr, false);
    if (b.is_discarded() || !b.is_object() || b.value("schema", "") != kGeometrySchema ||
        !b.contains("rows") || !b.at("rows").is_array())
        throw core::Error(file, 0, std::string("--baseline: not a ") + kGeometrySchema + " file");
    std::vector<GeometryRow> rows;
    for (const json& j : b.at("rows")) {
        try {
            rows.push_back(rowOf(j));
        } catch (const std::exception& e) {
            throw core::Error(
                file, 0, "--baseline: row " + std::to_string(rows.size() + 1) + ": " + e.what());
        }
    }
    return rows;
}

// Ranks, writes scores.json and the reports, and applies the baseline gate.
int finishRun(const fs::path& out, GeometryReport& report, const json& run,
              const std::vector<size_t>& caseOfRow, const std::vector<GeometryRow>& baseline,
              std::optional<double> failIfWorse) {
    rankGeometryRows(report.rows);
    json j = {{"schema", kGeometrySchema}, {"version", kGeometryVersion}};
    for (const auto& [k, v] : run.items())
        if (k != "cases") j[k] = v;
    j["rows"] = json::array();
    for (size_t i = 0; i < report.rows.size(); ++i)
        j["rows"].push_back(rowJson(report.rows[i], caseOfRow[i]));
    core::writeFile(out / "scores.json", j.dump(2) + "\n");
    writeGeometryReports(out, report);
    size_t problems = 0;
    for (const GeometryRow& r : report.rows)
        problems += !r.score.problem.empty();
    std::fputs(geometrySummaryText(report).c_str(), stdout);
    std::printf("%zu rows (%zu without a score: see \"problem\"): %s; reports: %s, %s\n",
                report.rows.size(), problems, (out / "scores.json").c_str(),
                (out / "report.md").c_str(), (out / "report.html").c_str());
    if (!failIfWorse) return 0;
    int worse = 0;
    for (const GeometryRow& br : baseline) {
        for (const GeometryRow& r : report.rows) {
            if (r.model != br.model || r.shape != br.shape || r.preset != br.preset ||
                r.channel != br.channel || !r.score.problem.empty() || !br.score.problem.empty())
                continue;
            const double noise = 3 * std::hypot(r.score.relL2Se, br.score.relL2Se);
            if (r.score.relL2 > br.score.relL2 * (1 + *failIfWorse / 100) &&
                r.score.relL2 - br.score.relL2 > noise) {
                std::fprintf(stderr, "worse: %s %s %s %s rel_l2 %s -> %s\n", r.model.c_str(),
                             r.shape.c_str(), r.preset.c_str(), r.channel.c_str(),
                             formatScore(br.score.relL2).c_str(),
                             formatScore(r.score.relL2).c_str());
                ++worse;
            }
        }
    }
    if (!worse) return 0;
    std::fprintf(stderr, "error: %d rows worse than the baseline by more than %s %%\n", worse,
                 formatScore(*failIfWorse).c_str());
    return 1;
}

std::string stemOf(const std::string& displayPath) {
    std::string m = displayPath.substr(displayPath.rfind('/') + 1);
    return m.substr(0, m.rfind('.'));
}

} // namespace

std::string geometryPictureName(const std::string& shape, const std::string& preset,
                                const std::string& channel) {
    std::string name = shape + "__" + preset + "_" + channel;
    for (char& c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_'))
            c = c == '=' ? '-' : '_';
    return name + ".png";
}

int runCompareGeometryCli(const fs::path& root, const GeometryArgs& a) {
    const GeometryArgs& g = a;
    if (a.out.empty()) throw core::Error("--out", 0, "give the folder to write");
    if (a.failIfWorse && a.baseline.empty())
        throw core::Error("--fail-if-worse", 0, "needs --baseline FILE");
    if (!a.shard.empty() && !a.baseline.empty())
        throw core::Error("--baseline", 0, "compare the merged run (leave out --shard)");
    const std::vector<GeometryRow> baseline =
        a.baseline.empty() ? std::vector<GeometryRow>{} : readBaseline(a.baseline);
    GeometryReport report;
    report.settings = g.settings;
    if (!g.sampling.empty())
        report.settings.sampling =
            core::enumFromName<integrate::Sampling>(g.sampling, "--sampling", "");
    std::string pictures = a.plots ? g.pictures : "";
    for (char c : pictures)
        if (c != 'R' && c != 'G' && c != 'B')
            throw core::Error("--pictures", 0,
                              "expected channel letters from R, G, B (e.g. G or RGB), got '" +
                                  g.pictures + "'");
    size_t shardK = 0, shardN = 1;
    if (!a.shard.empty()) {
        const auto [k, n] = parseShard(a.shard, "--shard");
        shardK = size_t(k); // 0-based
        shardN = size_t(n);
    }
    report.shapes = g.shapes.empty() ? mesh::defaultSuite() : g.shapes;
    for (std::string& s : report.shapes)
        s = mesh::makeSuiteShape(s, "--shapes").spec;
    report.presets = a.presets.empty() ? std::vector<std::string>{"Marble", "Skin1"} : a.presets;
    std::error_code ec;
    fs::create_directories(fs::path(a.out) / "images", ec);
    if (ec || !fs::is_directory(a.out))
        throw core::Error("--out", 0, "cannot create the folder '" + a.out + "'");
    checkWritable((fs::path(a.out) / "scores.json").string(), "--out");

    const std::vector<fs::path> models = modelFiles(root, a.models);
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, models);
    for (const auto& e : wb.library().entries())
        if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    std::vector<GeometrySkip> skips;
    const std::vector<GeometryCase> cases =
        geometryCases(wb.presets(), report.shapes, report.presets, &skips);
    json skipped = json::array();
    for (const GeometrySkip& s : skips)
        skipped.push_back({{"preset", s.preset},
                           {"channel", std::string(1, "RGB"[s.channel])},
                           {"reason", s.reason}});
    for (const auto& e : wb.library().entries())
        report.models.push_back(stemOf(e.displayPath));

    const std::atomic<bool>* stop = interruptFlag();
    std::vector<size_t> caseOfRow;
    size_t traced = 0, cached = 0;
    core::Stopwatch clock;
    for (size_t i = shardK; i < cases.size(); i += shardN) {
        const GeometryCase& c = cases[i];
        const std::string ch(1, "RGB"[c.channel]);
        const std::string what = "geometry " + std::to_string(i + 1) + "/" +
                                 std::to_string(cases.size()) + " " + c.shape + " " + c.preset +
                                 " " + ch;
        bool fromCache = false;
        const double caseStart = clock.ms();
        const auto ref = geometryReference(
            c, report.settings,
            [&](uint64_t done, uint64_t total) {
                core::progress("%s: reference %5.1f%%", what.c_str(),
                               total ? 100.0 * double(done) / double(total) : 100.0);
            },
            stop, fromCache);
        if (!ref) break;
        (fromCache ? cached : traced)++;
        std::vector<ChannelImage> images;
        std::vector<const ChannelImage*> shown;
        const double referenceSeconds = (clock.ms() - caseStart) / 1000;
        const MaterialSettings material = geometryMaterial(wb.presets(), c);
        const double radiusMm = geometryScene(c, report.settings).setup.radiusMm;
        for (const auto& e : wb.library().entries()) {
            GeometryRow row{
                stemOf(e.displayPath), c.shape, c.preset, ch, c.ldMm, radiusMm, {}, 0, false};
            std::optional<ChannelImage> img;
            try {
                img = geometryModelImage(e, material, c, report.settings, stop);
                if (img) row.score = imageRelativeL2(*img, *ref);
            } catch (const core::Error& err) { // said per case, in the row
                row.score.problem = err.what();
                std::fprintf(stderr, "\n%s: %s: %s\n", what.c_str(), row.model.c_str(), err.what());
            }
            if (stop->load()) break;
            // a model without an image shows as the background
            images.push_back(img ? std::move(*img)
                                 : ChannelImage{ref->width, ref->height,
                                                std::vector<double>(ref->mean.size()),
                                                std::vector<double>(ref->mean.size()),
                                                std::vector<char>(ref->mean.size())});
            report.rows.push_back(row);
            caseOfRow.push_back(i);
        }
        if (stop->load()) break;
        for (const ChannelImage& im : images)
            shown.push_back(&im);
        if (pictures.find(ch) != std::string::npos) {
            const RgbaImage strip = caseStrip(*ref, shown);
            gl::writePng(fs::path(a.out) / "images" / geometryPictureName(c.shape, c.preset, ch),
                         strip.width, strip.height, strip.rgba);
        }
        core::progress("%s: reference %s %.1f s, models %.1f s (total %.0f s)", what.c_str(),
                       fromCache ? "from the cache" : "traced", referenceSeconds,
                       (clock.ms() - caseStart) / 1000 - referenceSeconds, clock.ms() / 1000.0);
        core::progressEnd(); // this case's line stays
    }
    if (stop->load()) {
        core::progressEnd();
        std::fprintf(stderr, "error: compare --geometry: interrupted; nothing written\n");
        return kInterrupted;
    }
    std::fprintf(stderr, "%zu references traced, %zu from the cache, %.1f s\n", traced, cached,
                 clock.ms() / 1000.0);
    const json run = runJson(report, skipped, cases.size());
    if (!a.shard.empty()) {
        json j = run;
        j["schema"] = kShardSchema;
        j["version"] = kGeometryVersion;
        j["shard"] = {shardK + 1, shardN};
        j["rows"] = json::array();
        for (size_t r = 0; r < report.rows.size(); ++r)
            j["rows"].push_back(rowJson(report.rows[r], caseOfRow[r]));
        core::writeFile(fs::path(a.out) / "shard.json", j.dump(2) + "\n");
        std::printf("shard %zu/%zu: %zu rows: %s\n", shardK + 1, shardN, report.rows.size(),
                    (fs::path(a.out) / "shard.json").c_str());
        return 0;
    }
    return finishRun(a.out, report, run, caseOfRow, baseline, a.failIfWorse);
}

int runMergeGeometryCli(const std::vector<std::string>& dirs, const std::string& out) {
    if (dirs.empty()) throw core::Error("merge", 0, "give the shard folders");
    std::error_code ec;
    fs::create_directories(fs::path(out) / "images", ec);
    if (ec || !fs::is_directory(out))
        throw core::Error("--out", 0, "cannot create the folder '" + out + "'");
    checkWritable((fs::path(out) / "scores.json").string(), "--out");
    json run;
    size_t n = 0;
    ShardSet shards;
    std::vector<std::pair<size_t, json>> rows;
    GeometryReport report;
    for (const std::string& d : dirs) {
        const fs::path file = fs::path(d) / "shard.json";
        const json j = json::parse(core::readFile(file), nullptr, false);
        if (j.is_discarded() || j.value("schema", "") != kShardSchema ||
            j.value("version", 0) != kGeometryVersion)
            throw core::Error(file.string(), 0,
                              std::string("not a ") + kShardSchema + " file of version " +
                                  std::to_string(kGeometryVersion));
        json mine = j;
        for (const char* k : {"schema", "version", "shard", "rows"})
            mine.erase(k);
        const size_t k = j.at("shard").at(0).get<size_t>(), nk = j.at("shard").at(1).get<size_t>();
        if (run.is_null()) {
            run = mine;
            n = nk;
        } else if (mine != run || nk != n) {
            throw core::Error(file.string(), 0,
                              "a shard of another run (shapes, presets, models or settings "
                              "differ from " +
                                  dirs.front() + ")");
        }
        shards.add(k, n, file.string(), d);
        for (const json& r : j.at("rows"))
            rows.emplace_back(r.at("case").get<size_t>(), r);
        for (const auto& pic : fs::directory_iterator(fs::path(d) / "images", ec))
            fs::copy_file(pic.path(), fs::path(out) / "images" / pic.path().filename(),
                          fs::copy_options::overwrite_existing, ec);
    }
    shards.complete();
    std::stable_sort(rows.begin(), rows.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<size_t> caseOfRow;
    for (const auto& [c, r] : rows) {
        report.rows.push_back(rowOf(r));
        caseOfRow.push_back(c);
    }
    const json& st = run.at("settings");
    report.settings.size = st.at("size").get<int>();
    report.settings.referenceSpp = st.at("reference_spp").get<uint64_t>();
    report.settings.modelSpp = st.at("model_spp").get<uint64_t>();
    report.settings.sampling = core::enumFromName<integrate::Sampling>(
        st.at("sampling").get<std::string>(), "settings.sampling", "");
    report.settings.seed = st.at("seed").get<uint64_t>();
    for (const json& s : run.at("shapes"))
        report.shapes.push_back(s.at("spec").get<std::string>());
    report.presets = run.at("presets").get<std::vector<std::string>>();
    report.models = run.at("models").get<std::vector<std::string>>();
    return finishRun(out, report, run, caseOfRow, {}, std::nullopt);
}

} // namespace app
