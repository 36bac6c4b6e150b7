// The geometry scores (geometry_scoring.h).
#include "pipeline/geometry_scoring.h"

#include "core/core.h"
#include "core/fields.h"
#include "material/material.h"
#include "pathtrace/camera.h"
#include "pathtrace/image_io.h"
#include "pathtrace/mesh_tracer.h"
#include "pipeline/scoring.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace app {
namespace fs = std::filesystem;

namespace {

MaterialSettings presetMaterial(const std::vector<material::Preset>& table,
                                const std::string& name) {
    const material::Preset* p = material::findPreset(table, name);
    if (!p) throw core::Error("--presets", 0, material::unknownPresetMessage(table, name));
    MaterialSettings s;
    s.params = material::applyPreset(*p, s.params);
    s.preset = name;
    s.mode = ParamMode::Sigma;
    return s;
}

} // namespace

double geometryLdMm(const std::vector<material::Preset>& presetTable, const std::string& preset,
                    int channel) {
    const MaterialSettings s = presetMaterial(presetTable, preset);
    const double sa = s.params.sigmaA[channel], ss = s.params.sigmaS[channel], g = s.params.g;
    const double ld = 1.0 / std::sqrt(3.0 * sa * (sa + ss * (1 - g)));
    return std::isfinite(ld) && ld > 0 ? ld : 0.0;
}

std::vector<GeometryCase> geometryCases(const std::vector<material::Preset>& presetTable,
                                        const std::vector<std::string>& shapes,
                                        const std::vector<std::string>& presets,
                                        std::vector<GeometrySkip>* skipped) {
    std::vector<std::string> specs;
    for (const std::string& s : shapes)
        specs.push_back(mesh::makeSuiteShape(s, "--shapes").spec);
    for (const std::string& p : presets)
        presetMaterial(presetTable, p); // names checked before any work
    std::vector<GeometryCase> cases;
    for (size_t k = 0; k < specs.size(); ++k)
        for (const std::string& p : presets) {
            const MaterialSettings s = presetMaterial(presetTable, p);
            for (int c = 0; c < 3; ++c) {
                const pathtrace::Medium m{s.params.sigmaA[c], s.params.sigmaS[c], s.params.g,
                                          s.params.eta};
                const double ld = geometryLdMm(presetTable, p, c);
                if (ld == 0) {
                    if (skipped && k == 0)
                        skipped->push_back({p, c, "sigma_a = 0: no diffuse mean free path l_d"});
                    continue;
                }
                cases.push_back({specs[k], p, c, ld, m});
            }
        }
    return cases;
}

MaterialSettings geometryMaterial(const std::vector<material::Preset>& presetTable,
                                  const GeometryCase& c) {
    MaterialSettings s = presetMaterial(presetTable, c.preset);
    s.params.sigmaA = glm::dvec3(c.medium.sigmaA);
    s.params.sigmaS = glm::dvec3(c.medium.sigmaS);
    s.params.g = c.medium.g;
    s.params.eta = c.medium.eta;
    return s;
}

GeometryScene geometryScene(const GeometryCase& c, const GeometrySettings& s) {
    GeometryScene g{mesh::makeSuiteShape(c.shape, "--shapes"), {}};
    g.setup.radiusMm = 0.5 * g.shape.longestAxis * c.ldMm;
    for (int k = 0; k < 3; ++k)
        g.setup.lightDir[k] = g.shape.light[size_t(k)];
    g.setup.width = g.setup.height = s.size;
    g.setup.samplesPerPixel = s.referenceSpp;
    g.setup.seed = s.seed;
    return g;
}

fs::path geometryCacheFile(const GeometryCase& c, const GeometrySettings& s) {
    const fs::path dir = compareCacheDir();
    if (dir.empty()) return {};
    const std::string key = core::keyOf(std::string("geometry-reference"), kGeometryCacheVersion,
                                        c.shape, c.medium, c.ldMm, s.size, s.referenceSpp, s.seed);
    return dir / "geometry" / (key + ".exr");
}

