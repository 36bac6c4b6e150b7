// The scores against the path-traced reference (scoring.h has the definition of each).
#include "pipeline/scoring.h"

#include "core/core.h"
#include "core/fields.h"
#include "core/relative_error.h"
#include "core/statistics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>

namespace app {
namespace fs = std::filesystem;

using nlohmann::json;

namespace {

// The reference's radial histogram: [0, 4.5 l_d) in 360 bins of 0.0125 l_d. rel_err weighs ln r,
// so the bins at its lower bound, 0.1 l_d, must be narrow in ln r: with 0.05 l_d bins the dipole
// on Skin1 R scored 1.7 % (3 standard errors) below its value on finer grids
// (tests/app/rel_err_grid_test.cpp); far out, where these bins hold few paths, rel_err merges them.
constexpr double kRangeLd = 4.5;
constexpr int kBins = 360;

json resultJson(const pathtrace::SlabResult& r) {
    return {{"r_mid", r.rMid},
            {"rd", r.rd},
            {"rd_se", r.rdStderr},
            {"total_rd", r.totalRd},
            {"total_rd_se", r.totalRdStderr},
            {"specular", r.specular},
            {"paths", r.paths},
            {"batch_fraction", r.rdBatches.fraction},
            {"batch_means", r.rdBatches.mean}};
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
        if (!readBatchMeans(j, r.rd.size(), r.rdBatches)) return std::nullopt;
        return r;
    } catch (const std::exception&) { // a damaged cache entry is traced again
        return std::nullopt;
    }
}

} // namespace

bool readBatchMeans(const nlohmann::json& j, size_t bins, core::BatchMeans& out) {
    out = {};
    if (!j.contains("batch_fraction")) return true; // written before batch means: none
    out.fraction = j.at("batch_fraction").get<std::vector<double>>();
    out.mean = j.at("batch_means").get<std::vector<std::vector<double>>>();
    bool ok = out.mean.size() == out.fraction.size();
    for (const auto& b : out.mean)
        ok = ok && b.size() == bins;
    return ok;
}

pathtrace::SlabSettings scoringSlabSettings(double ldMm, uint64_t paths) {
    pathtrace::SlabSettings s;
    s.rMaxMm = kRangeLd * ldMm;
    s.bins = kBins;
    s.paths = paths;
    return s;
}

