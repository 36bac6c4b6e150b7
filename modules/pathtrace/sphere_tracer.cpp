// pathtrace/sphere_tracer: paths on the analytic sphere (see sphere_tracer.h), its pixel
// footprints, and the run.
#include "pathtrace/sphere_tracer.h"

#include "core/core.h"
#include "pathtrace/rng.h"
#include "pathtrace/sampling.h"
#include "pathtrace/sphere_walk.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace pathtrace {
namespace {

using walk::Hit;

// 32-point Gauss–Legendre nodes and weights on [0, 1] (Newton on P_32).
struct GaussRule {
    static constexpr int n = 32;
    double x[n], w[n];
    GaussRule() {
        for (int i = 0; i < n; ++i) {
            double z = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0;
            for (int it = 0; it < 100; ++it) {
                double p0 = 1, p1 = 0;
                for (int k = 1; k <= n; ++k) {
                    const double p2 = p1;
                    p1 = p0;
                    p0 = ((2.0 * k - 1) * z * p1 - (k - 1.0) * p2) / k;
                }
                dp = n * (z * p0 - p1) / (z * z - 1);
                const double dz = p0 / dp;
                z -= dz;
                if (std::fabs(dz) < 1e-15) break;
            }
            x[i] = 0.5 - 0.5 * z;
            w[i] = 1.0 / ((1 - z * z) * dp * dp);
        }
    }
};

// asin(y / c) with the ratio clamped to [−1, 1] (c > 0).
double asinRatio(double y, double c) {
    const double r = y / c;
    return r >= 1.0 ? 0.5 * std::numbers::pi : (r <= -1.0 ? -0.5 * std::numbers::pi : std::asin(r));
}

struct SphereGeo {
    double R;
    bool hit(const Dir& x, const Dir& u, double& s, Hit& h) const {
        const double b = walk::dot(x, u);
        const double negC = std::max(0.0, R * R - walk::dot(x, x)); // R² − |x|² >= 0 inside
        const double sq = std::sqrt(b * b + negC);
        const double t = b > 0.0 ? negC / (b + sq) : sq - b; // far root, without cancellation
        if (s < t) return false;
        Dir p = walk::madd(x, u, t);
        p = walk::mul(p, R / std::sqrt(walk::dot(p, p))); // back onto the sphere
        h.p = p;
        h.n = walk::mul(p, 1.0 / R);
        h.t = t;
        h.cosI = walk::dot(u, h.n);
        if (!(h.cosI > 0.0)) h.cosI = sq / R; // grazing: the chord's exact cosine
        return true;
    }
    Dir reflectStart(const Hit& h) const { return h.p; }
};

struct SphereScene {
    double R;
    Dir light, e1, e2; // light direction and a frame of its perpendicular plane
    OrthoCamera cam;
    const std::vector<double>* footprint;
};

template <bool Isotropic>
ExitRecord traceSpherePath(const walk::Consts& c, const SphereScene& sc, Pcg32 rng) {
    ExitRecord r;
    double a, b;
    for (;;) { // uniform in the unit disc
        a = 2.0 * rng.uniform() - 1.0;
        b = 2.0 * rng.uniform() - 1.0;
        if (a * a + b * b < 1.0) break;
    }
    const double rho2 = a * a + b * b;
    const double h = std::sqrt(1.0 - rho2);
    const Dir n = walk::normalized({a * sc.e1.x + b * sc.e2.x + h * sc.light.x,
                                    a * sc.e1.y + b * sc.e2.y + h * sc.light.y,
                                    a * sc.e1.z + b * sc.e2.z + h * sc.light.z});
    const double cosI = std::min(1.0, walk::dot(n, sc.light));
    r.hit = 1.0;
    const double f = fresnelDielectric(cosI, c.eta);
    r.specular = f;
    Dir u;
    if (!(f < 1.0) || !walk::refractIn(sc.light, n, cosI, c.eta, u)) {
        r.specular = 1.0;
        return r;
    }
    const SphereGeo geo{sc.R};
    Hit out;
    if (walk::walk<Isotropic>(c, geo, rng, walk::mul(n, sc.R), u, 1.0 - f, r, out)) {
        if (out.p.z > 0.0) { // visible to the camera: n(xo)·z > 0
            const int p = sc.cam.pixelOf(out.p.x, out.p.y);
            if (p >= 0 && (*sc.footprint)[static_cast<size_t>(p)] > 0) r.pixel = p;
        }
    }
    return r;
}

} // namespace

double sphereAreaOver(double R, double x0, double x1, double y0, double y1) {
    static const GaussRule gl;
    x0 = std::max(x0, -R);
    x1 = std::min(x1, R);
    y0 = std::max(y0, -R);
    y1 = std::min(y1, R);
    if (!(x0 < x1) || !(y0 < y1)) return 0.0;
    double cuts[6];
    int nc = 0;
    cuts[nc++] = x0;
    cuts[nc++] = x1;
    for (double y : {y0, y1}) {
        const double k = std::sqrt(std::max(0.0, R * R - y * y));
        for (double xc : {-k, k})
            if (xc > x0 && xc < x1) cuts[nc++] = xc;
    }
    for (int a = 1; a < nc; ++a) // insertion sort (std::sort on 6 doubles trips GCC 12's
        for (int b = a; b > 0 && cuts[b] < cuts[b - 1]; --b) // -Warray-bounds)
            std::swap(cuts[b], cuts[b - 1]);
    double area = 0.0;
    for (int piece = 0; piece + 1 < nc; ++piece) {
        const double a = cuts[piece], len = cuts[piece + 1] - a;
        if (!(len > 0)) continue;
        double sum = 0.0;
        for (int i = 0; i < GaussRule::n; ++i) {
            const double t = gl.x[i];
            const double x = a + len * t * t * (3.0 - 2.0 * t);
            const double jac = len * 6.0 * t * (1.0 - t);
            const double cx = std::sqrt(std::max(0.0, R * R - x * x));
            if (!(cx > 0)) continue;
            sum += gl.w[i] * jac * (asinRatio(y1, cx) - asinRatio(y0, cx));
        }
        area += R * sum;
    }
    return area;
}

