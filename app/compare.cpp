// `bssrdf-workbench compare`: the scoreboard (compare.h has the definitions of every number).
#include "compare.h"

#include "capture/scores.h"
#include "cli.h"
#include "cli_output.h"
#include "core/core.h"
#include "core/fields.h"
#include "core/text.h"
#include "gl/gl.h"
#include "material/material.h"
#include "model_stages.h"
#include "pathtrace/pathtrace.h"
#include "workbench.h"

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
constexpr double kPi = std::numbers::pi;

// The reference's radial histogram: [0, 4.5 l_d) in 90 bins (0.05 l_d each).
constexpr double kRangeLd = 4.5;
constexpr int kBins = 90;

fs::path referenceCacheDir() {
    if (const char* c = std::getenv("BSSRDF_WORKBENCH_CACHE"); c && *c)
        return fs::path(c) / "reference";
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
        return fs::path(x) / "bssrdf-workbench" / "reference";
    if (const char* h = std::getenv("HOME"); h && *h)
        return fs::path(h) / ".cache" / "bssrdf-workbench" / "reference";
    return {};
}

json resultJson(const pathtrace::SlabResult& r) {
    return {{"r_mid", r.rMid},
            {"rd", r.rd},
            {"rd_se", r.rdStderr},
            {"total_rd", r.totalRd},
            {"total_rd_se", r.totalRdStderr},
            {"specular", r.specular},
            {"paths", r.paths}};
}

std::optional<pathtrace::SlabResult> cachedResult(const fs::path& file) {
    std::error_code ec;
    if (file.empty() || !fs::exists(file, ec)) return std::nullopt;
    try {
        const json j = json::parse(core::readFile(file));
        pathtrace::SlabResult r;
        r.rMid = j.at("r_mid").get<std::vector<double>>();
        r.rd = j.at("rd").get<std::vector<double>>();
        r.rdStderr = j.at("rd_se").get<std::vector<double>>();
        r.totalRd = j.at("total_rd").get<double>();
        r.totalRdStderr = j.at("total_rd_se").get<double>();
        r.specular = j.at("specular").get<double>();
        r.paths = j.at("paths").get<uint64_t>();
        if (r.rd.size() != r.rMid.size() || r.rdStderr.size() != r.rMid.size()) return std::nullopt;
        return r;
    } catch (const std::exception&) { // a damaged cache entry is traced again
        return std::nullopt;
    }
}

// The path-traced reference of one medium, from the cache or traced (and cached).
pathtrace::SlabResult reference(const pathtrace::Medium& m, const pathtrace::SlabSettings& s,
                                const std::string& what, bool& fromCache) {
    const fs::path dir = referenceCacheDir();
    const fs::path file = dir.empty() ? fs::path() : dir / (core::keyOf(m, s) + ".json");
    if (auto r = cachedResult(file)) {
        fromCache = true;
        return *r;
    }
    fromCache = false;
    core::Stopwatch clock;
    pathtrace::SlabResult r = pathtrace::runSlab(m, s, [&](uint64_t done) {
        if (clock.ms() < 1000) return;
        std::fprintf(stderr, "\rcompare: reference %s  %5.1f%%   ", what.c_str(),
                     100.0 * double(done) / double(s.paths));
        std::fflush(stderr);
    });
    if (clock.ms() >= 1000) std::fprintf(stderr, "\n");
    if (std::string p = pathtrace::energyProblem(r); !p.empty())
        throw core::Error("reference", 0, what + ": " + p);
    if (!file.empty()) {
        std::error_code ec;
        fs::create_directories(dir, ec);
        try {
            core::writeFile(file, resultJson(r).dump());
        } catch (const core::Error& e) {
            core::logWarn(std::string("reference cache not written: ") + e.what());
        }
    }
    return r;
}

// 2π∫₀^∞ R r dr of one channel of a model: 2048 points in ln r from 1e-6 l_d to 60 l_d,
// trapezoid in ln r (∫ R r² d ln r).
double modelTotal(GLuint program, const bssrdf::ModelEntry& e, const bssrdf::Builtins& b, double ld,
                  int channel) {
    const int n = 2048;
    const double a = std::log(1e-6 * ld), z = std::log(60.0 * ld), h = (z - a) / (n - 1);
    std::vector<double> radii(n);
    for (int k = 0; k < n; ++k)
        radii[k] = std::exp(a + h * k);
    const bssrdf::Profile p = bssrdf::evaluateProfile(program, *e.model, e.values, b, radii);
    double sum = 0;
    for (int k = 0; k < n; ++k) {
        const double f = p.value[k][channel] * radii[k] * radii[k];
        sum += (k == 0 || k == n - 1 ? 0.5 : 1.0) * f;
    }
    return 2 * kPi * sum * h;
}

