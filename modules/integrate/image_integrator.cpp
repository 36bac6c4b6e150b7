// The BSSRDF-integrated image by uniform or disk sampling (integrate.h).
#include "integrate/integrate.h"

#include "core/core.h"
#include "gl/gl.h"
#include "pathtrace/fresnel.h"
#include "pathtrace/rng.h"
#include "sampling/analytic_surfaces.h"
#include "sampling/frame.h"
#include "sampling/mesh_surface.h"
#include "sampling/stratified.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace integrate {

struct ImageIntegrator::Geometry {
    std::unique_ptr<sampling::SphereSurface> sphere;
    std::unique_ptr<sampling::MeshSurface> mesh;
    double sizeMm = 0; // a length of the object's scale: offsets of shadow rays
    const sampling::Surface& surface() const {
        return sphere ? static_cast<const sampling::Surface&>(*sphere) : *mesh;
    }
    const sampling::AreaSampler& area() const {
        return sphere ? static_cast<const sampling::AreaSampler&>(*sphere) : *mesh;
    }
    bool convex() const { return sphere != nullptr; }
};

namespace {

void validateSetup(const litsphere::Setup& s) {
    if (!(std::isfinite(s.radiusMm) && s.radiusMm > 0))
        throw core::Error("integrate", 0, "radius must be a finite length > 0 mm");
    if (s.width < 1 || s.height < 1 || s.width > 8192 || s.height > 8192)
        throw core::Error("integrate", 0, "image size must be 1 … 8192 pixels on each side");
    const double l2 = s.lightDir[0] * s.lightDir[0] + s.lightDir[1] * s.lightDir[1] +
                      s.lightDir[2] * s.lightDir[2];
    if (!(std::isfinite(l2) && l2 > 0))
        throw core::Error("integrate", 0, "the light direction must be finite and non-zero");
}

// Unpolarised Fresnel transmittance into the medium at cos θi in (0, 1].
double fresnelTransmittance(double cosI, double eta) {
    return 1.0 - pathtrace::fresnelDielectric(cosI, eta);
}

// Model evaluations gathered before one trip to the GPU (a round of whole samples per pixel).
constexpr size_t kQueriesPerRound = size_t(1) << 15;

} // namespace

// One model evaluation waiting for the GPU: its query and factor Ft·cos⁺/p (or ·A).
struct ImageIntegrator::Pending {
    bssrdf::Query q;
    double factor;
};

ImageIntegrator::ImageIntegrator(const litsphere::Setup& setup)
    : m_setup(setup), m_geo(std::make_unique<Geometry>()) {
    validateSetup(setup);
    m_geo->sphere = std::make_unique<sampling::SphereSurface>(glm::dvec3(0.0), setup.radiusMm);
    m_geo->sizeMm = setup.radiusMm;
    findShadingPoints();
}

ImageIntegrator::ImageIntegrator(const litsphere::Setup& setup, mesh::Mesh m,
                                 const std::string& name)
    : m_setup(setup), m_geo(std::make_unique<Geometry>()) {
    validateSetup(setup);
    mesh::checkClosedOutward(m, name);
    mesh::normalizeMesh(m, name);
    m_geo->mesh = std::make_unique<sampling::MeshSurface>(m, 2 * setup.radiusMm, name);
    m_geo->sizeMm = 2 * setup.radiusMm;
    findShadingPoints();
}

