#include "pipeline/params_lab.h"

#include "core/core.h"
#include "core/text.h"
#include "pathtrace/bssrdf_estimate.h"
#include "pipeline/scoring.h"
#include "pipeline/workbench.h"

#include <cmath>
#include <tuple>

namespace app {

std::pair<double, double> diffuseAlbedo(const pathtrace::Medium& m, uint64_t paths) {
    // 8-point Gauss–Legendre on [-1, 1] (Abramowitz & Stegun 25.4.30), mapped to μ in (0, 1)
    static const double x[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                0.9602898564975363};
    static const double w[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                0.1012285362903763};
    pathtrace::EstimateSettings es;
    es.bins.rBins = 1;
    es.bins.rMaxMm = 1e6;
    es.bins.thetaSBins = 1;
    es.estimator = pathtrace::BssrdfEstimator::Implicit;
    es.paths = paths;
    es.seed = 11;
    es.thetaIDeg.clear(); // (the default holds normal incidence)
    std::vector<double> mu, weight;
    for (int i = 0; i < 4; ++i)
        for (double sign : {-1.0, 1.0}) {
            mu.push_back(0.5 * (1 + sign * x[i]));
            weight.push_back(0.5 * w[i]);
            es.thetaIDeg.push_back(std::acos(mu.back()) * 180 / M_PI);
        }
    double num = 0, den = 0, var = 0;
    for (size_t k = 0; k < mu.size(); ++k) {
        const pathtrace::BssrdfTally t =
            pathtrace::estimateChunks(m, es, k, 0, pathtrace::chunkCount(es));
        const pathtrace::BssrdfSlice s = pathtrace::finalize(t, es.bins, es.thetaIDeg[k], m);
        num += weight[k] * mu[k] * s.totalRd;
        den += weight[k] * mu[k] * (1 - s.specular);
        var += std::pow(weight[k] * mu[k] * s.totalRdStderr, 2);
    }
    return {num / den, std::sqrt(var) / den};
}

void measureLabCase(const material::MaterialParams& p, uint64_t paths, LabCase& c, bool diffuse) {
    c.sigmaA = p.sigmaA[0];
    c.sigmaS = p.sigmaS[0];
    const pathtrace::Medium m{p.sigmaA[0], p.sigmaS[0], p.g, p.eta};
    const double ld = 1.0 / std::sqrt(3.0 * m.sigmaA * (m.sigmaA + m.sigmaS * (1.0 - m.g)));
    bool cached = false;
    const pathtrace::SlabResult r = slabReference(
        m, scoringSlabSettings(ld, paths),
        "params-lab: " + c.mapping + " A " + core::formatNumber(c.albedo, 3) + " eta " +
            core::formatNumber(c.eta, 3) + " g " + core::formatNumber(c.g, 3),
        cached);
    c.measured = r.totalRd / (1 - r.specular);
    c.measuredSe = r.totalRdStderr / (1 - r.specular);
    double num = 0, den = 0;
    for (size_t i = 0; i < r.rMid.size(); ++i) {
        num += r.rMid[i] * r.rd[i] * r.rMid[i];
        den += r.rd[i] * r.rMid[i];
    }
    c.meanRadiusMm = den > 0 ? num / den : NAN;
    if (diffuse) std::tie(c.diffuse, c.diffuseSe) = diffuseAlbedo(m, paths);
}

std::vector<LabCase> runParamsLab(Workbench& wb, const LabSettings& s,
                                  const std::function<void(size_t, size_t)>& progress,
                                  const std::atomic<bool>* cancel) {
    std::vector<const ParamMapping*> maps;
    if (s.mappings.empty())
        for (const ParamMapping& m : paramMappings())
            maps.push_back(&m);
    for (const std::string& id : s.mappings) {
        const ParamMapping* m = findParamMapping(id);
        if (!m) {
            std::string known;
            for (const ParamMapping& k : paramMappings())
                known += (known.empty() ? "" : ", ") + k.id;
            throw core::Error("--mappings", 0,
                              "unknown mapping '" + id + "' (known: " + known + ")");
        }
        maps.push_back(m);
    }
    const size_t total = maps.size() * s.etas.size() * s.gs.size() * s.albedos.size();
    std::vector<LabCase> out;
    for (const ParamMapping* m : maps) {
        const bssrdf::ModelEntry* model = m->model.empty() ? nullptr : wb.library().find(m->model);
        for (double eta : s.etas)
            for (double g : s.gs)
                for (double a : s.albedos) {
                    if (cancel && cancel->load()) return out;
                    LabCase c;
                    c.mapping = m->id;
                    c.eta = eta;
                    c.g = g;
                    c.albedo = a;
                    c.lengthMm = s.lengthMm;
                    try {
                        const material::MaterialParams p = mapArtistParams(
                            *m, glm::dvec3(a), glm::dvec3(s.lengthMm), g, eta, model);
                        measureLabCase(p, s.paths, c, s.diffuse);
                    } catch (const core::Error& e) {
                        c.problem = e.what();
                        c.measured = c.measuredSe = c.meanRadiusMm = NAN;
                    }
                    out.push_back(c);
                    if (progress) progress(out.size(), total);
                }
    }
    return out;
}

} // namespace app
