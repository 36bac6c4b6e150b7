// The hidden `probe-model` subcommand (probe_commands.h).
#include "cli/probe_commands.h"
#include "cli/args.h"
#include "cli/command.h"

#include "bssrdf/model_probe.h"
#include "cli/capture_commands.h"
#include "cli/slab_command.h"
#include "core/core.h"
#include "gl/gl.h"
#include "render/render.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

namespace app {
namespace fs = std::filesystem;

void addProbeModelOptions(CLI::App* cmd, ProbeModelArgs& a) {
    cmd->group(""); // not listed in --help: the workbench runs it, not its users
    cmd->add_option("file", a.file, ".bssrdf file")->required();
    cmd->add_option("--sigma-a", a.sigmaA, "absorption R,G,B in 1/mm");
    cmd->add_option("--sigma-s", a.sigmaS, "scattering R,G,B in 1/mm");
    cmd->add_option("--g", a.g, "mean cosine");
    cmd->add_option("--eta", a.eta, "relative index of refraction");
    cmd->add_option("--scale", a.scale, "mm per mesh unit");
    cmd->add_option("--rmax", a.rMax, "largest radius in mm");
    cmd->add_option("--samples", a.samples, "number of radii")->check(CLI::Range(1, 1 << 20));
    cmd->add_option("--param", a.params, "a parameter's value: NAME=V or NAME=R,G,B");
    cmd->add_flag("--code-only", a.codeOnly, "generate the programs' code, evaluate nothing");
    cmd->add_option("--render-width", a.renderWidth,
                    "after the code (--code-only) or a check that passed: the traversal "
                    "program's code too, for this frame width")
        ->check(CLI::Range(0, 8192));
    cmd->add_option("--render-height", a.renderHeight, "and this frame height")
        ->check(CLI::Range(0, 8192));
}

namespace {
std::unique_ptr<gl::Context> probeContext() {
    try {
        return gl::createHeadlessContext(false);
    } catch (const std::exception& e) {
        std::printf("error: no headless GL context for the check: %s\n", e.what());
        return nullptr;
    }
}
} // namespace

int runProbeModel(const fs::path& root, const ProbeModelArgs& a) {
    const std::unique_ptr<gl::Context> ctx = probeContext();
    if (!ctx) return kProbeUnavailable;
    return probeModel(root, a);
}

int runProbeServer() {
    const std::unique_ptr<gl::Context> ctx = probeContext();
    if (!ctx) return kProbeUnavailable;
    std::printf("%s ready\n", kProbeTag);
    std::fflush(stdout);
    for (;;) {
        std::vector<std::string> fields(1);
        int c = 0;
        while ((c = std::getchar()) != EOF && c != kProbeRequestEnd) {
            if (c == kProbeFieldSeparator)
                fields.emplace_back();
            else
                fields.back() += char(c);
        }
        if (c == EOF) return 0;
        int code = 1;
        try {
            if (fields.size() < 2) throw core::Error("probe-server", 0, "a request without a file");
            const fs::path root = fields.front();
            ProbeModelArgs a;
            CLI::App cmd;
            addProbeModelOptions(&cmd, a);
            std::vector<std::string> args(fields.rbegin(), fields.rend() - 1); // CLI11: reversed
            cmd.parse(args);
            code = probeModel(root, a);
        } catch (const CLI::ParseError& e) {
            std::printf("error: %s\n", e.what());
            code = kUsageError;
        } catch (const std::exception& e) {
            std::printf("error: %s\n", e.what());
            code = 1;
        }
        std::printf("%s done %d\n", kProbeTag, code);
        std::fflush(stdout);
    }
}

int probeModel(const fs::path& root, const ProbeModelArgs& a) {
    const fs::path file = fs::absolute(a.file).lexically_normal();
    const std::string display = core::relativeTo(file, root);
    const bssrdf::Model m = bssrdf::loadModel(file, display);
    const shader::Sources src(root);
    const gl::Program pencil = bssrdf::buildModelProgram(m, "pencil_profile.comp", src);
    gl::Program inversion;
    if (bssrdf::inversionMayLoop(m)) // else init() and DiffuseReflectance() cannot loop
        inversion = bssrdf::buildModelProgram(m, "invert_rdr.comp", src);
    std::printf("%s key %s\n", kProbeTag, bssrdf::probeKey(m, src).c_str());

    bssrdf::ParamValues values = bssrdf::defaultValues(m);
    for (const std::string& p : a.params) {
        const size_t eq = p.find('=');
        if (eq == std::string::npos || !values.count(p.substr(0, eq)))
            throw core::Error("--param", 0, "'" + p + "' names no parameter of " + display);
        const glm::dvec3 v = parseRgb(p.substr(eq + 1), "--param");
        values[p.substr(0, eq)] = {float(v.x), float(v.y), float(v.z)};
    }
    bssrdf::Builtins b;
    b.sigmaA = glm::vec3(parseRgb(a.sigmaA, "--sigma-a"));
    b.sigmaS = glm::vec3(parseRgb(a.sigmaS, "--sigma-s"));
    b.g = float(a.g);
    b.ior = float(a.eta);
    b.scale = float(a.scale);

    // The driver's code generation, before the evaluation's time limit. The workbench builds the
    // same programs from the same text, and a driver with an on-disk shader cache (Mesa's,
    // NVIDIA's: on by default) gives it this code at its first dispatch instead of generating it
    // again on its GUI thread (bssrdf/program_library.cpp).
    bssrdf::warmUp(pencil.id());
    if (inversion.id()) bssrdf::warmUp(inversion.id());
    // After the line the workbench adopts the model at (`code generated`, `ok`), the code of the
    // renderer's traversal program for the scene's frame size, which the scene waits for.
    auto warmTraversal = [&] {
        if (a.renderWidth <= 0 || a.renderHeight <= 0) return;
        std::fflush(stdout);
        // $BSSRDF_WORKBENCH_PROBE_TRAVERSAL_DELAY_MS: a wait first (tests: the scene's and
        // texture space's wait for this code, shown on any driver, however fast)
        if (const char* d = std::getenv("BSSRDF_WORKBENCH_PROBE_TRAVERSAL_DELAY_MS"); d && *d)
            std::this_thread::sleep_for(
                std::chrono::milliseconds(std::clamp(std::atol(d), 0L, 60000L)));
        const gl::Program traversal = bssrdf::buildModelProgram(m, "octree_render.comp", src);
        render::warmTraversal(traversal.id(), a.renderWidth, a.renderHeight);
        std::printf("%s traversal code generated\n", kProbeTag);
    };
    if (a.codeOnly) {
        std::printf("%s code generated\n", kProbeTag);
        warmTraversal();
        return 0;
    }
    std::printf("%s evaluating\n", kProbeTag);
    std::fflush(stdout);
    bssrdf::ProbeResult r;
    try {
        r = bssrdf::evaluateProbe(pencil.id(), inversion.id(), m, values, b,
                                  bssrdf::radiusGrid(a.rMax, a.samples));
    } catch (const core::Error& e) {
        if (e.file() != m.path) throw;
        // a loop of the model ran past its budget (bssrdf/loop_budget.h)
        std::printf("error: %s: %s\n", display.c_str(), e.message().c_str());
        return kProbeLoopCut;
    }
    if (r.notWritten > 0) {
        std::printf("error: %s: Bssrdf() never returned: %zu of %zu evaluations ended without a "
                    "value (the GLSL compiler dropped the code after a loop that never ends?)\n",
                    display.c_str(), r.notWritten, r.evaluated);
        return kProbeLoopCut;
    }
    if (r.loopsCut > 0) {
        std::printf("error: %s: a loop in the model did not end: the GL driver stopped it at its "
                    "iteration limit in %zu of %zu evaluations (a loop that does not end?)\n",
                    display.c_str(), r.loopsCut, r.evaluated);
        return kProbeLoopCut;
    }
    std::printf("%s ok\n", kProbeTag);
    warmTraversal();
    return 0;
}

// The check of a new model in a child process (probe/model_probe_process.h).
Command probeModelCommand() {
    return {"probe-model", "check a model's first evaluation", false,
            [](CLI::App& cmd) -> CommandRun {
                auto a = std::make_shared<ProbeModelArgs>();
                addProbeModelOptions(&cmd, *a);
                return [a](CommandContext& ctx) { return runProbeModel(ctx.root(), *a); };
            }};
}

// The same check kept warm, one request after another on stdin; hidden from --help.
Command probeServerCommand() {
    return {"probe-server", "check models sent on stdin", true, [](CLI::App&) -> CommandRun {
                return [](CommandContext&) { return runProbeServer(); };
            }};
}

} // namespace app
