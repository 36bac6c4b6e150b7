// The scoreboard at oblique incidence (scoring_oblique.h has the definitions).
#include "pipeline/scoring_oblique.h"

#include "core/core.h"
#include "core/fields.h"
#include "core/relative_error.h"
#include "pipeline/scoring.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>

namespace app {
namespace fs = std::filesystem;
using nlohmann::json;

pathtrace::EstimateSettings obliqueSettings(double ldMm, double thetaIDeg, uint64_t paths) {
    pathtrace::EstimateSettings s;
    s.thetaIDeg = {thetaIDeg};
    s.bins.rBins = kObliqueRBins;
    s.bins.spacing = pathtrace::RadialSpacing::Log; // equal steps in ln r, as rel_err weighs them
    s.bins.rStartMm = core::kRelErrFromLd * ldMm;
    s.bins.rMaxMm = core::kRelErrToLd * ldMm;
    s.bins.thetaSBins = kObliqueThetaSBins;
    s.bins.dirCosBins = kObliqueDirCos;
    s.bins.dirPhiBins = kObliquePhi;
    s.paths = paths;
    s.seed = 1;
    s.estimator = pathtrace::BssrdfEstimator::Connections;
    return s;
}

namespace {

json sliceJson(const pathtrace::BssrdfSlice& s) {
    return {{"theta_i", s.thetaIDeg},
            {"specular", s.specular},
            {"paths", s.paths},
            {"R", s.R},
            {"R_se", s.RStderr},
            {"S", s.S},
            {"S_se", s.SStderr},
            {"total_rd", s.totalRd},
            {"total_rd_se", s.totalRdStderr},
            {"batch_fraction", s.RBatches.fraction},
            {"batch_means", s.RBatches.mean}};
}

std::optional<pathtrace::BssrdfSlice> cachedSlice(const fs::path& file,
                                                  const pathtrace::BssrdfBins& b) {
    std::error_code ec;
    if (file.empty() || !fs::exists(file, ec)) return std::nullopt;
    try {
        const json j = json::parse(core::readFile(file));
        pathtrace::BssrdfSlice s;
        s.thetaIDeg = j.at("theta_i").get<double>();
        s.specular = j.at("specular").get<double>();
        s.paths = j.at("paths").get<uint64_t>();
        s.R = j.at("R").get<std::vector<double>>();
        s.RStderr = j.at("R_se").get<std::vector<double>>();
        s.S = j.at("S").get<std::vector<double>>();
        s.SStderr = j.at("S_se").get<std::vector<double>>();
        s.totalRd = j.at("total_rd").get<double>();
        s.totalRdStderr = j.at("total_rd_se").get<double>();
        const size_t bins = size_t(b.spatialBins()), cells = bins * size_t(b.dirBins());
        if (s.R.size() != bins || s.RStderr.size() != bins || s.S.size() != cells ||
            s.SStderr.size() != cells || !readBatchMeans(j, bins, s.RBatches))
            return std::nullopt;
        return s;
    } catch (const std::exception&) { // a damaged cache entry is estimated again
        return std::nullopt;
    }
}

// rel_err over the slice's bins: one radial series per θs sector (and exit cell), index
// ib·cells + ic with ib = ir·sectors + it, weighted by `weight(ic)`; noisy rings merged within
// each series (core/relative_error.h).
core::RelativeError relErr(const pathtrace::BssrdfBins& b, const std::vector<double>& model,
                           const std::vector<double>& ref, const std::vector<double>& se, int cells,
                           const std::function<double(int)>& weight, double ldMm,
                           const core::BatchMeans& batches = {}) {
    std::vector<core::RadialSeries> series;
    for (int it = 0; it < b.thetaSBins; ++it)
        for (int ic = 0; ic < cells; ++ic) {
            core::RadialSeries s;
            s.weight = weight(ic);
            if (!batches.empty()) {
                s.batches.fraction = batches.fraction;
                s.batches.mean.resize(batches.mean.size());
            }
            for (int ir = 0; ir < b.rBins; ++ir) {
                const size_t i = size_t((ir * b.thetaSBins + it) * cells + ic);
                s.ref.push_back(ref[i]);
                s.refSe.push_back(se[i]);
                s.model.push_back(model[i]);
                for (size_t k = 0; k < s.batches.mean.size(); ++k)
                    s.batches.mean[k].push_back(batches.mean[k][i]);
            }
            series.push_back(std::move(s));
        }
    core::RelativeError e = core::radialRelativeError(
        b.rEdges(), series, core::kRelErrFromLd * ldMm, core::kRelErrToLd * ldMm);
    if (!e.valid()) e.value = std::numeric_limits<double>::infinity(), e.se = 0;
    return e;
}

} // namespace

pathtrace::BssrdfSlice obliqueReference(const pathtrace::Medium& m,
                                        const pathtrace::EstimateSettings& s,
                                        const std::string& what, bool& fromCache) {
    pathtrace::validate(s);
    const fs::path dir = compareCacheDir();
    const fs::path file = dir.empty() ? fs::path() : dir / (core::keyOf(m, s) + ".slice.json");
    if (auto r = cachedSlice(file, s.bins)) {
        fromCache = true;
        return *r;
    }
    fromCache = false;
    core::Stopwatch clock;
    const pathtrace::BssrdfTally t =
        pathtrace::estimateChunks(m, s, 0, 0, pathtrace::chunkCount(s), [&](uint64_t done) {
            if (clock.ms() < 1000) return;
            core::progress("reference %s  %5.1f%%", what.c_str(),
                           100.0 * double(done) / double(s.paths));
        });
    core::progressEnd();
    const pathtrace::BssrdfSlice slice = pathtrace::finalize(t, s.bins, s.thetaIDeg.at(0), m);
    if (std::string p = pathtrace::energyProblem(slice, s.orders); !p.empty())
        throw core::Error("reference", 0, what + ": " + p);
    if (!file.empty()) {
        std::error_code ec;
        fs::create_directories(dir, ec);
        try {
            core::writeFile(file, sliceJson(slice).dump());
        } catch (const core::Error& e) {
            core::logWarn(std::string("reference cache not written: ") + e.what());
        }
    }
    return slice;
}

capture::ScoreRow scoreSlice(const pathtrace::BssrdfBins& b, const pathtrace::BssrdfSlice& ref,
                             const ModelSlice& model, double ldMm) {
    capture::ScoreRow row;
    row.ldMm = ldMm;
    row.thetaI = ref.thetaIDeg;
    const int nb = b.spatialBins(), nc = b.dirBins();
    const std::vector<double> edges = b.rEdges();
    std::vector<double> area(size_t(nb), 0.0);
    for (int ib = 0; ib < nb; ++ib)
        area[size_t(ib)] = pathtrace::binArea(b, ib / b.thetaSBins);
    // over (ln r, θs): the θs sectors are equal, so each sector's series weighs 1
    const core::RelativeError plane = relErr(
        b, model.R, ref.R, ref.RStderr, 1, [](int) { return 1.0; }, ldMm, ref.RBatches);
    row.relErr = plane.value;
    row.relErrSe = plane.se;
    row.relErrSquared = plane.squared;
    if (nc > 1 && ref.S.size() == size_t(nb * nc) && model.S.size() == ref.S.size()) {
        const core::RelativeError dir = relErr(
            b, model.S, ref.S, ref.SStderr, nc,
            [&](int ic) { return pathtrace::cellProjectedSolidAngle(b, ic); }, ldMm);
        row.relErrDir = dir.value;
        row.relErrDirSe = dir.se;
    }
    // ring powers (Σ over θs of R·A) and their standard errors
    std::vector<double> ringM(size_t(b.rBins), 0.0), ringR(size_t(b.rBins), 0.0),
        ringVar(size_t(b.rBins), 0.0);
    double totM = 0, totR = 0, totVar = 0;
    for (int ib = 0; ib < nb; ++ib) {
        const size_t ir = size_t(ib / b.thetaSBins), i = size_t(ib);
        ringM[ir] += model.R[i] * area[i];
        ringR[ir] += ref.R[i] * area[i];
        ringVar[ir] += ref.RStderr[i] * ref.RStderr[i] * area[i] * area[i];
    }
    for (int ir = 0; ir < b.rBins; ++ir) {
        totM += ringM[size_t(ir)];
        totR += ringR[size_t(ir)];
        totVar += ringVar[size_t(ir)];
    }
    auto ringAt = [&](double r) {
        int best = 0;
        for (int ir = 0; ir < b.rBins; ++ir) {
            const double c = 0.5 * (edges[size_t(ir)] + edges[size_t(ir) + 1]);
            const double cb = 0.5 * (edges[size_t(best)] + edges[size_t(best) + 1]);
            if (std::abs(c - r) < std::abs(cb - r)) best = ir;
        }
        return size_t(best);
    };
    auto ratio = [&](size_t ir, double& se) {
        const double q = ringM[ir] / ringR[ir];
        se = std::abs(q) * std::sqrt(ringVar[ir]) / std::abs(ringR[ir]);
        return q;
    };
    row.ratio1 = ratio(ringAt(ldMm), row.ratio1Se);
    row.ratio4 = ratio(ringAt(4 * ldMm), row.ratio4Se);
    row.totalRatio = totM / totR;
    row.totalRatioSe = std::abs(row.totalRatio) * std::sqrt(totVar) / std::abs(totR);
    for (int ir = 0; ir < b.rBins; ++ir) {
        const size_t i = size_t(ir);
        const double d = std::abs(ringM[i] - ringR[i]);
        if (d > 0.05 * std::abs(ringR[i]) && d > 2 * std::sqrt(ringVar[i])) {
            row.rErr5Ld = 0.5 * (edges[i] + edges[i + 1]) / ldMm;
            break;
        }
    }
    return row;
}

} // namespace app
