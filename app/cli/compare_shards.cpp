// `compare --shard K/N` and the `merge` of its folders (compare_command.h): a shard writes the
// unranked rows and the report's curves of its units (one medium and angle each) with the unit
// of each; merge checks that the folders are the N shards of one run, puts everything back in
// unit order and finishes as one process does (finishCompare), so scores.json is byte for byte
// the single process's. Numbers round-trip exactly through JSON (shortest representation);
// NaN, which JSON lacks, is written as null and read back as NaN.
#include "cli/compare_command.h"

#include "cli/args.h"
#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kScoresShardSchema = "bssrdf-workbench-scores-shard";
constexpr int kScoresShardVersion = 1;

double jsonNumber(const json& j) {
    return j.is_null() ? std::nan("") : j.get<double>();
}
std::optional<double> jsonOptional(const json& j) {
    return j.is_null() ? std::nullopt : std::optional<double>(j.get<double>());
}
std::vector<double> jsonNumbers(const json& j) {
    std::vector<double> v;
    for (const json& x : j)
        v.push_back(jsonNumber(x));
    return v;
}

ScoreRow scoreRowOf(const json& j) {
    ScoreRow r;
    r.model = j.at("model").get<std::string>();
    r.preset = j.at("preset").get<std::string>();
    r.channel = j.at("channel").get<std::string>();
    r.thetaI = jsonNumber(j.at("theta_i"));
    r.ldMm = jsonNumber(j.at("ld_mm"));
    r.relErr = jsonNumber(j.at("rel_err"));
    r.relErrSe = jsonNumber(j.at("rel_err_se"));
    r.ratio1 = jsonNumber(j.at("ratio_1ld"));
    r.ratio1Se = jsonNumber(j.at("ratio_1ld_se"));
    r.ratio4 = jsonNumber(j.at("ratio_4ld"));
    r.ratio4Se = jsonNumber(j.at("ratio_4ld_se"));
    r.totalRatio = jsonNumber(j.at("total_ratio"));
    r.totalRatioSe = jsonNumber(j.at("total_ratio_se"));
    r.rErr5Ld = jsonOptional(j.at("r_err5_ld"));
    r.relErrDir = jsonOptional(j.at("rel_err_dir"));
    r.relErrDirSe = jsonOptional(j.at("rel_err_dir_se"));
    return r;
}

json curvesJson(const std::vector<std::pair<std::string, std::vector<double>>>& models) {
    json out = json::array();
    for (const auto& [name, v] : models)
        out.push_back({{"model", name}, {"values", v}});
    return out;
}
std::vector<std::pair<std::string, std::vector<double>>> curvesOf(const json& j) {
    std::vector<std::pair<std::string, std::vector<double>>> out;
    for (const json& m : j)
        out.emplace_back(m.at("model").get<std::string>(), jsonNumbers(m.at("values")));
    return out;
}

} // namespace

void writeCompareShard(const fs::path& out, const CompareRun& run, size_t k, size_t n) {
    json j = {{"schema", kScoresShardSchema},
              {"version", kScoresShardVersion},
              {"shard", {k, n}},
              {"run",
               {{"theta_i", run.report.thetaI},
                {"paths", run.report.paths},
                {"presets", run.presets},
                {"models", run.models},
                {"units", run.units},
                {"skipped", run.skipped}}},
              {"rows", json::array()},
              {"profiles", json::array()},
              {"slices", json::array()}};
    for (size_t i = 0; i < run.report.rows.size(); ++i) {
        json r = scoreRowJson(run.report.rows[i]);
        r["unit"] = run.unitOfRow[i];
        j["rows"].push_back(r);
    }
    for (size_t i = 0; i < run.report.profiles.size(); ++i) {
        const ProfileCurves& p = run.report.profiles[i];
        j["profiles"].push_back({{"unit", run.unitOfProfile[i]},
                                 {"preset", p.preset},
                                 {"channel", p.channel},
                                 {"ld_mm", p.ld},
                                 {"r", p.r},
                                 {"ref", p.ref},
                                 {"ref_se", p.refSe},
                                 {"models", curvesJson(p.models)}});
    }
    for (size_t i = 0; i < run.report.slices.size(); ++i) {
        const SliceMaps& m = run.report.slices[i];
        j["slices"].push_back({{"unit", run.unitOfSlice[i]},
                               {"preset", m.preset},
                               {"channel", m.channel},
                               {"theta_i", m.thetaI},
                               {"ld_mm", m.ld},
                               {"bins", core::toJson(m.bins)},
                               {"ref", m.refR},
                               {"ref_se", m.refSe},
                               {"models", curvesJson(m.models)}});
    }
    core::writeFile(out / "shard.json", j.dump(1) + "\n");
    std::printf("shard %zu/%zu: %zu rows: %s\n", k, n, run.report.rows.size(),
                (out / "shard.json").c_str());
}