std::string fmt(double v, int digits = 4) {
    return std::isfinite(v) ? core::formatNumber(v, digits) : "—";
}

json rowJson(const ScoreRow& r) {
    return {{"model", r.model},
            {"preset", r.preset},
            {"channel", r.channel},
            {"theta_i", r.thetaI},
            {"ld_mm", r.ldMm},
            {"rel_l2", r.relL2},
            {"rel_l2_se", r.relL2Se},
            {"ratio_1ld", r.ratio1},
            {"ratio_1ld_se", r.ratio1Se},
            {"ratio_4ld", r.ratio4},
            {"ratio_4ld_se", r.ratio4Se},
            {"total_ratio", r.totalRatio},
            {"total_ratio_se", r.totalRatioSe},
            {"r_err5_ld", r.rErr5Ld ? json(*r.rErr5Ld) : json(nullptr)},
            {"rank", r.rank},
            {"tie", r.tie}};
}

// rel_l2 → a cell colour from green (0) through yellow (10 %) to red (>= 30 %).
std::string cellColour(double rel) {
    const double t = std::clamp(rel / 0.3, 0.0, 1.0);
    const int red = int(std::lround(255 * std::min(1.0, 2 * t)));
    const int green = int(std::lround(200 * std::min(1.0, 2 * (1 - t))));
    char b[16];
    std::snprintf(b, sizeof b, "#%02x%02x60", red, green);
    return b;
}

std::string htmlEscape(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<')
            out += "&lt;";
        else if (c == '>')
            out += "&gt;";
        else if (c == '&')
            out += "&amp;";
        else
            out += c;
    }
    return out;
}

void writeReports(const fs::path& dir, const std::vector<ScoreRow>& rows, uint64_t paths) {
    std::ostringstream md, html;
    md << "# BSSRDF scoreboard\n\nθi = 0, " << paths
       << " reference paths per preset and channel. rel_l2 over [0.1, 4] l_d (± standard error "
          "from the reference); `=` marks a tie with the best of its preset and channel.\n\n"
       << "| preset | ch | model | rank | rel_l2 | ratio at 1 l_d | ratio at 4 l_d | total ratio "
          "| error > 5 % from |\n|---|---|---|---|---|---|---|---|---|\n";
    html << "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>BSSRDF scoreboard</title>"
            "<style>body{font-family:sans-serif;background:#111;color:#ddd}"
            "table{border-collapse:collapse}td,th{border:1px solid #444;padding:3px 8px;"
            "text-align:right}th{background:#222}td.l{text-align:left}</style></head><body>"
         << "<h1>BSSRDF scoreboard</h1><p>&theta;<sub>i</sub> = 0, " << paths
         << " reference paths per preset and channel; rel_l2 over [0.1, 4] l<sub>d</sub>, "
            "&plusmn; standard error from the reference; = marks a tie with the best.</p>"
         << "<table><tr><th>preset</th><th>ch</th><th>model</th><th>rank</th><th>rel_l2</th>"
            "<th>ratio 1 l<sub>d</sub></th><th>ratio 4 l<sub>d</sub></th><th>total ratio</th>"
            "<th>error &gt; 5 % from (l<sub>d</sub>)</th></tr>\n";
    for (const ScoreRow& r : rows) {
        const std::string rank = (r.tie ? "=" : "") + std::to_string(r.rank);
        const std::string rel = fmt(100 * r.relL2, 3) + " % ± " + fmt(100 * r.relL2Se, 2) + " %";
        const std::string err5 = r.rErr5Ld ? fmt(*r.rErr5Ld, 3) : "none";
        md << "| " << r.preset << " | " << r.channel << " | " << r.model << " | " << rank << " | "
           << rel << " | " << fmt(r.ratio1) << " | " << fmt(r.ratio4) << " | " << fmt(r.totalRatio)
           << " | " << err5 << " |\n";
        html << "<tr><td class=l>" << htmlEscape(r.preset) << "</td><td>" << r.channel
             << "</td><td class=l>" << htmlEscape(r.model) << "</td><td>" << rank
             << "</td><td style=\"background:" << cellColour(r.relL2) << ";color:#000\">"
             << htmlEscape(rel) << "</td><td>" << fmt(r.ratio1) << "</td><td>" << fmt(r.ratio4)
             << "</td><td>" << fmt(r.totalRatio) << "</td><td>" << err5 << "</td></tr>\n";
    }
    html << "</table></body></html>\n";
    core::writeFile(dir / "report.md", md.str());
    core::writeFile(dir / "report.html", html.str());
}

} // namespace

