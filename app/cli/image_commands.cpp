// `bssrdf-workbench sphere` / `mesh`: lit sphere / lit mesh images as EXR (see image_commands.h).
#include "cli/image_commands.h"
#include "cli/args.h"
#include "cli/command.h"
#include "cli/options.h"
#include "cli/output.h"
#include "cli/slab_command.h"
#include "core/text.h"
#include "pipeline/lit_sphere_stage.h"

#include "core/core.h"
#include "pathtrace/camera.h"
#include "pathtrace/image_io.h"
#include "pathtrace/lit_sphere.h"
#include "pathtrace/mesh_tracer.h"
#include "pathtrace/pathtrace.h"
#include "pathtrace/sphere_tracer.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

namespace app {
namespace {

struct ImageSetup {
    std::array<pathtrace::Medium, 3> media;
    pathtrace::LitSphereSetup setup;
};

ImageSetup prepare(const ImageArgs& a) {
    static const char* names[3] = {"red", "green", "blue"};
    ImageSetup k;
    for (int c = 0; c < 3; ++c) {
        pathtrace::Medium& m = k.media[static_cast<size_t>(c)];
        m.sigmaA = a.sigmaA[c];
        m.sigmaS = a.sigmaS[c];
        m.g = a.g;
        m.eta = a.eta;
        pathtrace::validate(m, std::string("medium (") + names[c] + ")");
    }
    if (a.out.empty()) throw core::Error("--out", 0, "give the EXR file to write");
    checkOutput(a.out, "--out", ".exr");
    if (!std::isfinite(a.radiusMm) || !(a.radiusMm > 0))
        throw core::Error("--radius", 0,
                          "radius must be a finite length > 0 mm, got " +
                              core::formatNumber(a.radiusMm, 6));
    const double l2 = a.light[0] * a.light[0] + a.light[1] * a.light[1] + a.light[2] * a.light[2];
    if (!std::isfinite(l2) || !(l2 > 0))
        throw core::Error("--light", 0,
                          "light direction must be finite and non-zero, got (" +
                              core::formatNumber(a.light[0], 6) + ", " +
                              core::formatNumber(a.light[1], 6) + ", " +
                              core::formatNumber(a.light[2], 6) + ")");
    if (a.width < 1 || a.width > 16384)
        throw core::Error("--width", 0, "must lie in [1, 16384], got " + std::to_string(a.width));
    if (a.height < 1 || a.height > 16384)
        throw core::Error("--height", 0, "must lie in [1, 16384], got " + std::to_string(a.height));
    if (a.spp < 1 || a.spp > 10000000)
        throw core::Error("--spp", 0, "must lie in [1, 10^7], got " + std::to_string(a.spp));
    if (double(a.spp) * a.width * a.height > 1e12)
        throw core::Error("--spp", 0,
                          "absurd path count: spp x pixels = " +
                              core::formatNumber(double(a.spp) * a.width * a.height, 6) +
                              " (> 10^12)");
    if (a.threads < 0)
        throw core::Error("--threads", 0,
                          "must be >= 0 (0: all hardware threads), got " +
                              std::to_string(a.threads));
    pathtrace::LitSphereSetup& s = k.setup;
    s.radiusMm = a.radiusMm;
    for (int i = 0; i < 3; ++i)
        s.lightDir[i] = a.light[i];
    s.width = a.width;
    s.height = a.height;
    s.samplesPerPixel = a.spp;
    s.seed = a.seed;
    s.threads = a.threads;
    pathtrace::validate(s);
    return k;
}

std::function<void(uint64_t)> progressLine(const char* what, uint64_t total,
                                           const core::Stopwatch& clock) {
    return [what, total, &clock](uint64_t done) {
        const double sec = clock.ms() / 1000.0;
        core::progress("%s: %5.1f%%  %llu / %llu paths  %.0f paths/s", what,
                       total ? 100.0 * double(done) / double(total) : 100.0,
                       static_cast<unsigned long long>(done),
                       static_cast<unsigned long long>(total), sec > 0 ? double(done) / sec : 0.0);
    };
}

// Writes the EXR and prints: paths, seconds, paths/s, specular fraction, mean exitance over
// the lit pixels (centre ray hits and n·lightDir > 0 there). Returns 0, or kEnergyCheckFailed
// (each failing channel's problem on stderr) when a channel fails its energy check.
int finish(const ImageArgs& a, const char* what, const pathtrace::Image& img,
           const pathtrace::ImageStats& st, const std::string& extra) {
    pathtrace::writeExr(a.out, img);
    double lit[3] = {0, 0, 0};
    size_t nLit = 0;
    for (size_t p = 0; p < st.pixels.footprint.size(); ++p) {
        if (!(st.pixels.footprint[p] > 0) || !(st.pixels.cosLight[p] > 0)) continue;
        ++nLit;
        for (int c = 0; c < 3; ++c)
            lit[c] += img.mean[3 * p + static_cast<size_t>(c)];
    }
    double spec[3];
    for (int c = 0; c < 3; ++c) {
        const auto& ch = st.channel[static_cast<size_t>(c)];
        spec[c] = ch.incident > 0 ? ch.specular / ch.incident : 0;
        lit[c] = nLit ? lit[c] / double(nLit) : 0;
    }
    const double rate = st.seconds > 0 ? double(st.paths) / st.seconds : 0;
    uint64_t events = 0;
    for (const auto& ch : st.channel)
        events += ch.events;
    const double perPath = st.paths ? double(events) / (3.0 * double(st.paths)) : 0;
    std::printf("%s: wrote %s (%dx%d%s): %llu paths per channel (%.1f events each), %.2f s, %.0f "
                "paths/s (all 3 channels); specular %.4g %.4g %.4g of incident; mean exitance "
                "over %zu lit pixels %.5g %.5g %.5g\n",
                what, a.out.c_str(), img.width, img.height, extra.c_str(),
                static_cast<unsigned long long>(st.paths), perPath, st.seconds, rate, spec[0],
                spec[1], spec[2], nLit, lit[0], lit[1], lit[2]);
    std::fflush(stdout);
    int status = 0;
    for (int c = 0; c < 3; ++c) {
        const std::string problem = pathtrace::energyProblem(st.channel[static_cast<size_t>(c)]);
        if (problem.empty()) continue;
        std::fprintf(stderr, "error: %s: channel %c: %s\n", what, "RGB"[c], problem.c_str());
        status = kEnergyCheckFailed;
    }
    return status;
}

} // namespace

int runSphereCli(const ImageArgs& a) {
    const ImageSetup k = prepare(a);
    const uint64_t total = pathtrace::litSpherePaths(k.setup);
    core::Stopwatch clock;
    pathtrace::ImageStats st;
    const pathtrace::Image img = pathtrace::traceLitSphere(
        k.media, k.setup, progressLine("sphere", total, clock), nullptr, {}, &st);
    core::progressEnd();
    return finish(a, "sphere", img, st, ", radius " + core::formatNumber(a.radiusMm, 6) + " mm");
}

int runMeshCli(const ImageArgs& a) {
    if (a.mesh.empty()) throw core::Error("--mesh", 0, "give the OBJ file to trace");
    const ImageSetup k = prepare(a);
    const pathtrace::LitMesh mesh = pathtrace::loadLitMesh(a.mesh);
    const uint64_t total = mesh.pathCount(k.setup);
    core::Stopwatch clock;
    pathtrace::ImageStats st;
    const pathtrace::Image img =
        mesh.trace(k.media, k.setup, progressLine("mesh", total, clock), nullptr, {}, &st);
    core::progressEnd();
    uint64_t leaks = 0;
    for (const auto& ch : st.channel)
        leaks += ch.leaks;
    std::string extra = ", " + a.mesh + ", " + std::to_string(mesh.mesh().triangles.size()) +
                        " triangles, scale " + core::formatNumber(2 * a.radiusMm, 6) +
                        " mm of the longest axis";
    if (leaks) extra += ", " + std::to_string(leaks) + " leaked paths";
    return finish(a, "mesh", img, st, extra);
}

namespace {

// The options of `sphere` and `mesh`, with the GUI's lit-sphere settings and the tracer's
// default medium as defaults; R,G,B triples and the size are read as text and parsed on run.
struct ImageCommandArgs {
    ImageArgs image;
    std::string sigmaA, sigmaS, light, size;
};

std::shared_ptr<ImageCommandArgs> addImageOptions(CLI::App& c) {
    auto a = std::make_shared<ImageCommandArgs>();
    const LitSphereSettings litDefaults;
    const pathtrace::Medium mediumDefaults;
    ImageArgs& ima = a->image;
    a->sigmaA = defaultText(mediumDefaults.sigmaA);
    a->sigmaS = defaultText(mediumDefaults.sigmaS);
    a->light = defaultText(litDefaults.lightDir);
    a->size = std::to_string(litDefaults.size) + "x" + std::to_string(litDefaults.size);
    ima.g = mediumDefaults.g;
    ima.eta = mediumDefaults.eta;
    ima.radiusMm = litDefaults.radiusMm;
    ima.spp = uint64_t(litDefaults.pathSpp);
    ima.seed = litDefaults.seed;
    const auto dflt = [](const std::string& v) { return " (default " + v + ")"; };
    c.add_option("--sigma-a", a->sigmaA,
                 "absorption R,G,B (or one value) in 1/mm" + dflt(a->sigmaA));
    c.add_option("--sigma-s", a->sigmaS,
                 "scattering R,G,B (or one value) in 1/mm" + dflt(a->sigmaS));
    c.add_option("--g", ima.g, "Henyey-Greenstein mean cosine" + dflt(defaultText(ima.g)));
    c.add_option("--eta", ima.eta, "relative index of refraction" + dflt(defaultText(ima.eta)));
    c.add_option("--radius", ima.radiusMm,
                 "sphere radius in mm; mesh: half its longest axis" +
                     dflt(defaultText(ima.radiusMm)));
    c.add_option("--light", a->light, "direction towards the light x,y,z" + dflt(a->light));
    c.add_option("--size", a->size, "image WxH" + dflt(a->size));
    c.add_option("--spp", ima.spp, "paths per covered pixel" + dflt(std::to_string(ima.spp)));
    c.add_option("--seed", ima.seed, "random seed" + dflt(std::to_string(ima.seed)));
    addCountOption(&c, "--threads", ima.threads, "worker threads, 0 … 1024 (default 0: all cores)",
                   kThreadLimits);
    c.add_option("--out", ima.out, "EXR file: R,G,B exitance and varR,varG,varB")->required();
    return a;
}

// The parsed ImageArgs of the text options.
ImageArgs parsedImageArgs(const ImageCommandArgs& a) {
    ImageArgs ima = a.image;
    const glm::dvec3 sa = parseRgb(a.sigmaA, "--sigma-a");
    const glm::dvec3 ss = parseRgb(a.sigmaS, "--sigma-s");
    const glm::dvec3 light = parseRgb(a.light, "--light");
    for (int c = 0; c < 3; ++c) {
        ima.sigmaA[c] = sa[c];
        ima.sigmaS[c] = ss[c];
        ima.light[c] = light[c];
    }
    if (!parseSize(a.size, ima.width, ima.height, 1))
        throw core::Error("--size", 0, "expected WxH between 1 and 8192, got '" + a.size + "'");
    return ima;
}

} // namespace

Command sphereCommand() {
    return {"sphere", "path-traced lit sphere (thesis 3.6.2) as EXR", false,
            [](CLI::App& cmd) -> CommandRun {
                auto a = addImageOptions(cmd);
                return [a](CommandContext& ctx) {
                    ctx.root(); // a project root is required, as for the other renderers
                    return runSphereCli(parsedImageArgs(*a));
                };
            }};
}

Command meshCommand() {
    return {"mesh", "path-traced lit mesh (Embree) as EXR", false, [](CLI::App& cmd) -> CommandRun {
                auto a = addImageOptions(cmd);
                cmd.add_option("--mesh", a->image.mesh,
                               "closed, outward-facing triangle mesh (OBJ)")
                    ->required();
                return [a](CommandContext& ctx) {
                    ctx.root();
                    return runMeshCli(parsedImageArgs(*a));
                };
            }};
}

} // namespace app
