// pathtrace/mesh_tracer: paths through an Embree mesh (see mesh_tracer.h).
#include "pathtrace/mesh_tracer.h"

#include "core/core.h"
#include "pathtrace/mesh_scene.h"
#include "pathtrace/rng.h"
#include "pathtrace/sampling.h"
#include "pathtrace/sphere_walk.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <thread>
#include <vector>

namespace pathtrace {
namespace {

using walk::Hit;

constexpr double kCameraZ = 1.0;     // camera rays start above the normalised mesh (|z| <= 0.5)
constexpr double kVisibleEps = 1e-4; // |z_hit − xo.z| for "xo is the camera ray's first hit"

Dir toDir(const std::array<double, 3>& a) {
    return {a[0], a[1], a[2]};
}

struct MeshGeo {
    const MeshScene* scene;
    double eps;
    // Looks ε beyond s: a collision that would land within ε of the surface is pulled back to
    // ε inside (distance to the face's plane), so that no walk starts from a point Embree's float
    // rays cannot tell from the surface (from there a ray can miss the face it starts on and the
    // path leaks out).
    bool hit(const Dir& x, const Dir& u, double& s, Hit& h) const {
        const double org[3] = {x.x, x.y, x.z}, dir[3] = {u.x, u.y, u.z};
        double t;
        uint32_t prim;
        if (!scene->intersect(org, dir, 0.0, s + eps, t, prim)) return false;
        if (t > s) { // pull back to a distance >= ε from the face's plane where possible
            const double cosN = walk::dot(u, toDir(scene->normal(prim)));
            if (cosN > 0) s = std::max(0.0, std::min(s, t - eps / cosN));
            return false;
        }
        h.t = t;
        h.p = walk::madd(x, u, t);
        h.n = toDir(scene->normal(prim));
        h.cosI = walk::dot(u, h.n);
        return true;
    }
    Dir reflectStart(const Hit& h) const { return walk::madd(h.p, h.n, -eps); }
};

struct MeshCtx {
    const MeshScene* scene;
    Dir light, e1, e2;
    double lo1, hi1, lo2, hi2, top; // source rectangle in (e1, e2), start height along light
    OrthoCamera cam;
    const std::vector<double>* footprint;
};

// The pixel of a camera-visible exit at p (−1 when hidden or uncovered).
int visiblePixel(const MeshCtx& m, const Dir& p) {
    const int pix = m.cam.pixelOf(p.x, p.y);
    if (pix < 0 || !((*m.footprint)[static_cast<size_t>(pix)] > 0)) return -1;
    const double org[3] = {p.x, p.y, kCameraZ}, dir[3] = {0.0, 0.0, -1.0};
    double t;
    uint32_t prim;
    if (!m.scene->intersect(org, dir, 0.0, std::numeric_limits<double>::infinity(), t, prim))
        return -1;
    if (!(m.scene->normal(prim)[2] > 0.0)) return -1;
    return std::fabs((kCameraZ - t) - p.z) < kVisibleEps ? pix : -1;
}

template <bool Isotropic>
ExitRecord traceMeshPath(const walk::Consts& c, const MeshCtx& m, double eps, Pcg32 rng) {
    ExitRecord r;
    const double a = m.lo1 + (m.hi1 - m.lo1) * rng.uniform();
    const double b = m.lo2 + (m.hi2 - m.lo2) * rng.uniform();
    const Dir org = walk::madd(walk::madd(walk::mul(m.light, m.top), m.e1, a), m.e2, b);
    const double o[3] = {org.x, org.y, org.z}, d[3] = {-m.light.x, -m.light.y, -m.light.z};
    double t;
    uint32_t prim;
    if (!m.scene->intersect(o, d, 0.0, std::numeric_limits<double>::infinity(), t, prim))
        return r; // missed the object
    const Dir n = toDir(m.scene->normal(prim));
    const double cosI = std::min(1.0, walk::dot(n, m.light));
    // A first hit from outside that faces away: the ray grazes a silhouette edge, where float
    // rounding can order the back face first. Counted as a miss (such rays would meet the front
    // face at cos θi ≈ 0, where F ≈ 1: a negligible, measure-zero share of the power).
    if (!(cosI > 0.0)) return r;
    r.hit = 1.0;
    const double f = fresnelDielectric(cosI, c.eta);
    r.specular = f;
    Dir u;
    if (!(f < 1.0) || !walk::refractIn(m.light, n, cosI, c.eta, u)) {
        r.specular = 1.0;
        return r;
    }
    const Dir p = walk::madd(org, m.light, -t);
    const MeshGeo geo{m.scene, eps};
    Hit out;
    if (walk::walk<Isotropic>(c, geo, rng, walk::madd(p, n, -eps), u, 1.0 - f, r, out))
        r.pixel = visiblePixel(m, out.p);
    return r;
}

// Runs f(row) for every row on `threads` threads (0: all), rows interleaved.
template <class F> void forRows(int rows, int threads, const F& f) {
    const int hw = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    const int n = std::clamp(threads > 0 ? threads : hw, 1, std::max(1, rows));
    std::vector<std::thread> pool;
    for (int k = 1; k < n; ++k)
        pool.emplace_back([&, k] {
            for (int j = k; j < rows; j += n)
                f(j);
        });
    for (int j = 0; j < rows; j += n)
        f(j);
    for (auto& th : pool)
        th.join();
}

} // namespace

struct LitMesh::FootprintCache {
    std::mutex mutex;
    bool valid = false;
    int width = 0, height = 0, subsamples = 0;
    std::array<double, 3> light{};
    PixelGeometry geometry;
};

LitMesh::LitMesh(Mesh mesh, std::string name)
    : m_mesh(std::move(mesh)), m_name(std::move(name)),
      m_cache(std::make_unique<FootprintCache>()) {
    checkClosedOutward(m_mesh, m_name);
    m_extent = normalizeMesh(m_mesh, m_name);
    m_scene = std::make_unique<MeshScene>(m_mesh);
}
LitMesh::~LitMesh() = default;
LitMesh::LitMesh(LitMesh&&) noexcept = default;
LitMesh& LitMesh::operator=(LitMesh&&) noexcept = default;

LitMesh loadLitMesh(const std::filesystem::path& path) {
    return LitMesh(loadObj(path), path.string());
}

PixelGeometry LitMesh::footprintsUnits(const LitSphereSetup& s, const TraceOptions& o) const {
    validate(s);
    validate(o);
    const auto l = unitLight(s);
    const int k = o.footprintSubsamples;
    std::lock_guard lock(m_cache->mutex);
    if (m_cache->valid && m_cache->width == s.width && m_cache->height == s.height &&
        m_cache->subsamples == k && m_cache->light == l)
        return m_cache->geometry;
    const OrthoCamera cam(s, 0.5);
    PixelGeometry g;
    const size_t n = static_cast<size_t>(s.width) * static_cast<size_t>(s.height);
    g.footprint.assign(n, 0.0);
    g.cosLight.assign(n, 0.0f);
    const double dir[3] = {0.0, 0.0, -1.0};
    const double subArea = cam.dx * cam.dy / (double(k) * k);
    forRows(s.height, s.threads, [&](int j) {
        for (int i = 0; i < s.width; ++i) {
            const size_t p = static_cast<size_t>(j) * static_cast<size_t>(s.width) + i;
            double t;
            uint32_t prim;
            const double centre[3] = {cam.centreX(i), cam.centreY(j), kCameraZ};
            if (!m_scene->intersect(centre, dir, 0.0, std::numeric_limits<double>::infinity(), t,
                                    prim))
                continue;
            const auto& nc = m_scene->normal(prim);
            g.cosLight[p] = static_cast<float>(nc[0] * l[0] + nc[1] * l[1] + nc[2] * l[2]);
            double area = 0.0;
            for (int b = 0; b < k; ++b)
                for (int a = 0; a < k; ++a) {
                    const double org[3] = {centre[0] + ((a + 0.5) / k - 0.5) * cam.dx,
                                           centre[1] - ((b + 0.5) / k - 0.5) * cam.dy, kCameraZ};
                    if (!m_scene->intersect(org, dir, 0.0, std::numeric_limits<double>::infinity(),
                                            t, prim))
                        continue;
                    const double nz = std::fabs(m_scene->normal(prim)[2]);
                    if (nz > 0) area += subArea / nz;
                }
            g.footprint[p] = area;
        }
    });
    m_cache->valid = true;
    m_cache->width = s.width;
    m_cache->height = s.height;
    m_cache->subsamples = k;
    m_cache->light = l;
    m_cache->geometry = g;
    return g;
}

PixelGeometry LitMesh::footprints(const LitSphereSetup& s, const TraceOptions& o) const {
    PixelGeometry g = footprintsUnits(s, o);
    const double scale = 2.0 * s.radiusMm;
    for (double& a : g.footprint)
        a *= scale * scale;
    return g;
}

uint64_t LitMesh::pathCount(const LitSphereSetup& s, const TraceOptions& o) const {
    const PixelGeometry g = footprintsUnits(s, o);
    uint64_t covered = 0;
    for (double a : g.footprint)
        covered += a > 0 ? 1 : 0;
    return s.samplesPerPixel * covered;
}

Image LitMesh::trace(const std::array<Medium, 3>& media, const LitSphereSetup& setup,
                     const std::function<void(uint64_t done)>& progress,
                     const std::atomic<bool>* cancel, const TraceOptions& options,
                     ImageStats* stats) const {
    static const char* names[3] = {"medium (red)", "medium (green)", "medium (blue)"};
    for (int c = 0; c < 3; ++c)
        validate(media[static_cast<size_t>(c)], names[c]);
    validate(setup);
    validate(options);
    core::Stopwatch clock;
    const double scale = 2.0 * setup.radiusMm; // mm per unit
    const PixelGeometry px = footprintsUnits(setup, options);
    uint64_t covered = 0;
    for (double a : px.footprint)
        covered += a > 0 ? 1 : 0;
    const uint64_t paths = setup.samplesPerPixel * covered;
    const auto l = unitLight(setup);
    MeshCtx m{m_scene.get(),           {l[0], l[1], l[2]}, {}, {}, 0, 0, 0, 0, 0,
              OrthoCamera(setup, 0.5), &px.footprint};
    const Dir helper = std::fabs(l[0]) < 0.9 ? Dir{1, 0, 0} : Dir{0, 1, 0};
    m.e1 = walk::normalized(walk::madd(helper, m.light, -walk::dot(helper, m.light)));
    m.e2 = {m.light.y * m.e1.z - m.light.z * m.e1.y, m.light.z * m.e1.x - m.light.x * m.e1.z,
            m.light.x * m.e1.y - m.light.y * m.e1.x};
    m.lo1 = m.lo2 = std::numeric_limits<double>::infinity();
    m.hi1 = m.hi2 = -m.lo1;
    double along = -std::numeric_limits<double>::infinity();
    for (const auto& v : m_mesh.vertices) {
        const Dir p{v[0], v[1], v[2]};
        const double a = walk::dot(p, m.e1), b = walk::dot(p, m.e2);
        m.lo1 = std::min(m.lo1, a);
        m.hi1 = std::max(m.hi1, a);
        m.lo2 = std::min(m.lo2, b);
        m.hi2 = std::max(m.hi2, b);
        along = std::max(along, walk::dot(p, m.light));
    }
    // A margin of 1e-6 units so that faces on the rectangle's border are inside it.
    m.lo1 -= 1e-6;
    m.lo2 -= 1e-6;
    m.hi1 += 1e-6;
    m.hi2 += 1e-6;
    m.top = along + 1.0;
    const double sourceArea = (m.hi1 - m.lo1) * (m.hi2 - m.lo2); // units²
    std::array<walk::Consts, 3> consts;
    std::array<double, 3> eps;
    for (size_t c = 0; c < 3; ++c) {
        consts[c] = walk::makeConsts(media[c], options, scale);
        eps[c] = std::clamp(0.01 * consts[c].invSigmaT, 2e-6, 1e-5);
    }
    const uint64_t seed = setup.seed;
    const ChunkTracer trace = [&](uint64_t first, uint64_t count, ExitRecord* out,
                                  const std::atomic<bool>* stop) -> uint64_t {
        for (int c = 0; c < 3; ++c) {
            const walk::Consts& k3 = consts[static_cast<size_t>(c)];
            const double e = eps[static_cast<size_t>(c)];
            const bool iso = media[static_cast<size_t>(c)].g == 0.0;
            ExitRecord* o = out + static_cast<uint64_t>(c) * count;
            for (uint64_t i = 0; i < count; ++i) {
                if ((i & 255u) == 0 && stop && stop->load(std::memory_order_relaxed)) return 0;
                const Pcg32 rng = Pcg32::forPath(seed, streamIndex(c, first + i));
                o[i] =
                    iso ? traceMeshPath<true>(k3, m, e, rng) : traceMeshPath<false>(k3, m, e, rng);
            }
        }
        return count;
    };
    const ImageTally t =
        runImageChunks(paths, setup.threads, px.footprint.size(), trace, progress, cancel);
    Image img = finalizeImage(t, px, setup.width, setup.height, sourceArea, scale * scale, stats);
    if (stats) stats->seconds = clock.ms() / 1000.0;
    return img;
}

} // namespace pathtrace