namespace {

// The three estimates of the traced image (R, G, B of the EXR) as one channel image.
ChannelImage averageOfChannels(const litsphere::Image& img, const std::vector<char>& covered) {
    ChannelImage out{img.width, img.height, {}, {}, covered};
    const size_t n = size_t(img.width) * size_t(img.height);
    out.mean.resize(n);
    out.variance.resize(n);
    for (size_t p = 0; p < n; ++p) {
        double m = 0, v = 0;
        for (size_t c = 0; c < 3; ++c) {
            m += img.mean[3 * p + c];
            v += img.variance[3 * p + c];
        }
        out.mean[p] = m / 3;
        out.variance[p] = v / 9;
    }
    return out;
}

std::vector<char> coveredPixels(const pathtrace::PixelGeometry& px) {
    std::vector<char> covered(px.footprint.size());
    for (size_t p = 0; p < covered.size(); ++p)
        covered[p] = px.footprint[p] > 0;
    return covered;
}

} // namespace

std::optional<ChannelImage>
geometryReference(const GeometryCase& c, const GeometrySettings& s,
                  const std::function<void(uint64_t, uint64_t)>& progress,
                  const std::atomic<bool>* cancel, bool& fromCache) {
    const GeometryScene scene = geometryScene(c, s);
    const pathtrace::LitMesh lit(scene.shape.mesh, c.shape);
    const std::vector<char> covered = coveredPixels(lit.footprints(scene.setup));
    const fs::path file = geometryCacheFile(c, s);
    std::error_code ec;
    if (!file.empty() && fs::exists(file, ec)) {
        try { // an unreadable entry or one of another size is traced again
            const litsphere::Image img = pathtrace::readExr(file);
            if (img.width == s.size && img.height == s.size) {
                fromCache = true;
                return averageOfChannels(img, covered);
            }
        } catch (const core::Error&) {
        }
    }
    fromCache = false;
    const std::array<pathtrace::Medium, 3> media{c.medium, c.medium, c.medium};
    const uint64_t total = lit.pathCount(scene.setup);
    pathtrace::ImageStats stats;
    const litsphere::Image img = lit.trace(
        media, scene.setup,
        [&](uint64_t done) {
            if (progress) progress(done, total);
        },
        cancel, {}, &stats);
    if (cancel && cancel->load()) return std::nullopt;
    for (const auto& ch : stats.channel)
        if (const std::string p = pathtrace::energyProblem(ch); !p.empty())
            throw core::Error("reference", 0, c.shape + " " + c.preset + ": " + p);
    if (!file.empty()) {
        fs::create_directories(file.parent_path(), ec);
        try {
            pathtrace::writeExr(file, img);
        } catch (const core::Error& e) {
            core::logWarn(std::string("geometry reference cache not written: ") + e.what());
        }
    }
    return averageOfChannels(img, covered);
}

std::unique_ptr<integrate::ImageIntegrator> geometryIntegrator(const bssrdf::ModelEntry& e,
                                                               const MaterialSettings& material,
                                                               const GeometryCase& c,
                                                               const GeometrySettings& s) {
    const GeometryScene scene = geometryScene(c, s);
    auto ig = std::make_unique<integrate::ImageIntegrator>(scene.setup, scene.shape.mesh, c.shape);
    integrate::Settings is;
    is.sampling = s.sampling;
    is.seed = s.seed;
    const material::MaterialParams eff = effectiveParams(e, material);
    ig->setModel(e.programs.at("pencil_profile.comp").id(), *e.model, e.values, builtinsOf(eff), is,
                 e.displayPath);
    return ig;
}

ChannelImage geometryChannelImage(const integrate::ImageIntegrator& ig, const GeometryCase& c,
                                  const std::string& modelName) {
    const litsphere::Image img = ig.image();
    ChannelImage out{img.width, img.height, {}, {}, ig.coveredPixels()};
    const size_t n = size_t(img.width) * size_t(img.height);
    out.mean.resize(n);
    out.variance.resize(n);
    for (size_t p = 0; p < n; ++p) {
        out.mean[p] = img.mean[3 * p + size_t(c.channel)];
        out.variance[p] = img.variance[3 * p + size_t(c.channel)];
        if (out.covered[p] && !std::isfinite(out.mean[p]))
            throw core::Error(modelName, 0,
                              c.shape + " " + c.preset +
                                  ": the integrated image is not finite at pixel " +
                                  std::to_string(p % size_t(img.width)) + ", " +
                                  std::to_string(p / size_t(img.width)));
    }
    return out;
}

