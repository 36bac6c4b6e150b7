// `bssrdf-workbench integrate` (integrate_command.h).
#include "cli/integrate_command.h"
#include "cli/args.h"
#include "cli/command.h"

#include "cli/capture_commands.h"
#include "cli/interrupt.h"
#include "cli/options.h"
#include "cli/output.h"
#include "core/core.h"
#include "core/text.h"
#include "gl/gl.h"
#include "integrate/integrate.h"
#include "mesh/mesh.h"
#include "pathtrace/image_io.h"
#include "pipeline/lit_sphere_stage.h"
#include "pipeline/model_stages.h"
#include "pipeline/workbench.h"

#include <CLI/CLI.hpp>
#include <memory>

#include <cmath>
#include <cstdio>

namespace app {
namespace fs = std::filesystem;

namespace {

// One default per setting: the panel's and the estimator's.
const LitSphereSettings kLit;
const integrate::Settings kIntegrate;

bool parseWxH(const std::string& s, int& w, int& h) {
    const size_t x = s.find('x');
    if (x == std::string::npos) return false;
    char* end = nullptr;
    const long a = std::strtol(s.c_str(), &end, 10);
    if (end != s.c_str() + x) return false;
    const long b = std::strtol(s.c_str() + x + 1, &end, 10);
    if (end != s.c_str() + s.size()) return false;
    if (a < 1 || b < 1 || a > 8192 || b > 8192) return false;
    w = int(a);
    h = int(b);
    return true;
}

} // namespace

void addIntegrateOptions(CLI::App* cmd, IntegrateArgs& a) {
    const auto dflt = [](const std::string& v) { return " (default " + v + ")"; };
    a.light = defaultText(kLit.lightDir);
    a.size = std::to_string(kLit.size) + "x" + std::to_string(kLit.size);
    a.seed = kIntegrate.seed;
    a.energyLoss = kIntegrate.energyLoss;
    cmd->add_option("--mesh", a.mesh, "closed, outward-facing triangle mesh (OBJ)");
    addNumberOption(cmd, "--sphere", a.sphereMm, "the lit sphere of this radius in mm instead",
                    core::Limits{1e-3, 1e4});
    addNumberOption(cmd, "--radius", a.radiusMm,
                    "mesh: half its longest axis in mm" + dflt(defaultText(kLit.radiusMm)),
                    core::Limits{1e-3, 1e4});
    cmd->add_option("--model", a.model, "the .bssrdf model")->required();
    cmd->add_option("--preset", a.preset,
                    "material preset; a material is required: --preset, or both --sigma-a and "
                    "--sigma-s");
    cmd->add_option("--sigma-a", a.sigmaA, "absorption R,G,B in 1/mm");
    cmd->add_option("--sigma-s", a.sigmaS, "scattering R,G,B in 1/mm");
    addNumberOption(cmd, "--g", a.g, "Henyey-Greenstein mean cosine");
    addNumberOption(cmd, "--eta", a.eta, "relative index of refraction");
    cmd->add_option("--sampling", a.sampling, "uniform (area) or disk (probe rays)")->required();
    cmd->add_option("--axes", a.axes,
                    "disk: probe axes uniform, pbrt, normal or all (every axis in each sample)" +
                        dflt(std::string(core::nameOf(kIntegrate.axes))));
    addCountOption(cmd, "--spp", a.spp, "samples per pixel", core::Limits{1, 1e7})->required();
    cmd->add_option("--light", a.light, "direction towards the light x,y,z" + dflt(a.light));
    cmd->add_option("--size", a.size, "image WxH" + dflt(a.size));
    cmd->add_option("--seed", a.seed, "random seed" + dflt(std::to_string(a.seed)));
    addNumberOption(cmd, "--energy-loss", a.energyLoss,
                    "disk: energy given up beyond R_m" + dflt(defaultText(a.energyLoss)),
                    core::Limits{1e-9, 0.5});
    cmd->add_option("--out", a.out, "EXR file: R,G,B exitance and varR,varG,varB")->required();
    refuseIgnoredOptions(cmd, {{{"--energy-loss"},
                                [&a] { return a.sampling == "uniform"; },
                                "only with --sampling disk"}});
}

int runIntegrateCli(const fs::path& root, const IntegrateArgs& a) {
    if (a.mesh.empty() == !a.sphereMm)
        throw core::Error("--mesh", 0, "give exactly one of --mesh FILE.obj and --sphere MM");
    if (a.sphereMm && a.radiusMm)
        throw core::Error("--radius", 0, "only with --mesh (--sphere gives the radius)");
    integrate::Settings s;
    s.sampling = core::enumFromName<integrate::Sampling>(a.sampling, "--sampling", "");
    if (!a.axes.empty()) {
        s.axes = core::enumFromName<sampling::AxisScheme>(a.axes, "--axes", "");
        if (s.sampling != integrate::Sampling::Disk)
            throw core::Error("--axes", 0, "only with --sampling disk");
    }
    s.seed = a.seed;
    s.energyLoss = a.energyLoss;
    litsphere::Setup setup;
    setup.radiusMm = a.sphereMm ? *a.sphereMm : a.radiusMm.value_or(kLit.radiusMm);
    const glm::dvec3 light = parseRgb(a.light, "--light");
    if (!(std::isfinite(glm::dot(light, light)) && glm::dot(light, light) > 0))
        throw core::Error("--light", 0, "the light direction must be finite and non-zero");
    for (int i = 0; i < 3; ++i)
        setup.lightDir[i] = light[i];
    if (!parseWxH(a.size, setup.width, setup.height))
        throw core::Error("--size", 0, "expected WxH between 1 and 8192, got '" + a.size + "'");
    if (double(a.spp) * setup.width * setup.height > 1e11)
        throw core::Error("--spp", 0, "absurd sample count: spp x pixels > 10^11");
    checkOutput(a.out, "--out", ".exr");
    mesh::Mesh m;
    if (!a.mesh.empty()) m = mesh::loadObj(a.mesh); // core::Error naming the file

    const fs::path model = resolveModel(root, a.model);
    auto ctx = gl::createHeadlessContext(false);
    Workbench wb(root, false, {model});
    auto& e = wb.library().entries().at(0);
    if (e.problem) throw core::Error(e.problem->file, e.problem->line, e.problem->message);
    wb.shared() = settingsFromArgs(wb, a.preset, a.sigmaA, a.sigmaS, a.g, a.eta);
    wb.update();
    const ModelView& v = wb.view(e.displayPath);
    if (!v.effective) throw core::Error(e.displayPath, 0, v.materialProblem);
    const std::string name = a.mesh.empty() ? "sphere" : a.mesh;
    std::unique_ptr<integrate::ImageIntegrator> ig =
        a.mesh.empty() ? std::make_unique<integrate::ImageIntegrator>(setup)
                       : std::make_unique<integrate::ImageIntegrator>(setup, std::move(m), name);
    ig->setModel(e.programs.at("pencil_profile.comp").id(), *e.model, e.values,
                 builtinsOf(*v.effective), s, e.displayPath);

    const std::atomic<bool>* stop = interruptFlag();
    core::Stopwatch clock;
    uint64_t done = 0;
    while (done < a.spp && !stop->load()) {
        const int batch = int(std::min<uint64_t>(a.spp - done, 4));
        ig->step(batch, stop);
        done = ig->samplesPerPixelDone();
        core::progress("integrate: %llu / %llu samples per pixel  %.1f s", (unsigned long long)done,
                       (unsigned long long)a.spp, clock.ms() / 1000.0);
    }
    core::progressEnd();
    pathtrace::writeExr(a.out, ig->image());
    const auto rm = ig->radiusMax();
    std::printf("%s: %s sampling%s, %llu samples per pixel, %llu model evaluations, %.2f s%s\n",
                a.out.c_str(), core::nameOf(s.sampling),
                s.sampling == integrate::Sampling::Disk
                    ? (" (axes " + std::string(core::nameOf(s.axes)) + ", R_m " +
                       core::formatNumber(rm[0], 3) + "/" + core::formatNumber(rm[1], 3) + "/" +
                       core::formatNumber(rm[2], 3) + " mm)")
                          .c_str()
                    : "",
                (unsigned long long)done, (unsigned long long)ig->evaluations(), ig->seconds(),
                done < a.spp ? " (partial: interrupted)" : "");
    return done < a.spp ? kInterrupted : 0;
}

Command integrateCommand() {
    return {"integrate",
            "BSSRDF-integrated lit sphere or mesh, uniform or disk importance sampling, as EXR",
            false, [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<IntegrateArgs>();
                addIntegrateOptions(&cmd, *a);
                return [a](CommandContext& ctx) { return runIntegrateCli(ctx.root(), *a); };
            }};
}

} // namespace app