ScoreRow scoreAgainstReference(const std::vector<double>& rMid, const std::vector<double>& rd,
                               const std::vector<double>& rdSe, double specular, double totalRd,
                               double totalRdSe, double ldMm, const std::vector<double>& model,
                               double modelTotal) {
    ScoreRow s;
    s.ldMm = ldMm;
    const double entering = 1.0 - specular;
    const size_t n = rMid.size();
    const double dr = n > 1 ? rMid[1] - rMid[0] : 1.0;
    double num = 0, den = 0;
    std::vector<size_t> in;
    for (size_t i = 0; i < n; ++i)
        if (rMid[i] >= 0.1 * ldMm && rMid[i] <= 4.0 * ldMm) in.push_back(i);
    for (size_t i : in) {
        const double ref = rd[i] / entering, d = model[i] - ref;
        num += d * d * rMid[i] * dr;
        den += ref * ref * rMid[i] * dr;
    }
    s.relL2 = den > 0 ? std::sqrt(num / den) : std::numeric_limits<double>::infinity();
    double var = 0;
    if (num > 0 && den > 0)
        for (size_t i : in) {
            const double ref = rd[i] / entering, d = model[i] - ref;
            const double grad =
                s.relL2 / 2 * (-2 * d / num - 2 * ref / den) * rMid[i] * dr / entering;
            var += grad * grad * rdSe[i] * rdSe[i];
        }
    s.relL2Se = std::sqrt(var);
    auto ratioAt = [&](double r, double& se) {
        size_t best = 0;
        for (size_t i = 0; i < n; ++i)
            if (std::abs(rMid[i] - r) < std::abs(rMid[best] - r)) best = i;
        const double ref = rd[best] / entering;
        const double ratio = model[best] / ref;
        se = std::abs(ratio) * rdSe[best] / std::abs(rd[best]);
        return ratio;
    };
    s.ratio1 = ratioAt(ldMm, s.ratio1Se);
    s.ratio4 = ratioAt(4 * ldMm, s.ratio4Se);
    const double refTotal = totalRd / entering;
    s.totalRatio = modelTotal / refTotal;
    s.totalRatioSe = std::abs(s.totalRatio) * totalRdSe / std::abs(totalRd);
    for (size_t i : in) {
        const double ref = rd[i] / entering, d = std::abs(model[i] - ref);
        if (d > 0.05 * std::abs(ref) && d > 2 * rdSe[i] / entering) {
            s.rErr5Ld = rMid[i] / ldMm;
            break;
        }
    }
    return s;
}

void rankRows(std::vector<ScoreRow>& rows) {
    std::map<std::tuple<std::string, std::string, double>, std::vector<ScoreRow*>> groups;
    for (ScoreRow& r : rows)
        groups[{r.preset, r.channel, r.thetaI}].push_back(&r);
    for (auto& [key, g] : groups) {
        std::sort(g.begin(), g.end(),
                  [](const ScoreRow* a, const ScoreRow* b) { return a->relL2 < b->relL2; });
        // A rank group starts at its best model (the leader); a model whose rel_l2 exceeds the
        // leader's by no more than the noise, 2√(se² + se_leader²), shares the leader's rank
        // and both are marked as ties; otherwise it leads a new group at its own position.
        ScoreRow* leader = nullptr;
        for (size_t k = 0; k < g.size(); ++k) {
            ScoreRow& r = *g[k];
            r.tie = false;
            const double noise =
                leader ? 2 * std::sqrt(r.relL2Se * r.relL2Se + leader->relL2Se * leader->relL2Se)
                       : 0.0;
            if (leader && r.relL2 - leader->relL2 <= noise) {
                r.rank = leader->rank;
                r.tie = true;
                leader->tie = true;
            } else {
                r.rank = int(k) + 1;
                leader = &r;
            }
        }
    }
    std::stable_sort(rows.begin(), rows.end(), [](const ScoreRow& a, const ScoreRow& b) {
        return std::tie(a.preset, a.channel, a.thetaI, a.rank, a.relL2) <
               std::tie(b.preset, b.channel, b.thetaI, b.rank, b.relL2);
    });
}