ImageIntegrator::ImageIntegrator(const mesh::Mesh& m, double scaleMm, const std::string& name,
                                 const ViewPoints& view)
    : m_geo(std::make_unique<Geometry>()) {
    if (!(std::isfinite(scaleMm) && scaleMm > 0))
        throw core::Error("integrate", 0, "the scale must be a finite length > 0 mm");
    const size_t pixels = size_t(view.width) * size_t(view.height);
    if (view.width < 1 || view.height < 1 || view.position.size() != pixels ||
        view.normal.size() != pixels)
        throw core::Error("integrate", 0, "the view's G-buffer does not match its size");
    const double l2 = glm::dot(view.lightDir, view.lightDir);
    if (!(std::isfinite(l2) && l2 > 0))
        throw core::Error("integrate", 0, "the light direction must be finite and non-zero");
    m_setup.width = view.width;
    m_setup.height = view.height;
    m_setup.radiusMm = scaleMm;
    m_geo->mesh = std::make_unique<sampling::MeshSurface>(m, scaleMm, name);
    m_geo->sizeMm = scaleMm;
    m_light = glm::normalize(view.lightDir);
    m_irradiance = view.irradiance;
    m_view = true;
    m_hit.assign(pixels, 0);
    m_shading.assign(pixels, {});
    m_toCamera.assign(pixels, glm::dvec3(0, 0, 1));
    for (size_t p = 0; p < pixels; ++p) {
        if (!(view.position[p].w > 0.5f)) continue;
        const glm::dvec3 x(view.position[p]), n(view.normal[p]);
        if (!(glm::dot(n, n) > 0)) continue;
        m_hit[p] = 1;
        m_shading[p] = {x * scaleMm, glm::normalize(n)};
        const glm::dvec3 d = view.camera - x;
        if (glm::dot(d, d) > 0) m_toCamera[p] = glm::normalize(d);
    }
}

ImageIntegrator::~ImageIntegrator() = default;

void ImageIntegrator::findShadingPoints() {
    const double l[3] = {m_setup.lightDir[0], m_setup.lightDir[1], m_setup.lightDir[2]};
    m_light = glm::normalize(glm::dvec3(l[0], l[1], l[2]));
    const int w = m_setup.width, h = m_setup.height;
    const double e = m_setup.extent();
    m_hit.assign(size_t(w) * size_t(h), 0);
    m_shading.assign(m_hit.size(), {});
    const double far = 10 * m_geo->sizeMm + 10 * e;
    tbb::parallel_for(0, h, [&](int j) {
        std::vector<sampling::SurfaceHit> hits;
        for (int i = 0; i < w; ++i) {
            const double x = e * (2 * (i + 0.5) / w - 1), y = e * (1 - 2 * (j + 0.5) / h);
            hits.clear();
            m_geo->surface().intersectAll({x, y, far}, {0, 0, -1}, 0, 2 * far, hits);
            if (hits.empty()) continue;
            const auto first =
                std::min_element(hits.begin(), hits.end(),
                                 [](const sampling::SurfaceHit& a, const sampling::SurfaceHit& b) {
                                     return a.t < b.t;
                                 });
            if (first->point.n.z <= 0) continue; // a back face: the camera sees no outside
            const size_t p = size_t(j) * size_t(w) + size_t(i);
            m_hit[p] = 1;
            m_shading[p] = first->point;
        }
    });
}

void ImageIntegrator::setModel(GLuint pencilProgram, const bssrdf::Model& m,
                               const bssrdf::ParamValues& values, const bssrdf::Builtins& b,
                               const Settings& s, const std::string& name) {
    if (!(s.energyLoss > 0 && s.energyLoss < 1))
        throw core::Error("integrate", 0, "the energy given up beyond R_m must lie in (0, 1)");
    // built before anything changes: on an error the previous model stays
    std::unique_ptr<RadialSource> radial;
    std::unique_ptr<sampling::DiskSampler> disk;
    if (s.sampling == Sampling::Disk) {
        core::Stopwatch clock;
        radial = std::make_unique<RadialSource>(
            radialSource(pencilProgram, m, values, b, s.energyLoss, name));
        // channels in proportion to their kept energy (disk_sampling.h)
        disk = std::make_unique<sampling::DiskSampler>(
            radial->pointers(), s.axes, sampling::energyChannelProbabilities(radial->pointers()));
        gl::recordTiming("integrate: radial distributions (" + radial->kind + ")", clock.ms());
    }
    m_program = pencilProgram;
    m_model = m;
    m_values = values;
    m_builtins = b;
    m_settings = s;
    m_disk = std::move(disk);
    m_radial = std::move(radial);
    m_sum.assign(3 * m_hit.size(), 0.0);
    m_sumSq.assign(3 * m_hit.size(), 0.0);
    // the stratified blocks' state: the disk estimator's only (sampling/stratified.h)
    const size_t blocks = m_disk ? m_hit.size() : 0;
    m_blockPartial.assign(3 * blocks, 0.0);
    m_strata.assign(blocks, {});
    m_blockSumSq.assign(3 * blocks, 0.0);
    m_blockPartial.shrink_to_fit();
    m_strata.shrink_to_fit();
    m_blockSumSq.shrink_to_fit();
    m_samples = 0;
    m_evaluations = 0;
    m_seconds = 0;
}