uint64_t litSpherePaths(const LitSphereSetup& s) {
    validate(s);
    const OrthoCamera cam(s, s.radiusMm);
    uint64_t covered = 0;
    for (int j = 0; j < s.height; ++j)
        for (int i = 0; i < s.width; ++i) {
            const double x = cam.centreX(i), y = cam.centreY(j);
            if (x * x + y * y < s.radiusMm * s.radiusMm) ++covered;
        }
    return s.samplesPerPixel * covered;
}

PixelGeometry sphereFootprints(const LitSphereSetup& s) {
    validate(s);
    const double R = s.radiusMm;
    const OrthoCamera cam(s, R);
    const auto l = unitLight(s);
    PixelGeometry g;
    const size_t n = static_cast<size_t>(s.width) * static_cast<size_t>(s.height);
    g.footprint.assign(n, 0.0);
    g.cosLight.assign(n, 0.0f);
    for (int j = 0; j < s.height; ++j)
        for (int i = 0; i < s.width; ++i) {
            const double x = cam.centreX(i), y = cam.centreY(j);
            const double r2 = x * x + y * y;
            if (!(r2 < R * R)) continue;
            const size_t p = static_cast<size_t>(j) * static_cast<size_t>(s.width) + i;
            g.footprint[p] = sphereAreaOver(R, x - 0.5 * cam.dx, x + 0.5 * cam.dx, y - 0.5 * cam.dy,
                                            y + 0.5 * cam.dy);
            const double z = std::sqrt(R * R - r2);
            g.cosLight[p] = static_cast<float>((x * l[0] + y * l[1] + z * l[2]) / R);
        }
    return g;
}

Image traceLitSphere(const std::array<Medium, 3>& media, const LitSphereSetup& setup,
                     const std::function<void(uint64_t done)>& progress,
                     const std::atomic<bool>* cancel, const TraceOptions& options,
                     ImageStats* stats) {
    static const char* names[3] = {"medium (red)", "medium (green)", "medium (blue)"};
    for (int c = 0; c < 3; ++c)
        validate(media[static_cast<size_t>(c)], names[c]);
    validate(setup);
    validate(options);
    core::Stopwatch clock;
    const uint64_t paths = litSpherePaths(setup);
    const PixelGeometry px = sphereFootprints(setup);
    const auto l = unitLight(setup);
    SphereScene sc{setup.radiusMm, {l[0], l[1], l[2]}, {}, {}, OrthoCamera(setup, setup.radiusMm),
                   &px.footprint};
    // A frame of the plane perpendicular to the light (Frisvad-style branch on the larger axis).
    const Dir helper = std::fabs(l[0]) < 0.9 ? Dir{1, 0, 0} : Dir{0, 1, 0};
    const double k = walk::dot(helper, sc.light);
    sc.e1 = walk::normalized(walk::madd(helper, sc.light, -k));
    sc.e2 = {sc.light.y * sc.e1.z - sc.light.z * sc.e1.y,
             sc.light.z * sc.e1.x - sc.light.x * sc.e1.z,
             sc.light.x * sc.e1.y - sc.light.y * sc.e1.x};
    std::array<walk::Consts, 3> consts;
    for (int c = 0; c < 3; ++c)
        consts[static_cast<size_t>(c)] =
            walk::makeConsts(media[static_cast<size_t>(c)], options, 1.0);
    const uint64_t seed = setup.seed;
    const ChunkTracer trace = [&](uint64_t first, uint64_t count, ExitRecord* out,
                                  const std::atomic<bool>* stop) -> uint64_t {
        for (int c = 0; c < 3; ++c) {
            const walk::Consts& k3 = consts[static_cast<size_t>(c)];
            const bool iso = media[static_cast<size_t>(c)].g == 0.0;
            ExitRecord* o = out + static_cast<uint64_t>(c) * count;
            for (uint64_t i = 0; i < count; ++i) {
                if ((i & 255u) == 0 && stop && stop->load(std::memory_order_relaxed)) return 0;
                const Pcg32 rng = Pcg32::forPath(seed, streamIndex(c, first + i));
                o[i] =
                    iso ? traceSpherePath<true>(k3, sc, rng) : traceSpherePath<false>(k3, sc, rng);
            }
        }
        return count;
    };
    const ImageTally t =
        runImageChunks(paths, setup.threads, px.footprint.size(), trace, progress, cancel);
    const double R = setup.radiusMm;
    Image img =
        finalizeImage(t, px, setup.width, setup.height, std::numbers::pi * R * R, 1.0, stats);
    if (stats) stats->seconds = clock.ms() / 1000.0;
    return img;
}

} // namespace pathtrace