int runMergeCompareCli(const std::vector<std::string>& dirs, const std::string& out, bool plots) {
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec || !fs::is_directory(out))
        throw core::Error("--out", 0, "cannot create the folder '" + out + "'");
    json run;
    size_t n = 0;
    ShardSet shards;
    std::vector<std::pair<size_t, json>> rows, profiles, slices;
    for (const std::string& d : dirs) {
        const fs::path file = fs::path(d) / "shard.json";
        const json j = json::parse(core::readFile(file), nullptr, false);
        if (j.is_discarded() || j.value("schema", "") != kScoresShardSchema ||
            j.value("version", 0) != kScoresShardVersion)
            throw core::Error(file.string(), 0,
                              std::string("not a ") + kScoresShardSchema + " file of version " +
                                  std::to_string(kScoresShardVersion));
        const size_t k = j.at("shard").at(0).get<size_t>(), nk = j.at("shard").at(1).get<size_t>();
        if (run.is_null()) {
            run = j.at("run");
            n = nk;
        } else if (j.at("run") != run || nk != n) {
            throw core::Error(file.string(), 0,
                              "a shard of another run (presets, models, angles or paths differ "
                              "from " +
                                  dirs.front() + ")");
        }
        shards.add(k, n, file.string(), d);
        for (const char* part : {"rows", "profiles", "slices"})
            for (const json& x : j.at(part))
                (part[0] == 'r'   ? rows
                 : part[0] == 'p' ? profiles
                                  : slices)
                    .emplace_back(x.at("unit").get<size_t>(), x);
    }
    shards.complete();
    const auto byUnit = [](const auto& a, const auto& b) { return a.first < b.first; };
    for (auto* v : {&rows, &profiles, &slices})
        std::stable_sort(v->begin(), v->end(), byUnit);
    CompareReport report;
    report.paths = run.at("paths").get<uint64_t>();
    report.thetaI = run.at("theta_i").get<std::vector<double>>();
    for (const auto& [u, r] : rows)
        report.rows.push_back(scoreRowOf(r));
    for (const auto& [u, p] : profiles)
        report.profiles.push_back({p.at("preset").get<std::string>(), p.at("channel").get<int>(),
                                   jsonNumber(p.at("ld_mm")), jsonNumbers(p.at("r")),
                                   jsonNumbers(p.at("ref")), jsonNumbers(p.at("ref_se")),
                                   curvesOf(p.at("models"))});
    for (const auto& [u, m] : slices) {
        SliceMaps s{m.at("preset").get<std::string>(),
                    m.at("channel").get<int>(),
                    jsonNumber(m.at("theta_i")),
                    jsonNumber(m.at("ld_mm")),
                    {},
                    jsonNumbers(m.at("ref")),
                    jsonNumbers(m.at("ref_se")),
                    curvesOf(m.at("models"))};
        core::fromJson(m.at("bins"), s.bins, "shard.json", "bins");
        report.slices.push_back(std::move(s));
    }
    auto ctx = gl::createHeadlessContext(false); // the plots are drawn by the panels' GL code
    return finishCompare(out, report, run.at("skipped"), plots, {}, std::nullopt);
}

} // namespace app