std::array<double, 3> ImageIntegrator::radiusMax() const {
    if (!m_radial) return {0, 0, 0};
    return {m_radial->channel[0]->radiusMax(), m_radial->channel[1]->radiusMax(),
            m_radial->channel[2]->radiusMax()};
}

void ImageIntegrator::step(int samplesPerPixel, const std::atomic<bool>* cancel) {
    if (!m_model || samplesPerPixel < 1) return;
    core::Stopwatch clock;
    const size_t pixels = m_hit.size();
    const double eta = m_builtins.ior;
    const uint64_t seed = pathtrace::splitmix64(m_settings.seed ^ 0x494e5447ull); // 'INTG'
    const uint64_t strataSeed = pathtrace::splitmix64(seed ^ 0x4c485342ull);      // 'LHSB'
    constexpr uint64_t K = uint64_t(sampling::kBlockSamples);
    const sampling::Surface& surface = m_geo->surface();
    const double eps = 1e-7 * m_geo->sizeMm, far = 10 * m_geo->sizeMm;
    // Rounds of `batch` samples per pixel: the queries of a round go to the GPU together.
    const int batch =
        int(std::clamp<size_t>(kQueriesPerRound / std::max<size_t>(pixels, 1), 1, 64));
    for (int done = 0; done < samplesPerPixel;) {
        if (cancel && cancel->load()) break;
        const int n = std::min(batch, samplesPerPixel - done);
        const uint64_t s0 = m_samples;
        // per pixel: the pending evaluations of its n samples, in sample order, and how many
        // each sample has (storage kept between rounds: no allocation per sample)
        std::vector<std::vector<Pending>>& pending = m_pending;
        pending.resize(pixels);
        m_pendingCount.assign(pixels * size_t(n), 0);
        tbb::parallel_for(size_t(0), pixels, [&](size_t p) {
            pending[p].clear();
            if (!m_hit[p]) return;
            const sampling::SurfacePoint& at = m_shading[p];
            const sampling::Frame f = sampling::Frame::fromNormal(at.x, at.n);
            std::vector<sampling::SurfaceHit> hits, shadow;
            sampling::BlockStrata<2>* strata = m_disk ? &m_strata[p] : nullptr;
            for (int k = 0; k < n; ++k) {
                std::vector<Pending>& out = pending[p];
                const size_t before = out.size();
                const uint64_t sample = s0 + uint64_t(k);
                pathtrace::Pcg32 rng = pathtrace::Pcg32::forPath(seed, sample * pixels + p);
                // the Latin-hypercube block of this sample (stratified.h), drawn at its first
                // sample and kept between rounds
                if (m_disk && sample % K == 0) {
                    pathtrace::Pcg32 prng =
                        pathtrace::Pcg32::forPath(strataSeed, (sample / K) * pixels + p);
                    *strata = sampling::BlockStrata<2>::draw(prng);
                }
                const int stratum = int(sample % K);
                // x lit (cos > 0, not shadowed): queue Bssrdf(x → P) with Ft·cos⁺·k, k the
                // estimator's factor of f(x): the MIS weight over the density, or the area
                auto add = [&](const sampling::SurfacePoint& x, double cosL, double k) {
                    if (!m_geo->convex()) { // a shadow ray toward the light
                        shadow.clear();
                        surface.intersectAll(x.x + eps * x.n, m_light, eps, far, shadow);
                        if (!shadow.empty()) return;
                    }
                    Pending q;
                    q.q.xo = glm::vec3(at.x - x.x);
                    q.q.wi = glm::vec3(m_view ? x.n : m_light);
                    q.q.wo = glm::vec3(at.n);
                    q.factor = fresnelTransmittance(cosL, eta) * cosL * k;
                    out.push_back(q);
                };
                if (m_disk) {
                    // stratified: the strategy with the radius, and the angle; one probe, or
                    // four along every axis (AxisScheme::All), each hit weighted by
                    // weightOverPdf (disk_sampling.h)
                    const double u0 = strata->u(0, stratum, rng.uniform());
                    const double u1 = strata->u(1, stratum, rng.uniform());
                    std::array<sampling::Probe, 4> probes;
                    const int np = m_disk->probes(f, u0, u1, probes);
                    for (int i = 0; i < np; ++i) {
                        const sampling::Probe& probe = probes[size_t(i)];
                        hits.clear();
                        m_disk->probeHits(surface, f, probe, hits);
                        for (const sampling::SurfaceHit& h : hits) {
                            const double cosL = glm::dot(h.point.n, m_light);
                            if (!(cosL > 0)) continue; // unlit: no contribution, no pdf needed
                            const double k = m_disk->weightOverPdf(f, probe, h.point.x, h.point.n);
                            if (k > 0) add(h.point, cosL, k);
                        }
                    }
                } else {
                    // independent samples (stratified.h says why this one is not stratified)
                    const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
                    const sampling::SurfacePoint x = m_geo->area().sampleArea(u0, u1, u2);
                    const double cosL = glm::dot(x.n, m_light);
                    if (cosL > 0) add(x, cosL, m_geo->area().area());
                }
                m_pendingCount[p * size_t(n) + size_t(k)] = uint32_t(out.size() - before);
            }
        });
        std::vector<bssrdf::Query> queries;
        size_t total = 0;
        for (const auto& v : pending)
            total += v.size();
        queries.reserve(total);
        for (const auto& v : pending)
            for (const Pending& q : v)
                queries.push_back(q.q);
        const std::vector<glm::dvec3> values =
            bssrdf::evaluateQueries(m_program, *m_model, m_values, m_builtins, queries);
        size_t i = 0;
        for (size_t p = 0; p < pixels; ++p) {
            if (!m_hit[p]) continue;
            // the view's radiance: E0 and the exit transmittance Ft(η, cos θo)/π
            glm::dvec3 scale(1.0);
            if (m_view) {
                const double cosO =
                    std::min(1.0, std::abs(glm::dot(m_shading[p].n, m_toCamera[p])));
                scale = m_irradiance * (fresnelTransmittance(cosO, eta) / std::numbers::pi);
            }
            const Pending* q = pending[p].data();
            for (int k = 0; k < n; ++k) {
                glm::dvec3 F(0.0);
                for (uint32_t j = m_pendingCount[p * size_t(n) + size_t(k)]; j > 0; --j)
                    F += values[i++] * (q++)->factor;
                F *= scale;
                const bool blockEnds = (s0 + uint64_t(k) + 1) % K == 0;
                for (int c = 0; c < 3; ++c) {
                    const size_t at = 3 * p + size_t(c);
                    m_sum[at] += F[c];
                    m_sumSq[at] += F[c] * F[c];
                    if (!m_disk) continue;
                    m_blockPartial[at] += F[c];
                    if (blockEnds) {
                        m_blockSumSq[at] += m_blockPartial[at] * m_blockPartial[at];
                        m_blockPartial[at] = 0;
                    }
                }
            }
        }
        m_evaluations += queries.size();
        m_samples += uint64_t(n);
        done += n;
    }
    m_seconds += clock.ms() / 1000.0;
}

litsphere::Image ImageIntegrator::image() const {
    litsphere::Image img;
    img.width = m_setup.width;
    img.height = m_setup.height;
    const size_t pixels = m_hit.size();
    img.mean.assign(3 * pixels, 0.0f);
    img.variance.assign(3 * pixels, 0.0f);
    img.samples = m_samples * pixels;
    if (m_samples == 0 || m_sum.size() != 3 * pixels) return img;
    const double n = double(m_samples);
    for (size_t i = 0; i < 3 * pixels; ++i) {
        img.mean[i] = float(m_sum[i] / n);
        // stratified blocks (disk; the whole blocks' Σ B is Σ F less the current block's) or
        // independent samples (uniform): stratified.h
        img.variance[i] = float(
            m_disk ? sampling::blockVarianceOfMean(m_samples, m_sum[i], m_sumSq[i],
                                                   m_sum[i] - m_blockPartial[i], m_blockSumSq[i])
                   : sampling::independentVarianceOfMean(m_samples, m_sum[i], m_sumSq[i]));
    }
    return img;
}

} // namespace integrate