pathtrace::SlabResult slabReference(const pathtrace::Medium& m, const pathtrace::SlabSettings& s,
                                    const std::string& what, bool& fromCache) {
    const fs::path dir = compareCacheDir();
    const fs::path file = dir.empty() ? fs::path() : dir / (core::keyOf(m, s) + ".json");
    if (auto r = cachedResult(file)) {
        fromCache = true;
        return *r;
    }
    fromCache = false;
    core::Stopwatch clock;
    pathtrace::SlabResult r = pathtrace::runSlab(m, s, [&](uint64_t done) {
        if (clock.ms() < 1000) return;
        core::progress("%s  %5.1f%%", what.c_str(), 100.0 * double(done) / double(s.paths));
    });
    core::progressEnd();
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

std::string formatScore(double v, int digits) {
    return std::isfinite(v) ? core::formatNumber(v, digits) : "—";
}

fs::path compareCacheDir() {
    if (const char* c = std::getenv("BSSRDF_WORKBENCH_CACHE"); c && *c)
        return fs::path(c) / "reference";
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
        return fs::path(x) / "bssrdf-workbench" / "reference";
    if (const char* h = std::getenv("HOME"); h && *h)
        return fs::path(h) / ".cache" / "bssrdf-workbench" / "reference";
    return {};
}

// 2π∫₀^∞ R r dr of one channel of a model: 2048 points in ln r from 1e-6 l_d to 60 l_d,
// trapezoid in ln r (∫ R r² d ln r).
double modelTotalRd(GLuint program, const bssrdf::ModelEntry& e, const bssrdf::Builtins& b,
                    double ld, int channel) {
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
    return 2 * std::numbers::pi * sum * h;
}

std::vector<double> binEdges(const std::vector<double>& rMid) {
    std::vector<double> e;
    if (rMid.empty()) return e;
    const double dr = rMid.size() > 1 ? rMid[1] - rMid[0] : 2 * rMid[0];
    for (double r : rMid)
        e.push_back(r - 0.5 * dr);
    e.push_back(rMid.back() + 0.5 * dr);
    e.front() = std::max(e.front(), 0.0);
    return e;
}

bssrdf::Profile binAverageProfile(GLuint program, const bssrdf::ModelEntry& e,
                                  const bssrdf::Builtins& b, const std::vector<double>& edges,
                                  std::string& problem) {
    const size_t n = edges.empty() ? 0 : edges.size() - 1;
    std::vector<core::BinNodes> nodes(n);
    std::vector<double> radii;
    radii.reserve(4 * n);
    for (size_t i = 0; i < n; ++i) {
        nodes[i] = core::areaAverageNodes(edges[i], edges[i + 1]);
        radii.insert(radii.end(), nodes[i].r.begin(), nodes[i].r.end());
    }
    const bssrdf::Profile atNodes = bssrdf::evaluateProfile(program, *e.model, e.values, b, radii);
    problem = bssrdf::profileProblem(atNodes);
    bssrdf::Profile avg;
    for (size_t i = 0; i < n; ++i) {
        glm::dvec3 v(0.0);
        for (size_t k = 0; k < 4; ++k)
            v += nodes[i].w[k] * atNodes.value[4 * i + k];
        avg.r.push_back(0.5 * (edges[i] + edges[i + 1]));
        avg.value.push_back(v);
    }
    return avg;
}

std::vector<double> channelOf(const bssrdf::Profile& p, int channel) {
    std::vector<double> v(p.value.size());
    for (size_t i = 0; i < v.size(); ++i)
        v[i] = p.value[i][channel];
    return v;
}

ScoreRow scoreAgainstReference(const std::vector<double>& edges, const std::vector<double>& rd,
                               const std::vector<double>& rdSe, double specular, double totalRd,
                               double totalRdSe, double ldMm, const std::vector<double>& model,
                               double modelTotal, const core::BatchMeans& rdBatches) {
    ScoreRow s;
    s.ldMm = ldMm;
    const double entering = 1.0 - specular;
    const size_t n = rd.size();
    std::vector<double> rMid(n), ref(n), refSe(n);
    for (size_t i = 0; i < n; ++i) {
        rMid[i] = 0.5 * (edges[i] + edges[i + 1]);
        ref[i] = rd[i] / entering;
        refSe[i] = rdSe[i] / entering;
    }
    const core::RelativeError e =
        core::radialRelativeError(edges, ref, refSe, model, core::kRelErrFromLd * ldMm,
                                  core::kRelErrToLd * ldMm, rdBatches.scaled(1 / entering));
    s.relErr = e.valid() ? e.value : std::numeric_limits<double>::infinity();
    s.relErrSe = e.valid() ? e.se : 0.0;
    s.relErrSquared = e.squared;
    // the model's power over the reference's in the bins whose centres lie within ±5 % of r:
    // a window of fixed width in ln r, so the ratio does not hang on one bin of a fine grid
    auto ratioAt = [&](double r, double& se) {
        double num = 0, den = 0, var = 0;
        for (size_t i = 0; i < n; ++i) {
            if (std::abs(rMid[i] - r) > 0.05 * r) continue;
            const double area = edges[i + 1] * edges[i + 1] - edges[i] * edges[i];
            num += model[i] * area;
            den += ref[i] * area;
            var += refSe[i] * refSe[i] * area * area;
        }
        const double ratio = den > 0 ? num / den : std::numeric_limits<double>::quiet_NaN();
        se = std::abs(ratio) * std::sqrt(var) / den;
        return ratio;
    };
    s.ratio1 = ratioAt(ldMm, s.ratio1Se);
    s.ratio4 = ratioAt(4 * ldMm, s.ratio4Se);
    const double refTotal = totalRd / entering;
    s.totalRatio = modelTotal / refTotal;
    s.totalRatioSe = std::abs(s.totalRatio) * totalRdSe / std::abs(totalRd);
    for (size_t i = 0; i < n; ++i) {
        if (rMid[i] < core::kRelErrFromLd * ldMm || rMid[i] > core::kRelErrToLd * ldMm) continue;
        const double d = std::abs(model[i] - ref[i]);
        if (d > 0.05 * std::abs(ref[i]) && d > 2 * refSe[i]) {
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
                  [](const ScoreRow* a, const ScoreRow* b) { return a->relErr < b->relErr; });
        // A rank group starts at its best model (the leader); a model whose rel_err exceeds the
        // leader's by no more than the noise, 2√(se² + se_leader²), shares the leader's rank
        // and both are marked as ties; otherwise it leads a new group at its own position.
        ScoreRow* leader = nullptr;
        for (size_t k = 0; k < g.size(); ++k) {
            ScoreRow& r = *g[k];
            r.tie = false;
            const double noise =
                leader
                    ? 2 * std::sqrt(r.relErrSe * r.relErrSe + leader->relErrSe * leader->relErrSe)
                    : 0.0;
            if (leader && r.relErr - leader->relErr <= noise) {
                r.rank = leader->rank;
                r.tie = true;
                leader->tie = true;
            } else {
                r.rank = int(k) + 1;
                leader = &r;
            }
        }
    }
    // channels in the order of the pencil plot and every colour triple: R, G, B (then any other
    // name, alphabetically), not B, G, R as their names sort
    const auto channelOrder = [](const std::string& c) {
        return c == "R" ? 0 : c == "G" ? 1 : c == "B" ? 2 : 3;
    };
    std::stable_sort(rows.begin(), rows.end(), [&](const ScoreRow& a, const ScoreRow& b) {
        const int ca = channelOrder(a.channel), cb = channelOrder(b.channel);
        return std::tie(a.preset, ca, a.channel, a.thetaI, a.rank, a.relErr) <
               std::tie(b.preset, cb, b.channel, b.thetaI, b.rank, b.relErr);
    });
}

std::vector<ModelSummary> summarizeModels(const std::vector<ScoreRow>& rows) {
    std::map<std::string, std::vector<const ScoreRow*>> byModel;
    for (const ScoreRow& r : rows)
        byModel[r.model].push_back(&r);
    std::vector<ModelSummary> out;
    for (const auto& [model, own] : byModel) {
        ModelSummary m;
        m.model = model;
        m.rows = own.size();
        std::vector<double> rel;
        for (const ScoreRow* r : own) {
            m.first += r->rank == 1;
            rel.push_back(r->relErr);
            if (rel.size() == 1 || r->relErr > m.worst.relErr) m.worst = *r;
        }
        m.medianRelErr = core::median(std::move(rel));
        out.push_back(std::move(m));
    }
    std::stable_sort(out.begin(), out.end(), [](const ModelSummary& a, const ModelSummary& b) {
        return a.medianRelErr < b.medianRelErr;
    });
    return out;
}

} // namespace app