std::optional<ChannelImage> geometryModelImage(const bssrdf::ModelEntry& e,
                                               const MaterialSettings& material,
                                               const GeometryCase& c, const GeometrySettings& s,
                                               const std::atomic<bool>* cancel) {
    const auto ig = geometryIntegrator(e, material, c, s);
    while (ig->samplesPerPixelDone() < s.modelSpp) {
        if (cancel && cancel->load()) return std::nullopt;
        ig->step(int(std::min<uint64_t>(s.modelSpp - ig->samplesPerPixelDone(), 4)), cancel);
    }
    return geometryChannelImage(*ig, c, e.displayPath);
}

ImageScore imageRelativeL2(const ChannelImage& model, const ChannelImage& ref) {
    ImageScore s;
    if (model.mean.size() != ref.mean.size()) {
        s.problem = "the images differ in size";
        return s;
    }
    double D = 0, N = 0, varD = 0, varN = 0, cov = 0, sumM = 0, sumR = 0, varM = 0, varR = 0;
    for (size_t p = 0; p < ref.mean.size(); ++p) {
        if (!ref.covered[p] || !model.covered[p]) continue;
        ++s.pixels;
        const double m = model.mean[p], r = ref.mean[p], vm = model.variance[p],
                     vr = ref.variance[p], v = vm + vr, d = m - r;
        const double delta2 = std::max(0.0, d * d - v), rho2 = std::max(0.0, r * r - vr);
        D += d * d - v;
        N += r * r - vr;
        varD += 4 * delta2 * v + 2 * v * v;
        varN += 4 * rho2 * vr + 2 * vr * vr;
        cov += -4 * d * r * vr + 2 * vr * vr;
        sumM += m;
        sumR += r;
        varM += vm;
        varR += vr;
    }
    if (s.pixels == 0) {
        s.problem = "no pixel shows the object in both images";
        return s;
    }
    if (!(N > 0) || !(sumR > 0)) {
        s.problem = "the reference is dark (no light reached the visible surface)";
        return s;
    }
    const double e2 = D / N;
    const double varE2 = std::max(0.0, (varD + e2 * e2 * varN - 2 * e2 * cov) / (N * N));
    const double se2 = std::sqrt(varE2);
    s.relL2 = std::sqrt(std::max(0.0, e2));
    s.relL2Se = std::sqrt(std::max(0.0, e2) + se2) - s.relL2;
    s.meanRatio = sumM / sumR;
    s.meanRatioSe = std::sqrt(varM / (sumR * sumR) + sumM * sumM * varR / std::pow(sumR, 4));
    return s;
}

void rankGeometryRows(std::vector<GeometryRow>& rows) {
    std::map<std::tuple<std::string, std::string, std::string>, std::vector<GeometryRow*>> groups;
    for (GeometryRow& r : rows) {
        r.rank = 0;
        r.tie = false;
        if (r.score.problem.empty()) groups[{r.shape, r.preset, r.channel}].push_back(&r);
    }
    for (auto& [key, g] : groups) {
        std::stable_sort(g.begin(), g.end(), [](const GeometryRow* a, const GeometryRow* b) {
            return a->score.relL2 < b->score.relL2;
        });
        // as rankRows (scoring.h): a model within the noise of its group's leader shares its rank
        GeometryRow* leader = nullptr;
        for (size_t k = 0; k < g.size(); ++k) {
            GeometryRow& r = *g[k];
            const double noise =
                leader ? 2 * std::hypot(r.score.relL2Se, leader->score.relL2Se) : 0.0;
            if (leader && r.score.relL2 - leader->score.relL2 <= noise) {
                r.rank = leader->rank;
                r.tie = leader->tie = true;
            } else {
                r.rank = int(k) + 1;
                leader = &r;
            }
        }
    }
}

} // namespace app
