// bench convergence (bench.h): relative RMSE against time, log–log, of the renderers of the
// Render panel on the default scene (bunny, directional light, the dipole on Marble): the
// hierarchical point-cloud render at several ε and brute force (each one deterministic image:
// one point each), and the Monte Carlo render by uniform area sampling and by disk probe rays
// with each axis scheme (a point after 1, 2, 4, … samples per pixel).
//   The converged image: the Monte Carlo render by disk probe rays (every axis in each sample,
//   another seed)
//   with `referenceSpp` samples per pixel; its own relative standard error is printed and each
//   Monte Carlo error has the reference's variance taken off (as bench sampling). The
//   point-cloud renders keep a floor: their point discretisation and shadow map against the
//   reference's exact shadow rays.
//   rel_rmse = √((Σ (x − ref)² − Σ var_ref) / Σ ref²) over the frame's pixels and the three
//   channels (every method is independent of the reference, so its variance is taken off).
//   Writes DIR/convergence.csv and DIR/convergence.png (the workbench's plot code, headless).
#include "bench/bench.h"

#include "core/core.h"
#include "core/fields.h"
#include "gl/gl.h"
#include "gui/report_png.h"
#include "integrate/integrate.h"
#include "pipeline/model_stages.h"
#include "pipeline/monte_carlo_stage.h"
#include "pipeline/workbench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace app {
namespace fs = std::filesystem;

namespace {

double relRmse(const std::vector<double>& x, const litsphere::Image& ref, bool takeOffRefVar) {
    double num = 0, den = 0, var = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        const double d = x[i] - double(ref.mean[i]);
        num += d * d;
        den += double(ref.mean[i]) * double(ref.mean[i]);
        if (std::isfinite(ref.variance[i])) var += double(ref.variance[i]);
    }
    if (takeOffRefVar) num = std::max(0.0, num - var);
    return den > 0 ? std::sqrt(num / den) : 0.0;
}

} // namespace