int runCompareCli(const fs::path& root, const CompareArgs& a) {
    if (a.out.empty()) throw core::Error("--out", 0, "give the folder to write");
    if (a.failIfWorse && a.baseline.empty())
        throw core::Error("--fail-if-worse", 0, "needs --baseline FILE");
    if (a.failIfWorse && !(*a.failIfWorse >= 0))
        throw core::Error("--fail-if-worse", 0, "must be a percentage >= 0");
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

    std::vector<fs::path> models;
    if (a.models.empty()) {
        for (const auto& e : fs::directory_iterator(root / "materials", ec))
            if (e.path().extension() == ".bssrdf") models.push_back(e.path());
        std::sort(models.begin(), models.end());
    } else {
        for (const auto& m : a.models)
            models.push_back(resolveModel(root, m));
    }
    if (models.empty()) throw core::Error("--models", 0, "no model files");

    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, models);
    for (const auto& e : wb.library().entries())
        if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    std::vector<std::string> presets = a.presets;
    if (presets.empty())
        for (const auto& p : wb.presets())
            presets.push_back(p.name);
    for (const auto& name : presets)
        if (!material::findPreset(wb.presets(), name)) {
            std::string known;
            for (const auto& p : wb.presets())
                known += (known.empty() ? "" : ", ") + p.name;
            throw core::Error("--presets", 0,
                              "unknown preset '" + name + "' (known: " + known + ")");
        }

    std::vector<ScoreRow> rows;
    json skipped = json::array();
    size_t cached = 0, traced = 0;
    for (const std::string& preset : presets) {
        MaterialSettings s;
        wb.applyPreset(s, preset);
        const material::MaterialParams& p = s.params;
        for (int c = 0; c < 3; ++c) {
            const pathtrace::Medium m{p.sigmaA[c], p.sigmaS[c], p.g, p.eta};
            const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
            if (!(std::isfinite(ld) && ld > 0)) { // σa = 0 (Spectralon): no l_d to score over
                skipped.push_back({{"preset", preset},
                                   {"channel", std::string(1, "RGB"[c])},
                                   {"reason", "sigma_a = 0: no diffuse mean free path l_d"}});
                std::fprintf(stderr, "compare: %s %c not scored (sigma_a = 0: no l_d)\n",
                             preset.c_str(), "RGB"[c]);
                continue;
            }
            pathtrace::SlabSettings ss;
            ss.rMaxMm = kRangeLd * ld;
            ss.bins = kBins;
            ss.paths = a.paths;
            bool fromCache = false;
            const pathtrace::SlabResult ref =
                reference(m, ss, preset + " " + std::string(1, "RGB"[c]), fromCache);
            (fromCache ? cached : traced)++;
            for (auto& e : wb.library().entries()) {
                if (!e.usable()) continue;
                const material::MaterialParams eff = effectiveParams(e, s);
                const bssrdf::Builtins b = builtinsOf(eff);
                const GLuint program = e.programs.at("pencil_profile.comp").id();
                const bssrdf::Profile prof =
                    bssrdf::evaluateProfile(program, *e.model, e.values, b, ref.rMid);
                if (std::string bad = bssrdf::profileProblem(prof); !bad.empty())
                    throw core::Error(e.displayPath, 0, preset + ": " + bad);
                std::vector<double> mv(prof.value.size());
                for (size_t i = 0; i < mv.size(); ++i)
                    mv[i] = prof.value[i][c];
                ScoreRow row = scoreAgainstReference(ref.rMid, ref.rd, ref.rdStderr, ref.specular,
                                                     ref.totalRd, ref.totalRdStderr, ld, mv,
                                                     modelTotal(program, e, b, ld, c));
                row.model = e.displayPath.substr(e.displayPath.rfind('/') + 1);
                row.model = row.model.substr(0, row.model.rfind('.'));
                row.preset = preset;
                row.channel = std::string(1, "RGB"[c]);
                rows.push_back(row);
            }
        }
    }
    rankRows(rows);

    json j = {{"schema", kSchema}, {"version", kSchemaVersion}, {"theta_i", {0.0}},
              {"paths", a.paths},  {"rows", json::array()},     {"skipped", skipped}};
    for (const ScoreRow& r : rows)
        j["rows"].push_back(rowJson(r));
    writeReports(a.out, rows, a.paths);
    core::writeFile(fs::path(a.out) / "scores.json", j.dump(2) + "\n");
    std::printf("%zu rows (%zu references traced, %zu from the cache): %s\n", rows.size(), traced,
                cached, (fs::path(a.out) / "scores.json").c_str());

    if (!a.failIfWorse) return 0;
    int worse = 0;
    for (const ScoreRow& r : rows)
        for (const ScoreRow& b : baseline) {
            if (b.model != r.model || b.preset != r.preset || b.channel != r.channel ||
                b.thetaI != r.thetaI)
                continue;
            const double noise = 2 * std::sqrt(r.relL2Se * r.relL2Se + b.relL2Se * b.relL2Se);
            if (r.relL2 > b.relL2 * (1 + *a.failIfWorse / 100) && r.relL2 - b.relL2 > noise) {
                std::fprintf(stderr, "worse: %s %s %s rel_l2 %s -> %s\n", r.model.c_str(),
                             r.preset.c_str(), r.channel.c_str(), fmt(b.relL2).c_str(),
                             fmt(r.relL2).c_str());
                ++worse;
            }
        }
    if (worse) {
        std::fprintf(stderr, "error: %d rows worse than the baseline by more than %s %%\n", worse,
                     fmt(*a.failIfWorse).c_str());
        return 1;
    }
    return 0;
}

} // namespace app
