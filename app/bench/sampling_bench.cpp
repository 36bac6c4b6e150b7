// bench sampling (bench.h): equal-time relative RMSE of the BSSRDF-integrated lit picture by
// disk importance sampling against uniform area sampling (integrate/integrate.h), on the lit
// sphere and on the bunny, Marble and Skin1, for each probe-axis scheme; then, per scheme, the
// lowest ratio over the presets on each scene against the targets (10x sphere, 5x bunny).
//   Reference: the disk estimator (every axis in each sample, another seed) run for
//   `referenceFactor` × the budget; its own relative standard error is printed beside, so a
//   reader can tell how much of a measured error is the reference's.
//   rel_rmse = √((Σ_p,c (x − ref)² − Σ_p,c var_ref) / Σ_p,c ref²) over the pixels (the
//   reference's own variance of the mean taken off: the error against the truth).
//   Each method runs whole samples per pixel until `seconds` have passed (at least one), in one
//   process on one machine, so the ratio compares like with like.
#include "bench/bench.h"

#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"
#include "integrate/integrate.h"
#include "mesh/mesh.h"
#include "pipeline/model_stages.h"
#include "pipeline/workbench.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

namespace app {
namespace fs = std::filesystem;

namespace {

struct Run {
    litsphere::Image image;
    uint64_t spp = 0;
    double seconds = 0;
};

Run runFor(integrate::ImageIntegrator& ig, const bssrdf::ModelEntry& e, const bssrdf::Builtins& b,
           const integrate::Settings& s, double seconds) {
    ig.setModel(e.programs.at("pencil_profile.comp").id(), *e.model, e.values, b, s, e.displayPath);
    core::Stopwatch clock;
    do {
        ig.step(1);
    } while (clock.ms() < 1000 * seconds);
    return {ig.image(), ig.samplesPerPixelDone(), clock.ms() / 1000};
}

// The error against the truth: Σ(x − ref)² estimates Σ(x − truth)² + Σ var_ref for a reference
// independent of x, so the reference's own variance is taken off.
double relRmse(const litsphere::Image& x, const litsphere::Image& ref) {
    double num = 0, den = 0, refVar = 0;
    for (size_t i = 0; i < ref.mean.size(); ++i) {
        const double d = double(x.mean[i]) - double(ref.mean[i]);
        num += d * d;
        den += double(ref.mean[i]) * double(ref.mean[i]);
        if (std::isfinite(ref.variance[i])) refVar += double(ref.variance[i]);
    }
    return den > 0 ? std::sqrt(std::max(0.0, num - refVar) / den) : 0.0;
}

double relStdError(const litsphere::Image& x) {
    double var = 0, den = 0;
    for (size_t i = 0; i < x.mean.size(); ++i) {
        if (std::isfinite(x.variance[i])) var += double(x.variance[i]);
        den += double(x.mean[i]) * double(x.mean[i]);
    }
    return den > 0 ? std::sqrt(var / den) : 0.0;
}

} // namespace

int benchSampling(const fs::path& root, double seconds, int size, double referenceFactor) {
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, {root / "materials" / "dipole.bssrdf"});
    const bssrdf::ModelEntry& e = wb.library().entries().at(0);
    if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    std::printf("bench sampling: dipole, %dx%d pixels, light (0.5, 0.5, 0.71), %.3g s per method "
                "and case, reference %.3g s of disk sampling along every axis (another seed)\n",
                size, size, seconds, seconds * referenceFactor);
    litsphere::Setup setup;
    setup.width = setup.height = size;
    setup.lightDir[0] = 0.5;
    setup.lightDir[1] = 0.5;
    setup.lightDir[2] = 0.7071;
    struct Scene {
        const char* name;
        double radiusMm;
    };
    const mesh::Mesh bunny = mesh::loadObj(root / "third_party/bunny/bunny.obj");
    const std::array<sampling::AxisScheme, 4> schemes = {
        sampling::AxisScheme::All, sampling::AxisScheme::Uniform, sampling::AxisScheme::Pbrt,
        sampling::AxisScheme::NormalOnly};
    // per scene and scheme, the lowest ratio over the presets (the targets' summary)
    std::array<std::array<double, 4>, 2> lowest;
    for (auto& row : lowest)
        row.fill(INFINITY);
    int scene = 0;
    for (const Scene sc : {Scene{"sphere", 10.0}, Scene{"bunny", 25.0}}) {
        setup.radiusMm = sc.radiusMm;
        std::unique_ptr<integrate::ImageIntegrator> ig =
            std::string(sc.name) == "sphere"
                ? std::make_unique<integrate::ImageIntegrator>(setup)
                : std::make_unique<integrate::ImageIntegrator>(setup, bunny, "bunny.obj");
        for (const char* preset : {"Marble", "Skin1"}) {
            MaterialSettings m;
            wb.applyPreset(m, preset);
            const bssrdf::Builtins b = builtinsOf(effectiveParams(e, m));
            integrate::Settings ref;
            ref.sampling = integrate::Sampling::Disk;
            ref.axes = sampling::AxisScheme::All;
            ref.seed = 12345;
            const Run r = runFor(*ig, e, b, ref, seconds * referenceFactor);
            integrate::Settings uni;
            uni.sampling = integrate::Sampling::Uniform;
            const Run u = runFor(*ig, e, b, uni, seconds);
            const double ue = relRmse(u.image, r.image);
            for (size_t j = 0; j < schemes.size(); ++j) {
                const sampling::AxisScheme axes = schemes[j];
                integrate::Settings d;
                d.sampling = integrate::Sampling::Disk;
                d.axes = axes;
                const Run k = runFor(*ig, e, b, d, seconds);
                const double de = relRmse(k.image, r.image);
                std::printf("scene=%s preset=%s axes=%s seconds=%.3g uniform_rel_rmse=%.4g "
                            "disk_rel_rmse=%.4g ratio=%.3g   (spp uniform %llu, disk %llu; "
                            "reference rel se %.2g)\n",
                            sc.name, preset, core::nameOf(axes), seconds, ue, de,
                            de > 0 ? ue / de : 0.0, (unsigned long long)u.spp,
                            (unsigned long long)k.spp, relStdError(r.image));
                std::fflush(stdout);
                lowest[size_t(scene)][j] =
                    std::min(lowest[size_t(scene)][j], de > 0 ? ue / de : 0.0);
            }
        }
        ++scene;
    }
    // the targets: at least 10x on the sphere and 5x on the bunny, for every preset
    for (size_t j = 0; j < schemes.size(); ++j) {
        const bool met = lowest[0][j] >= 10 && lowest[1][j] >= 5;
        std::printf(
            "target axes=%s sphere_min_ratio=%.3g (>= 10) bunny_min_ratio=%.3g (>= 5): %s\n",
            core::nameOf(schemes[j]), lowest[0][j], lowest[1][j], met ? "met" : "not met");
    }
    return 0;
}

} // namespace app