int benchConvergence(const fs::path& root, const ConvergenceBenchOptions& o) {
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, {root / "materials" / "dipole.bssrdf"});
    wb.applyPreset(wb.shared(), o.preset);
    SceneSettings& s = wb.scene().settings();
    s.render.width = o.width;
    s.render.height = o.height;
    s.points.points = o.points;
    wb.update();
    wb.finishScene();
    for (const auto& p : wb.scene().problems())
        throw core::Error(p);
    const SceneModelInput model = wb.sceneModelInput();
    const bssrdf::ModelEntry& e = *model.entry;
    const integrate::ViewPoints view = viewPointsOf(wb.scene());
    const double scale = double(model.builtins.scale);
    auto integrator = [&](integrate::Sampling sampling, sampling::AxisScheme axes, uint64_t seed) {
        auto ig = std::make_unique<integrate::ImageIntegrator>(wb.scene().mesh(), scale, s.meshFile,
                                                               view);
        integrate::Settings is;
        is.sampling = sampling;
        is.axes = axes;
        is.seed = seed;
        ig->setModel(e.programs.at("pencil_profile.comp").id(), *e.model, e.values, model.builtins,
                     is, e.displayPath);
        return ig;
    };
    std::printf("bench convergence: dipole, %s, bunny %dx%d, %zu points, converged image: disk "
                "probe rays (every axis in each sample) with %d spp\n",
                o.preset.c_str(), o.width, o.height, o.points, o.referenceSpp);
    auto ref = integrator(integrate::Sampling::Disk, sampling::AxisScheme::All, 777);
    ref->step(o.referenceSpp);
    const litsphere::Image refImg = ref->image();
    {
        double var = 0, den = 0;
        for (size_t i = 0; i < refImg.mean.size(); ++i) {
            var += refImg.variance[i];
            den += double(refImg.mean[i]) * refImg.mean[i];
        }
        std::printf("reference: %.1f s, relative standard error %.3g\n", ref->seconds(),
                    std::sqrt(var / den));
    }
    struct Curve {
        std::string name;
        std::vector<double> t, err;
    };
    std::vector<Curve> curves;
    std::ostringstream csv;
    csv << "method,seconds,rel_rmse,spp_or_eps\n";
    // the point-cloud renders: one image each (the frame's GPU time)
    Curve hier{"hierarchical (eps)", {}, {}};
    auto pointCloudPoint = [&](bool brute, float eps) {
        s.render.bruteForce = brute;
        s.render.eps = eps;
        wb.update();
        wb.finishScene();
        const render::Frame& f = wb.scene().frame();
        const double sec = (f.gbufferMs + f.profileMs + f.traverseMs) / 1000;
        const render::Readback rb = wb.scene().readback();
        std::vector<double> x(3 * rb.hdr.size());
        for (size_t p = 0; p < rb.hdr.size(); ++p)
            for (int c = 0; c < 3; ++c)
                x[3 * p + size_t(c)] = rb.hdr[p].w > 0.5f ? rb.hdr[p][c] : 0.0;
        const double err = relRmse(x, refImg, true);
        const char* name = brute ? "brute force" : "hierarchical";
        std::printf("method=%s eps=%g seconds=%.4g rel_rmse=%.4g\n", name, eps, sec, err);
        csv << name << "," << sec << "," << err << "," << eps << "\n";
        return std::pair{sec, err};
    };
    for (float eps : o.eps) {
        auto [t, err] = pointCloudPoint(false, eps);
        hier.t.push_back(t);
        hier.err.push_back(err);
    }
    { // in order of time, so the curve does not double back
        std::vector<size_t> k(hier.t.size());
        for (size_t i = 0; i < k.size(); ++i)
            k[i] = i;
        std::sort(k.begin(), k.end(), [&](size_t a, size_t b) { return hier.t[a] < hier.t[b]; });
        Curve sorted{hier.name, {}, {}};
        for (size_t i : k) {
            sorted.t.push_back(hier.t[i]);
            sorted.err.push_back(hier.err[i]);
        }
        curves.push_back(sorted);
    }
    {
        auto [t, err] = pointCloudPoint(true, 0.0f);
        curves.push_back({"brute force", {t}, {err}});
    }
    struct Mc {
        const char* name;
        integrate::Sampling sampling;
        sampling::AxisScheme axes;
    };
    for (const Mc m :
         {Mc{"uniform area", integrate::Sampling::Uniform, sampling::AxisScheme::Uniform},
          Mc{"disk, axes 1/3 each", integrate::Sampling::Disk, sampling::AxisScheme::Uniform},
          Mc{"disk, axes pbrt", integrate::Sampling::Disk, sampling::AxisScheme::Pbrt},
          Mc{"disk, normal only", integrate::Sampling::Disk, sampling::AxisScheme::NormalOnly},
          Mc{"disk, every axis", integrate::Sampling::Disk, sampling::AxisScheme::All}}) {
        auto ig = integrator(m.sampling, m.axes, 1);
        Curve c{m.name, {}, {}};
        for (int spp = 1; spp <= o.maxSpp; spp *= 2) {
            ig->step(int(spp - ig->samplesPerPixelDone()));
            const litsphere::Image img = ig->image();
            std::vector<double> x(img.mean.begin(), img.mean.end());
            const double err = relRmse(x, refImg, true);
            c.t.push_back(ig->seconds());
            c.err.push_back(err);
            std::printf("method=montecarlo sampling=%s spp=%d seconds=%.4g rel_rmse=%.4g\n", m.name,
                        spp, ig->seconds(), err);
            csv << "montecarlo " << m.name << "," << ig->seconds() << "," << err << "," << spp
                << "\n";
        }
        curves.push_back(c);
    }
    if (o.out.empty()) return 0;
    fs::create_directories(o.out);
    core::writeFile(fs::path(o.out) / "convergence.csv", csv.str());
    std::vector<plot::Series> series;
    for (size_t k = 0; k < curves.size(); ++k) {
        plot::Series ps;
        ps.label = curves[k].name;
        ps.x = curves[k].t;
        ps.y = curves[k].err;
        ps.color = plot::defaultColor(k);
        ps.marker = curves[k].t.size() == 1;
        ps.thickness = 2.0f;
        series.push_back(ps);
    }
    plot::Axis x = plot::autoRange(series, plot::Scale::Log, false);
    x.label = "seconds (this machine)";
    plot::Axis y = plot::autoRange(series, plot::Scale::Log, true);
    y.label = "relative RMSE";
    core::writeFile(fs::path(o.out) / "convergence.png",
                    plotPng(720, 460, series, x, y, "Render panel renderers: error against time",
                            "bunny, dipole on " + o.preset + ", against " +
                                std::to_string(o.referenceSpp) + " spp of disk sampling"));
    std::printf("wrote %s and %s\n", (fs::path(o.out) / "convergence.csv").c_str(),
                (fs::path(o.out) / "convergence.png").c_str());
    return 0;
}

} // namespace app
